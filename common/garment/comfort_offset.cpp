#include "garment/comfort_offset.h"

#include <algorithm>
#include <cmath>

#include "collision/body_collider.h"

namespace gp {
namespace {

// Closest-point corrections of x towards the exact distance `offset` outside
// the body (see apply_comfort_offset). `hint` warm-starts the side queries.
// In a slot narrower than twice the offset a correction from one wall lands
// nearer the other, and the next one sends it back: when two successive
// directions oppose, x goes instead to the nearest point of the line where
// the offset planes of both walls meet (the crease of the offset surface,
// out of the slot), and the corrections go on from there.
Eigen::Vector3d correct_to_offset(Eigen::Vector3d x, const SurfaceLocator& body,
                                  const collision::BodyCollider& sided, const Eigen::MatrixXd& N_body,
                                  const ComfortOffsetOptions& options, int& hint) {
  if (!(options.offset > 0)) return x;
  Eigen::Vector3d c_prev = Eigen::Vector3d::Zero(), n_prev = Eigen::Vector3d::Zero();
  for (int it = 0; it < options.max_iterations; ++it) {
    const SurfaceLocator::Hit hit = body.closest(x);
    const collision::Proximity side = sided.query(x, hint);
    hint = side.face;
    const bool inside = side.signed_distance < 0.0;
    if (!inside && std::abs(hit.distance - options.offset) <= options.tolerance) break;
    // On the surface itself (distance 0) the normal gives the side.
    Eigen::Vector3d dir = hit.distance > 1e-12 ? Eigen::Vector3d((x - hit.point) / hit.distance)
                                               : evaluate_normal(N_body, body.F(), hit.at);
    if (inside && hit.distance > 1e-12) dir = -dir;
    if (options.solve_creases && it > 0 && dir.dot(n_prev) < 0.0) {
      // y = x + l1 n1 + l2 n2 on both planes n_i . (y - c_i) = offset.
      const double n12 = n_prev.dot(dir), det = 1.0 - n12 * n12;
      // Walls at least 6 degrees apart, and a step of at most a few offsets:
      // parallel walls have no crease near.
      const double r1 = options.offset - n_prev.dot(x - c_prev), r2 = options.offset - dir.dot(x - hit.point);
      const double l1 = det > 0.01 ? (r1 - n12 * r2) / det : 0.0, l2 = det > 0.01 ? (r2 - n12 * r1) / det : 0.0;
      const Eigen::Vector3d step = l1 * n_prev + l2 * dir;
      if (det > 0.01 && step.norm() < 4.0 * options.offset) {
        x += step;
        c_prev = hit.point;
        n_prev = dir;
        continue;
      }
    }
    c_prev = hit.point;
    n_prev = dir;
    x = hit.point + options.offset * dir;
  }
  return x;
}

}  // namespace

ComfortOffsetStats apply_comfort_offset(Eigen::MatrixXd& V, const SurfaceLocator& body,
                                        const Eigen::MatrixXd& N_body,
                                        const ComfortOffsetOptions& options,
                                        const std::vector<char>& fixed) {
  // Which side of the body a point is on (pseudo-normal signs, see
  // collision/body_collider.h): a start along the normal field can land inside
  // another body part (an arm, in an armpit), and the correction must then
  // lead out of it, not to the offset inside it.
  collision::BodyCollider sided(body.F());
  sided.set_body(body.V());
  int hint = -1;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!fixed.empty() && fixed[static_cast<size_t>(v)]) continue;
    const Eigen::Vector3d x0 = V.row(v).transpose();
    const SurfaceLocator::Hit start = body.closest(x0);
    const Eigen::Vector3d n = evaluate_normal(N_body, body.F(), start.at);
    const Eigen::Vector3d x = options.start_along_normal ? Eigen::Vector3d(start.point + options.offset * n) : x0;
    V.row(v) = correct_to_offset(x, body, sided, N_body, options, hint).transpose();
  }
  return measure_offset(V, body, options.offset);
}

ComfortOffsetStats measure_offset(const Eigen::MatrixXd& V, const SurfaceLocator& body, double offset) {
  ComfortOffsetStats stats;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const double d = body.closest(V.row(v).transpose()).distance - offset;
    stats.max_error = std::max(stats.max_error, std::abs(d));
    stats.max_below = std::max(stats.max_below, -d);
    stats.max_above = std::max(stats.max_above, d);
    stats.mean_error += std::abs(d);
  }
  if (V.rows() > 0) stats.mean_error /= static_cast<double>(V.rows());
  return stats;
}

