#include "adapt/body_contact.h"

#include <algorithm>
#include <utility>

#include "core/error.h"

namespace gp::adapt {
namespace {

// A vertex within this distance [m] above the comfort offset touches it (the
// position projection leaves vertices at the offset up to rounding).
constexpr double kTouchTolerance = 1e-6;
// Largest speed [m/s] at which a contact constraint pushes a vertex back out to
// the offset.
constexpr double kMaxCorrectionSpeed = 0.5;

}  // namespace

void check_options(const BodyContactOptions& options) {
  if (!(options.pin_clearance >= 0.0 && options.pin_clearance <= 1.0)) {
    throw UsageError("pin_clearance must be within [0, 1] (a fraction of the comfort offset)");
  }
}

BodyContact::BodyContact(collision::ContactSurface surface, const Eigen::MatrixXd& V_body,
                         std::vector<int> reachable_faces, const Eigen::MatrixXi& F_cloth,
                         const Eigen::MatrixXd& V_cloth, const std::vector<int>& pinned, double offset,
                         const BodyContactOptions& options, int threads)
    : options_(options),
      offset_(offset),
      surface_(std::move(surface)),
      collider_(surface_.F, std::move(reachable_faces)),
      continuous_(F_cloth, surface_.F, collider_.face_ids(), options.sweep) {
  check_options(options_);
  const Eigen::MatrixXd V_surface = surface_.positions(V_body);
  collider_.set_threads(threads);
  if (options_.facing_gaps) {
    collider_.set_facing_gaps(true);
    collider_.set_min_pinch_offset(options_.sweep.thickness);
  }
  collider_.set_body(V_surface);
  continuous_.set_pinned(pinned);
  continuous_.set_threads(threads);
  continuous_.set_body(V_surface);
  initial_crossings_ = collision::find_crossings(V_surface, surface_.F, V_cloth, F_cloth);
  continuous_active_ = options_.continuous && initial_crossings_.intersection_free();

  offsets_ = Eigen::VectorXd::Constant(V_cloth.rows(), offset_);
  int hint = -1;
  for (int v = 0; v < V_cloth.rows(); ++v) {
    const collision::Proximity q = collider_.query(V_cloth.row(v).transpose(), hint);
    hint = q.face;
    offsets_(v) = std::min(offset_, q.signed_distance);
  }
  initial_min_distance_ = offsets_.size() ? offsets_.minCoeff() : offset_;
  offsets_grown_ = initial_min_distance_ >= offset_;
}

void BodyContact::constraints(const Eigen::MatrixXd& X, double h, std::vector<cloth::VelocityConstraint>& out) {
  if (!options_.velocity_constraints) return;
  // The normal velocity follows the body and closes any gap below the offset
  // within the step, but no faster than kMaxCorrectionSpeed (halved substeps
  // would turn a depth into a huge speed); the projection after the step does
  // the rest. A vertex in the band is never pulled towards the body.
  for (const collision::Contact& c : collider_.contacts(X, offsets_, options_.band)) {
    cloth::VelocityConstraint k;
    k.vertex = c.vertex;
    k.normal = c.outward;
    k.normal_velocity = c.body_normal_speed + std::min(std::max(c.offset - c.signed_distance, 0.0) / h, kMaxCorrectionSpeed);
    k.touching = c.signed_distance <= c.offset + kTouchTolerance;
    out.push_back(k);
  }
}

void BodyContact::project(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) { collider_.resolve(X, Vel, offsets_); }

void BodyContact::sweep(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end) {
  if (continuous_active_) continuous_.enforce(X_start, X_end, s_start, s_end);
}

collision::BodyFrame BodyContact::prepare(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd& V_previous,
                                          double dt) const {
  const Eigen::MatrixXd body_velocity = surface_.positions((V_body - V_previous) / dt);
  return collider_.prepare(surface_.positions(V_body), &body_velocity);
}

void BodyContact::move_to(collision::BodyFrame frame, const Eigen::MatrixXd& V_body) {
  collider_.set_body(std::move(frame));
  continuous_.set_body(surface_.positions(V_body));
}

void BodyContact::stand_still(const Eigen::MatrixXd& V_body) {
  const Eigen::MatrixXd V_surface = surface_.positions(V_body);
  collider_.set_body(V_surface);
  continuous_.set_body(V_surface);
}

void BodyContact::advance_offsets(double dt) {
  if (offsets_grown_) return;
  const double grow = options_.initial_push_speed * dt;
  for (int v = 0; v < offsets_.size(); ++v) offsets_(v) = std::min(offset_, offsets_(v) + grow);
  offsets_grown_ = offsets_.minCoeff() >= offset_;
}

void BodyContact::use_garment_offsets() {
  offsets_.setConstant(offset_);
  offsets_grown_ = true;
}

void BodyContact::restore(Offsets offsets) {
  if (offsets.per_vertex.size() != offsets_.size()) throw UsageError("offsets of another cloth");
  offsets_ = std::move(offsets.per_vertex);
  offsets_grown_ = offsets.grown;
}

cloth::StaticBody BodyContact::static_body(std::vector<int>& hints, double room_within) const {
  hints.assign(static_cast<size_t>(offsets_.size()), -1);
  cloth::StaticBody body;
  body.features = [this](const Eigen::Vector3d& p, double radius, std::vector<cloth::BodyFeature>& out) {
    for (const collision::BodyCollider::NearFeature& f : collider_.closest_features_within(p, radius)) {
      out.push_back({f.point, f.kind, f.edge});
    }
  };
  body.distance = [this, &hints, room_within](int v, const Eigen::Vector3d& p, bool with_room) {
    const collision::Proximity q = collider_.query(p, hints[static_cast<size_t>(v)]);
    hints[static_cast<size_t>(v)] = q.face;
    cloth::BodyDistance d;
    d.signed_distance = q.signed_distance;
    d.outward = q.outward;
    if (with_room && q.signed_distance < room_within) d.room = collider_.gap(q);
    return d;
  };
  return body;
}

void BodyContact::keep_pins_off(Eigen::MatrixXd& targets, std::vector<int>& hints, PinClearanceStats& stats) const {
  if (!(options_.pin_clearance > 0.0)) return;
  keep_off_body(targets, collider_, options_.pin_clearance * offset_, hints, stats);
}

}  // namespace gp::adapt
