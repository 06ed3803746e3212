#include "avatar/girth.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "mesh/slice_mesh.h"

namespace gp {

double convex_hull_perimeter(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 2) return 0.0;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  double per = 0.0;
  for (size_t i = 0; i < hull.size(); ++i) per += (hull[(i + 1) % hull.size()] - hull[i]).norm();
  return per;
}

double mesh_girth(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal) {
  return mesh_girth(V, F, point, normal, nullptr);
}

double mesh_girth(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal, double* loop_length) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d e1 =
      (std::abs(n.y()) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  const auto loops = slice_mesh(V, F, point, n);
  double best = -1.0;
  double best_area = 1e300;
  for (const auto& loop : loops) {
    std::vector<Eigen::Vector2d> q;
    q.reserve(loop.size());
    for (const auto& p : loop) q.emplace_back((p - point).dot(e1), (p - point).dot(e2));
    // Point-in-polygon (even-odd) for the origin.
    bool inside = false;
    for (size_t i = 0, j = q.size() - 1; i < q.size(); j = i++) {
      if ((q[i].y() > 0) != (q[j].y() > 0) &&
          0 < (q[j].x() - q[i].x()) * (0 - q[i].y()) / (q[j].y() - q[i].y()) + q[i].x())
        inside = !inside;
    }
    if (!inside) continue;
    double area = 0.0, length = 0.0;
    for (size_t i = 0, j = q.size() - 1; i < q.size(); j = i++) {
      area += q[j].x() * q[i].y() - q[i].x() * q[j].y();
      length += (q[i] - q[j]).norm();
    }
    // The innermost enclosing loop (smallest area) is the body part itself.
    if (std::abs(area) < best_area) {
      best_area = std::abs(area);
      best = convex_hull_perimeter(q);
      if (loop_length) *loop_length = length;
    }
  }
  return best;
}

}  // namespace gp
