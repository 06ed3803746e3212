#include "pattern/flatten.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/math.h"
#include "linalg/cholmod_solver.h"
#include "mesh/measures.h"
#include "mesh/principal_stretches.h"
#include "mesh/topology.h"
#include "pattern/flatten_common.h"

namespace gp {

using namespace flatten_detail;

Eigen::MatrixXd lscm_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop,
                             double min_weight_fraction) {
  const int n = static_cast<int>(V.rows());
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, min_weight_fraction);
  // Per triangle, w/2 |D u - R D v|^2 with R the quarter turn (u_x = v_y,
  // u_y = -v_x): the Cauchy-Riemann residual, whose area-weighted sum is the
  // conformal energy of Levy et al. 2002 (Mullen et al. 2008, eq. 4: the
  // Dirichlet energy minus the flat area). Assembled per triangle so that a
  // thin triangle can weigh more than its area.
  std::vector<Triplet> trip;
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    if (t.degenerate) continue;
    Eigen::Matrix<double, 2, 6> M;
    M.leftCols<3>() = t.D;
    M.rightCols<3>().row(0) = -t.D.row(1);
    M.rightCols<3>().row(1) = t.D.row(0);
    const Eigen::Matrix<double, 6, 6> K = t.area * M.transpose() * M;
    int idx[6];
    for (int k = 0; k < 3; ++k) idx[k] = F(f, k), idx[k + 3] = F(f, k) + n;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) trip.emplace_back(idx[i], idx[j], K(i, j));
  }
  Eigen::SparseMatrix<double> H(2 * n, 2 * n);
  H.setFromTriplets(trip.begin(), trip.end());
  const auto [p, q] = far_pair(V, loop);
  Eigen::VectorXd fixed = Eigen::VectorXd::Constant(2 * n, std::numeric_limits<double>::quiet_NaN());
  fixed[p] = 0.0;
  fixed[p + n] = 0.0;
  fixed[q] = (V.row(p) - V.row(q)).norm();
  fixed[q + n] = 0.0;
  const Eigen::VectorXd x = solve_with_fixed(H, fixed);
  Eigen::MatrixXd UV(n, 2);
  UV.col(0) = x.head(n);
  UV.col(1) = x.tail(n);
  double total = 0.0;
  for (int f = 0; f < F.rows(); ++f) total += signed_area_2d(UV, F.row(f));
  if (total < 0.0) UV.col(0) *= -1.0;
  return UV;
}

Eigen::MatrixXd tutte_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop) {
  const int n = static_cast<int>(V.rows());
  double perimeter = 0.0;
  std::vector<double> s(loop.size(), 0.0);
  for (size_t k = 0; k < loop.size(); ++k) {
    s[k] = perimeter;
    perimeter += (V.row(loop[(k + 1) % loop.size()]) - V.row(loop[k])).norm();
  }
  const double radius = perimeter / (2.0 * M_PI);
  Eigen::VectorXd fixed = Eigen::VectorXd::Constant(2 * n, std::numeric_limits<double>::quiet_NaN());
  for (size_t k = 0; k < loop.size(); ++k) {
    const double angle = 2.0 * M_PI * s[k] / perimeter;
    fixed[loop[k]] = radius * gp::math::cos(angle);
    fixed[loop[k] + n] = radius * gp::math::sin(angle);
  }
  const auto neighbors = vertex_neighbors(F, n);
  std::vector<Triplet> trip;
  for (int i = 0; i < n; ++i)
    for (int j : neighbors[static_cast<size_t>(i)]) {
      trip.emplace_back(i, i, 1.0);
      trip.emplace_back(i, j, -1.0);
      trip.emplace_back(i + n, i + n, 1.0);
      trip.emplace_back(i + n, j + n, -1.0);
    }
  Eigen::SparseMatrix<double> H(2 * n, 2 * n);
  H.setFromTriplets(trip.begin(), trip.end());
  const Eigen::VectorXd x = solve_with_fixed(H, fixed);
  Eigen::MatrixXd UV(n, 2);
  UV.col(0) = x.head(n);
  UV.col(1) = x.tail(n);
  return UV;
}

}  // namespace gp
