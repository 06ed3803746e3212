#pragma once
// A key pose of a motion run: the settled drape, its stretch, penetration and
// crossing figures, and the bounds within which it counts as a fit.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "collision/crossings.h"
#include "spec/spec_object.h"

namespace gp::adapt {

// Cloth the body holds at a key pose: a patch of faces stretched beyond what
// cloth survives (MotionRunOptions::settle.held_stretch), where it is and how much
// room the body leaves there.
struct HeldCloth {
  std::string region;                 // "left hand", "right foot" (a hull) or "body vertex <id>"
  int body_vertex = -1;               // body vertex nearest to the patch
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // the body point closest to the patch's most stretched face [m]
  double gap = 0.0;                   // m to the nearest body surface facing that point (BodyCollider::facing_distance; infinity: none within 5 cm)
  // The contact surface's face (collision/contact_surface.h) holding that
  // point and the point's barycentric coordinates in it, so that it can be
  // found in another frame of the body.
  int surface_face = -1;
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();
  double max_stretch = 0.0;
  std::vector<int> faces;             // the patch's cloth faces, ascending
};

struct KeyPoseResult {
  std::string pose;
  int key = 0;                        // index in the motion's key sequence
  // An in-between frame (MotionRunResult::frames): its index in the motion's frames, its
  // transition (keys[transition] -> keys[transition + 1]) and parameter in it; -1 at a key pose.
  int frame = -1;
  int transition = -1;
  double t = 0.0;
  Eigen::MatrixXd V_draped;           // #V by 3
  Eigen::VectorXd face_max_stretch;   // #F, largest principal stretch against the rest shape
  Eigen::VectorXd face_rest_area;     // #F, rest areas (m^2)
  double max_stretch = 0.0;
  double p99_stretch = 0.0;           // 99th percentile over faces, weighted by rest area
  double mean_stretch = 0.0;          // rest-area weighted mean
  double area_fraction_above = 0.0;   // rest-area fraction with max stretch above 1 + delta
  double deepest_penetration = 0.0;   // m inside the body (0 when nothing is inside)
  double rest_area_growth = 1.0;      // rest area / design rest area
  double rest_area_change = 0.0;      // relative rest-area change over the last fixed_point_steps settle steps
  long steps = 0;                     // simulation steps up to this key pose
  int settle_steps = 0;
  bool settled = false;
  double max_speed = 0.0;             // largest instantaneous vertex speed at the end [m/s]
  double max_net_speed = 0.0;         // largest net vertex speed over the last settle check [m/s]
  collision::CrossingReport crossings;  // the drape against the body at this pose
  // Solved statically (MotionRunOptions::settle.equilibrium): the Newton iterations at this pose, the force
  // residual at the end (cloth/static_solve.h) [mean vertex weights] and at each iterate.
  bool solved_static = false;
  int newton_iterations = 0;
  double force_residual = 0.0;
  std::vector<double> force_residuals;
  // The settling stopped early: cloth stretched beyond held_stretch stopped
  // improving (MotionRunOptions::settle.held_steps), the body holds it.
  bool held = false;
  std::vector<HeldCloth> held_cloth;  // patches beyond held_stretch, most stretched first (at most 5)
};

// The bounds of a fitted key pose; it fails when any is exceeded.
struct FitCriteria {
  double max_area_above = 0.01;    // rest-area fraction with max stretch above 1 + delta: fails at or above
  double p99_margin = 0.02;        // fails when the p99 stretch exceeds 1 + delta + p99_margin
  double max_penetration = 0.002;  // m: fails when a cloth vertex lies deeper inside the body
  // Body edges through cloth triangles plus cloth edges through body
  // triangles (collision/crossings.h): fails above this count.
  long max_crossings = 0;
  // Fails a key pose whose cloth still moved at the settle cap: its figures
  // are a snapshot of cloth on its way (a skirt the hand drags), not a fit.
  bool require_settled = true;
  // Cloth stretched beyond tear_stretch would tear (woven cloth breaks at a
  // few tens of percent): a pose fails when more than max_torn_area of the
  // rest area is, however little that is of the 1 + delta budget. A hand
  // that grips and drags a skirt stretches a few triangles by 2-4.
  double tear_stretch = 1.5;
  double max_torn_area = 0.001;    // rest-area fraction: fails above
};

// The criteria as a report records them and a reader takes them back
// (spec/option_fields.h).
struct FitCriteriaFields {
  template <class Fields>
  void operator()(FitCriteria& c, Fields& f) const {
    f.number("max_area_fraction_above_limit", c.max_area_above, Range::between(0.0, 1.0));
    f.number("p99_margin", c.p99_margin, Range::non_negative());
    f.number("max_penetration_m", c.max_penetration, Range::non_negative());
    f.integer("max_crossings", c.max_crossings, Range::non_negative());
    f.flag("require_settled", c.require_settled);
    f.number("tear_stretch", c.tear_stretch, Range::between(1.0, 100.0));
    f.number("max_torn_area_fraction", c.max_torn_area, Range::between(0.0, 1.0));
  }
};

// Sets k's max, p99 (area-weighted) and mean stretch and the area fraction
// above `limit` from per-face stretches s and areas (both #F), and keeps both.
void stretch_figures(const Eigen::VectorXd& s, const Eigen::VectorXd& area, double limit, KeyPoseResult& k);

// The stretch bounds a key pose's figures exceed, in words ("p99 stretch
// 1.134 above 1.120"); empty when they hold. delta: the stretch limit.
std::vector<std::string> stretch_failures(const KeyPoseResult& k, double delta, const FitCriteria& criteria);

// The rest-area fraction of k's faces whose largest stretch exceeds `stretch`.
double area_fraction_above(const KeyPoseResult& k, double stretch);

// The patch as a report records it (positions and gap in metres).
OrderedJson to_json(const HeldCloth& h);

// All bounds a key pose's figures exceed (stretch, torn cloth, penetration,
// crossings, settling); empty when it passes.
std::vector<std::string> check_pose(const KeyPoseResult& k, double delta, const FitCriteria& criteria);

}  // namespace gp::adapt
