#include "adapt/open_pose.h"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

#include "collision/body_collider.h"
#include "core/error.h"

namespace gp::adapt {
namespace {

// The least room in front of the patches in body frame V_surface (the
// contact surface's vertices): each patch's point found again on its face,
// and the nearest surface facing it within `radius` (infinity: none).
double smallest_gap(collision::BodyCollider& collider, const Eigen::MatrixXd& V_surface, const Eigen::MatrixXi& F,
                    const std::vector<HeldCloth>& held, double radius) {
  collider.set_body(V_surface);
  double least = std::numeric_limits<double>::infinity();
  for (const HeldCloth& h : held) {
    const int f = h.surface_face;
    const Eigen::Vector3d a = V_surface.row(F(f, 0)).transpose(), b = V_surface.row(F(f, 1)).transpose(),
                          c = V_surface.row(F(f, 2)).transpose();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0.0)) continue;
    const Eigen::Vector3d p = h.barycentric(0) * a + h.barycentric(1) * b + h.barycentric(2) * c;
    least = std::min(least, collider.facing_distance(p, n.normalized(), radius));
  }
  return least;
}

}  // namespace

Opening choose_opening(PoseInterpolator& interpolator, int pose, const std::vector<HeldCloth>& held, double offset,
                       const OpeningOptions& options) {
  if (pose < 0 || pose >= interpolator.pose_count()) throw UsageError("the held pose is out of range");
  if (held.empty()) throw UsageError("an opening needs the patches the body holds");
  for (const HeldCloth& h : held) {
    if (h.surface_face < 0) throw UsageError("a held patch has no contact-surface face");
  }
  std::vector<int> steps = options.steps;
  std::sort(steps.begin(), steps.end(), std::greater<int>());  // least opening first
  const Eigen::MatrixXd& V_pose = interpolator.pose(pose);
  const collision::ContactSurface surface =
      collision::contact_surface(V_pose, interpolator.faces(), options.contact_surface);
  collision::BodyCollider collider(surface.F);
  const double needed = options.clearance * offset;
  Opening best;
  best.pose = pose;
  best.gap_at_largest.assign(static_cast<size_t>(interpolator.pose_count()), 0.0);
  for (int n : steps) {
    if (n < 1) throw UsageError("an opening's step count must be at least 1");
    for (int toward = 0; toward < interpolator.pose_count(); ++toward) {
      if (toward == pose) continue;
      const Eigen::MatrixXd V = interpolator.frame(pose, toward, 1.0 / n);
      // Room is measured up to twice what is needed, so that openings that
      // free the cloth rank by it, then by how little the body moves.
      const double gap = std::min(smallest_gap(collider, surface.positions(V), surface.F, held, 2.0 * needed),
                                  2.0 * needed);
      const double moved = (V - V_pose).rowwise().norm().maxCoeff();
      if (n == steps.back()) best.gap_at_largest[static_cast<size_t>(toward)] = gap;
      if (gap >= needed && (!best.found || gap > best.smallest_gap ||
                            (gap == best.smallest_gap && moved < best.largest_displacement))) {
        best.found = true;
        best.toward = toward;
        best.steps = n;
        best.smallest_gap = gap;
        best.largest_displacement = moved;
      }
    }
    if (best.found) return best;
  }
  return best;
}

}  // namespace gp::adapt
