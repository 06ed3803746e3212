#include "registration/surface_growth.h"

#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "core/error.h"
#include "mesh/measures.h"

namespace gp {

SurfaceGrowth surface_growth(const Eigen::MatrixXd& V_ref, const Eigen::MatrixXd& V_pose, const Eigen::MatrixXi& F,
                             double radius) {
  if (!(radius > 0.0) || !std::isfinite(radius)) throw UsageError("surface growth: the radius must be positive");
  if (V_pose.rows() != V_ref.rows() || V_ref.cols() != 3 || V_pose.cols() != 3)
    throw UsageError("surface growth: the two poses must have the same vertices (#V by 3)");
  SurfaceGrowth g;
  g.radius = radius;
  const Eigen::VectorXd a_ref = face_areas(V_ref, F), a_pose = face_areas(V_pose, F);
  // The faces by the grid cell (of the radius' size) of their reference centroid: a vertex's
  // neighbourhood lies in the 27 cells around its own.
  using Cell = std::array<long, 3>;
  auto cell_of = [radius](const Eigen::Vector3d& x) {
    return Cell{static_cast<long>(std::floor(x.x() / radius)), static_cast<long>(std::floor(x.y() / radius)),
                static_cast<long>(std::floor(x.z() / radius))};
  };
  Eigen::MatrixXd centroid(F.rows(), 3);
  std::map<Cell, std::vector<int>> cells;
  for (int f = 0; f < F.rows(); ++f) {
    centroid.row(f) = (V_ref.row(F(f, 0)) + V_ref.row(F(f, 1)) + V_ref.row(F(f, 2))) / 3.0;
    if (!(a_ref(f) > 0.0) || !centroid.row(f).allFinite()) continue;
    cells[cell_of(centroid.row(f).transpose())].push_back(f);
  }
  // Each vertex's share of the reference's area (a third of each face's), the weights of p99.
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(V_ref.rows());
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) weight(F(f, k)) += a_ref(f) / 3.0;
  Eigen::VectorXd factor = Eigen::VectorXd::Ones(V_ref.rows());
  double total = 0.0, above = 0.0;
  bool any = false;
  for (int v = 0; v < V_ref.rows(); ++v) {
    const Eigen::Vector3d x = V_ref.row(v).transpose();
    if (!x.allFinite()) continue;
    const Cell c = cell_of(x);
    double ref = 0.0, pose = 0.0;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(Cell{c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells.end()) continue;
          for (int f : it->second) {
            if ((centroid.row(f).transpose() - x).squaredNorm() >= radius * radius) continue;
            ref += a_ref(f);
            pose += a_pose(f);
          }
        }
    // No area to compare, or a pose whose vertices are not finite there (register-check names those).
    if (!(ref > 0.0) || !std::isfinite(pose)) {
      weight(v) = 0.0;
      continue;
    }
    factor(v) = pose / ref;
    total += weight(v);
    if (factor(v) > 1.25) above += weight(v);
    if (!any || factor(v) > g.largest.factor) g.largest = {factor(v), v, x};
    if (!any || factor(v) < g.smallest.factor) g.smallest = {factor(v), v, x};
    any = true;
  }
  if (!any) return g;
  g.p99 = area_weighted_percentile(factor, weight, 0.99);
  g.share_above_1_25 = total > 0.0 ? above / total : 0.0;
  return g;
}

}  // namespace gp
