#include "mesh/slice_mesh.h"

#include <algorithm>
#include <map>
#include <utility>

namespace gp {

std::vector<std::vector<Eigen::Vector3d>> slice_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                     const Eigen::Vector3d& point,
                                                     const Eigen::Vector3d& normal,
                                                     std::vector<bool>* closed) {
  const Eigen::Vector3d n = normal.normalized();
  Eigen::VectorXd s(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) s(i) = (V.row(i).transpose() - point).dot(n);
  auto positive = [&](int v) { return s(v) >= 0.0; };
  // Cut points are identified by their (sorted) edge; each crossing triangle
  // links the cut point where its boundary goes from + to - to the one where
  // it comes back, which orders the polyline consistently with the orientation.
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
  // Open polylines start at a point nothing leads to (a cut on a border edge);
  // they are walked first so that no loop walk starts in their middle.
  std::vector<bool> has_prev(points.size(), false);
  for (int j : next)
    if (j >= 0) has_prev[static_cast<size_t>(j)] = true;
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  if (closed) closed->clear();
  std::vector<bool> used(points.size(), false);
  for (int pass = 0; pass < 2; ++pass)
    for (size_t start = 0; start < points.size(); ++start) {
      if (used[start] || (pass == 0 && has_prev[start])) continue;
      std::vector<Eigen::Vector3d> polyline;
      int i = static_cast<int>(start);
      while (i >= 0 && !used[static_cast<size_t>(i)]) {
        used[static_cast<size_t>(i)] = true;
        polyline.push_back(points[static_cast<size_t>(i)]);
        i = next[static_cast<size_t>(i)];
      }
      // A lone cut point (a border edge whose face does not lead on) is no section.
      if (pass == 0 && polyline.size() < 2) continue;
      polylines.push_back(std::move(polyline));
      if (closed) closed->push_back(pass == 1 && i == static_cast<int>(start));
    }
  return polylines;
}

double polyline_length(const std::vector<Eigen::Vector3d>& polyline, bool closed) {
  double length = 0;
  for (size_t i = 0; i + 1 < polyline.size(); ++i) length += (polyline[i + 1] - polyline[i]).norm();
  if (closed && polyline.size() > 2) length += (polyline.front() - polyline.back()).norm();
  return length;
}

}  // namespace gp
