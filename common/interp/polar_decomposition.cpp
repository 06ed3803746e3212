#include "interp/polar_decomposition.h"

#include <Eigen/Dense>

#include <Eigen/SVD>

namespace gp {

void polar_decomposition(const Eigen::Matrix3d& Q, Eigen::Matrix3d& R, Eigen::Matrix3d& S) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Q, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d& Vm = svd.matrixV();
  Eigen::Vector3d sigma = svd.singularValues();
  if ((U * Vm.transpose()).determinant() < 0.0) {
    // Singular values are sorted decreasingly: flip the least significant one.
    U.col(2) = -U.col(2);
    sigma(2) = -sigma(2);
  }
  R = U * Vm.transpose();
  S = Vm * sigma.asDiagonal() * Vm.transpose();
  S = 0.5 * (S + S.transpose()).eval();
}

}  // namespace gp
