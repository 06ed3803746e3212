#include "garment/comfort_offset.h"

#include <algorithm>
#include <cmath>

#include "collision/body_collider.h"

namespace gp {

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
    Eigen::Vector3d x = options.start_along_normal ? Eigen::Vector3d(start.point + options.offset * n) : x0;
    if (options.offset > 0) {
      for (int it = 0; it < options.max_iterations; ++it) {
        const SurfaceLocator::Hit hit = body.closest(x);
        const collision::Proximity side = sided.query(x, hint);
        hint = side.face;
        const bool inside = side.signed_distance < 0.0;
        if (!inside && std::abs(hit.distance - options.offset) <= options.tolerance) break;
        // On the surface itself (distance 0) the normal gives the side.
        Eigen::Vector3d dir =
            hit.distance > 1e-12 ? Eigen::Vector3d((x - hit.point) / hit.distance)
                                 : evaluate_normal(N_body, body.F(), hit.at);
        if (inside && hit.distance > 1e-12) dir = -dir;
        x = hit.point + options.offset * dir;
      }
    }
    V.row(v) = x.transpose();
  }
  return measure_offset(V, body, options.offset);
}

ComfortOffsetStats measure_offset(const Eigen::MatrixXd& V, const SurfaceLocator& body, double offset) {
  ComfortOffsetStats stats;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const double e = std::abs(body.closest(V.row(v).transpose()).distance - offset);
    stats.max_error = std::max(stats.max_error, e);
    stats.mean_error += e;
  }
  if (V.rows() > 0) stats.mean_error /= static_cast<double>(V.rows());
  return stats;
}

}  // namespace gp
