#pragma once
// The seam between the cloth and the body it meets during a fit. BodyContact
// owns the body collider (the comfort offset, velocity contacts, pinches),
// the continuous contact (no feature passes through the other surface within
// a step), the per-vertex offsets that grow from where a garment starts
// inside its offset to the garment's, and the translation of contacts into
// the cloth step's constraints (cloth/step_contact.h). The schedule of a fit
// (garment_motion.h) moves the body and asks it; the cloth step calls it at
// its three points, before the solve and after it.
#include <vector>

#include <Eigen/Core>

#include "adapt/pin_targets.h"
#include "cloth/static_solve.h"
#include "cloth/step_contact.h"
#include "collision/body_collider.h"
#include "collision/contact_surface.h"
#include "collision/continuous_contact.h"
#include "collision/crossings.h"

namespace gp::adapt {

// How the cloth meets the body (MotionRunOptions::contact); the measurements
// behind the defaults are in common/adapt/README.md and collision/README.md.
struct BodyContactOptions {
  double reach = 0.15;  // m: body faces farther from the garment (at the first frame and every key pose) are culled
  // Contact as velocity constraints inside the implicit solve (filtered CG)
  // for vertices within the comfort offset plus `band` [m]; false: only the
  // position projection after each step.
  bool velocity_constraints = true;
  double band = 5e-4;
  // In a pinch the gap also counts the nearest body surface facing the
  // closest point in any direction (BodyCollider::set_facing_gaps), so the
  // offset shrinks smoothly towards a gap's rim instead of jumping where the
  // ray along the normal leaves it, and never below the continuous contact's
  // thickness (BodyCollider::set_min_pinch_offset). Off by default: on the
  // slim-shirt it left the A-pose unsettled after 1,000 steps with 58
  // crossings in the armpits (collision/README.md, "Caches and pinches").
  bool facing_gaps = false;
  // Intersection-free contact in both directions (collision/continuous_contact.h):
  // body vertices and edges push the cloth out of their way, no body feature
  // or cloth vertex passes through the other surface within a step. Active
  // only when the design garment starts free of intersections with the body
  // (BodyContact::initial_crossings), since it keeps every body feature on
  // the side of the cloth it starts on.
  bool continuous = true;
  collision::ContinuousContactOptions sweep;  // the continuous contact's thickness, tolerance, rounds
  // What the cloth collides with: the body plus convex hulls over its hands
  // (collision/contact_surface.h), taken in the garment's design pose (or the
  // motion's first frame where the pose set lacks it). Penetration depths are
  // measured against it; crossings against the body itself.
  collision::ContactSurfaceOptions surface;
  // Pin targets kept at least this fraction of the comfort offset from the
  // contact surface in every body frame (pin_targets.h): the continuous
  // contact never moves a pinned vertex, so where another body part rises
  // beside a bound point (a shoulder lifted towards the neckline) the target
  // moves out instead of letting the body through the cloth next to it.
  // Targets farther out follow their binding alone; 0: all of them do.
  double pin_clearance = 0.5;
  double initial_push_speed = 0.1;  // m/s at which vertices that start inside the offset are pushed out to it
};

// Throws UsageError for options out of their ranges.
void check_options(const BodyContactOptions& options);

class BodyContact final : public cloth::StepContact {
 public:
  // The contact surface (the body and its hand hulls) at its first frame V_body (the body's
  // vertices, #Vb by 3); the surface faces the cloth can reach (reachable_body_faces); the cloth's
  // faces, design positions (#V by 3) and pinned vertices; the garment's comfort offset [m].
  // Vertices that start closer to the body than the offset start at their own distance.
  BodyContact(collision::ContactSurface surface, const Eigen::MatrixXd& V_body, std::vector<int> reachable_faces,
              const Eigen::MatrixXi& F_cloth, const Eigen::MatrixXd& V_cloth, const std::vector<int>& pinned,
              double offset, const BodyContactOptions& options, int threads);

  // cloth::StepContact: the velocity constraints of vertices within their offset plus the band,
  // the projection out to the offsets, and the continuous contact where it is active.
  void constraints(const Eigen::MatrixXd& X, double h, std::vector<cloth::VelocityConstraint>& out) override;
  void project(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) override;
  void sweep(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end) override;

  // The next body frame (the body's vertices) made ready from the frame before it, dt [s] earlier:
  // only reads, so it may run on another thread while the cloth steps.
  collision::BodyFrame prepare(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd& V_previous, double dt) const;
  // Makes a prepared frame current: the collider's, and the continuous contact's end of the next
  // step (its start the frame before).
  void move_to(collision::BodyFrame frame, const Eigen::MatrixXd& V_body);
  // The body standing still at V_body: no velocity, the next step's start and end alike.
  void stand_still(const Eigen::MatrixXd& V_body);

  // The offsets of vertices that started inside theirs grow by initial_push_speed over dt [s],
  // up to the garment's.
  void advance_offsets(double dt);
  // Every offset the garment's from now on (the static solve's barrier pushes a vertex that is
  // still inside its offset out gradually itself).
  void use_garment_offsets();
  bool offsets_grown() const { return offsets_grown_; }  // every offset is the garment's
  // The offsets' state, to go on from after an excursion (an observed in-between frame).
  struct Offsets {
    Eigen::VectorXd per_vertex;
    bool grown = false;
  };
  Offsets offsets() const { return {offsets_, offsets_grown_}; }
  void restore(Offsets offsets);

  // The body as the static solve meets it (cloth/static_solve.h): the collider's distances, with
  // the room in front of vertices within room_within [m] of it, and the closest features within a
  // radius. `hints` (one per cloth vertex, reset here) warm-start the distance queries and must
  // outlive the solve, as must this object.
  cloth::StaticBody static_body(std::vector<int>& hints, double room_within) const;
  const Eigen::VectorXd& vertex_offsets() const { return offsets_; }

  // The pin targets (#pins by 3) moved out to pin_clearance times the offset from the current body
  // (pin_targets.h); `hints` one per pin.
  void keep_pins_off(Eigen::MatrixXd& targets, std::vector<int>& hints, PinClearanceStats& stats) const;

  const collision::ContactSurface& surface() const { return surface_; }
  const collision::BodyCollider& collider() const { return collider_; }
  // The design garment's crossings with the first body frame; the continuous contact is active
  // only without any (and with BodyContactOptions::continuous).
  const collision::CrossingReport& initial_crossings() const { return initial_crossings_; }
  bool continuous_active() const { return continuous_active_; }
  double initial_min_distance() const { return initial_min_distance_; }  // m, signed, of the design garment
  const collision::CollisionStats& collider_stats() const { return collider_.stats(); }
  const collision::ContinuousContactStats& continuous_stats() const { return continuous_.stats(); }

 private:
  BodyContactOptions options_;
  double offset_;
  collision::ContactSurface surface_;
  collision::BodyCollider collider_;
  collision::ContinuousContact continuous_;
  collision::CrossingReport initial_crossings_;
  bool continuous_active_ = false;
  double initial_min_distance_ = 0.0;
  Eigen::VectorXd offsets_;
  bool offsets_grown_ = false;
};

}  // namespace gp::adapt
