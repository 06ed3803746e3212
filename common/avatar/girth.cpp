#include "avatar/girth.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

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

std::vector<std::vector<Eigen::Vector3d>> slice_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                     const Eigen::Vector3d& point,
                                                     const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  Eigen::VectorXd s(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) s(i) = (V.row(i).transpose() - point).dot(n);
  auto positive = [&](int v) { return s(v) >= 0.0; };
  // Cut points are identified by their (sorted) edge; each crossing triangle
  // links the cut point where its boundary goes from + to - to the one where
  // it comes back, which orders the loop consistently with the orientation.
  std::map<std::pair<int, int>, int> point_id;
  std::vector<Eigen::Vector3d> points;
  std::vector<int> next;
  auto cut = [&](int a, int b) {
    const std::pair<int, int> key(std::min(a, b), std::max(a, b));
    auto it = point_id.find(key);
    if (it != point_id.end()) return it->second;
    const double t = s(a) / (s(a) - s(b));
    points.push_back(V.row(a).transpose() + t * (V.row(b) - V.row(a)).transpose());
    next.push_back(-1);
    const int id = static_cast<int>(points.size()) - 1;
    point_id.emplace(key, id);
    return id;
  };
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    int out_edge = -1, in_edge = -1;
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (positive(a) && !positive(b))
        out_edge = cut(a, b);
      else if (!positive(a) && positive(b))
        in_edge = cut(a, b);
    }
    if (out_edge >= 0 && in_edge >= 0) next[in_edge] = out_edge;
  }
  std::vector<std::vector<Eigen::Vector3d>> loops;
  std::vector<bool> used(points.size(), false);
  for (size_t start = 0; start < points.size(); ++start) {
    if (used[start] || next[start] < 0) continue;
    std::vector<Eigen::Vector3d> loop;
    int i = static_cast<int>(start);
    while (i >= 0 && !used[i]) {
      used[i] = true;
      loop.push_back(points[i]);
      i = next[i];
    }
    loops.push_back(std::move(loop));
  }
  return loops;
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
