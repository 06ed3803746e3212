#include "mesh/laplacian.h"

#include <vector>

#include <Eigen/Geometry>

namespace gp {

Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<size_t>(F.rows()) * 12);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int i = F(f, k), j = F(f, (k + 1) % 3), o = F(f, (k + 2) % 3);
      const Eigen::Vector3d a = V.row(i) - V.row(o), b = V.row(j) - V.row(o);
      const double s = a.cross(b).norm();
      if (!(s > 0.0)) continue;
      const double w = 0.5 * a.dot(b) / s;  // half the cotangent of the angle at o
      trip.emplace_back(i, i, w);
      trip.emplace_back(j, j, w);
      trip.emplace_back(i, j, -w);
      trip.emplace_back(j, i, -w);
    }
  Eigen::SparseMatrix<double> L(V.rows(), V.rows());
  L.setFromTriplets(trip.begin(), trip.end());
  return L;
}

Eigen::VectorXd lumped_mass(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(V.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 1)) - V.row(F(f, 0)), b = V.row(F(f, 2)) - V.row(F(f, 0));
    const double area = 0.5 * a.cross(b).norm();
    for (int k = 0; k < 3; ++k) m[F(f, k)] += area / 3.0;
  }
  return m;
}

}  // namespace gp