OffsetSurface::OffsetSurface(const SurfaceLocator& body, const Eigen::MatrixXd& N_body, double offset,
                             double fillet_radius, const ComfortOffsetOptions& correction,
                             const std::vector<char>& near)
    : body_(body),
      N_body_(N_body),
      offset_(offset),
      fillet_radius_(std::max(0.0, fillet_radius)),
      correction_(correction),
      sided_(std::make_unique<collision::BodyCollider>(body.F())) {
  correction_.offset = offset;
  sided_->set_body(body.V());
  if (fillet_radius_ > 0) {
    Eigen::MatrixXd V_outer = body.V();
    ComfortOffsetOptions outer = correction_;
    outer.offset = offset + fillet_radius_;
    outer.start_along_normal = true;
    outer.solve_creases = true;
    std::vector<char> skip;
    if (!near.empty())
      for (char n : near) skip.push_back(!n);
    apply_comfort_offset(V_outer, body, N_body, outer, skip);
    // In a pinch narrower than 2 (offset + R) the corrections of a vertex
    // swing between the two sides without reaching the distance: such
    // vertices are not on the outer surface and go, with their faces, and so
    // do faces that join far-apart parts of it (longer than twice their body
    // edge plus the offset; a convex part only stretches an edge by
    // (radius + offset) / radius).
    const Eigen::MatrixXi& F = body.F();
    const double distance = outer.offset, tolerance = std::max(1e-4 * distance, 10.0 * outer.tolerance);
    std::vector<char> on(static_cast<size_t>(V_outer.rows()), 0);
    for (Eigen::Index v = 0; v < V_outer.rows(); ++v) {
      if (!skip.empty() && skip[static_cast<size_t>(v)]) continue;
      const collision::Proximity q = sided_->query(V_outer.row(v).transpose());
      on[static_cast<size_t>(v)] = std::abs(q.signed_distance - distance) <= tolerance;
    }
    // A face whose centre is well inside the distance is a chord across a
    // crease that bends (under an arm), through the pinch: it goes too. On a
    // convex part a face's centre is inside only by its sagitta, about
    // (edge length)^2 / (8 radius).
    std::vector<int> kept;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      bool keep = true;
      double longest = 0.0;
      for (int k = 0; k < 3 && keep; ++k) {
        const int a = F(f, k), b = F(f, (k + 1) % 3);
        const double length = (V_outer.row(a) - V_outer.row(b)).norm();
        longest = std::max(longest, length);
        keep = on[static_cast<size_t>(a)] && length <= 2.0 * (body.V().row(a) - body.V().row(b)).norm() + distance;
      }
      if (keep) {
        const Eigen::Vector3d centre = (V_outer.row(F(f, 0)) + V_outer.row(F(f, 1)) + V_outer.row(F(f, 2))).transpose() / 3.0;
        keep = sided_->query(centre).signed_distance >= distance - tolerance - 0.1 * longest;
      }
      if (keep) kept.push_back(static_cast<int>(f));
    }
    if (!kept.empty()) {
      Eigen::MatrixXi F_outer(static_cast<Eigen::Index>(kept.size()), 3);
      for (size_t i = 0; i < kept.size(); ++i) F_outer.row(static_cast<Eigen::Index>(i)) = F.row(kept[i]);
      outer_ = std::make_unique<SurfaceLocator>(V_outer, F_outer);
    }
  }
}

OffsetSurface::~OffsetSurface() = default;

Eigen::Vector3d OffsetSurface::to_exact_offset(const Eigen::Vector3d& x) const {
  int hint = -1;
  return correct_to_offset(x, body_, *sided_, N_body_, correction_, hint);
}

Eigen::Vector3d OffsetSurface::project(const Eigen::Vector3d& x) const {
  if (!outer_) {
    // The exact surface, in one step: out along the closest-point direction
    // (inside the body: the way out that is nearest).
    const SurfaceLocator::Hit hit = body_.closest(x);
    if (hit.distance < 1e-12) return hit.point + offset_ * evaluate_normal(N_body_, body_.F(), hit.at);
    const double side = sided_->query(x).signed_distance < 0.0 ? -1.0 : 1.0;
    return hit.point + side * offset_ * (x - hit.point) / hit.distance;
  }
  const collision::Proximity at = sided_->query(x);
  // Outside the closed region between the body and the outer surface the
  // direction to the outer surface does not say which side x belongs to;
  // the closest body point does.
  const Eigen::Vector3d p =
      at.signed_distance < 0.0 || at.signed_distance >= offset_ + fillet_radius_ ? at.closest : x;
  const SurfaceLocator::Hit y = outer_->closest(p);
  // p on the outer surface itself (never a body point, which is at least
  // offset + R from it): towards the closest body point.
  const Eigen::Vector3d dir = y.distance > 1e-12 ? Eigen::Vector3d((p - y.point) / y.distance)
                                                 : Eigen::Vector3d((at.closest - p).normalized());
  const Eigen::Vector3d q = y.point + fillet_radius_ * dir;
  const collision::Proximity check = sided_->query(q, at.face);
  if (check.signed_distance >= offset_ - correction_.tolerance) return q;
  return to_exact_offset(q);
}

}  // namespace gp
