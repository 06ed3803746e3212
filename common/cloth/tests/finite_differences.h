#pragma once
// Central finite differences of a triangle's energy and gradient (9 dofs: the
// corners as columns of X), and the smallest eigenvalue of a 9 by 9 block,
// shared by the energy tests.
#include <Eigen/Dense>

#include "cloth/cloth_energy.h"

namespace gp::cloth::testing {

template <class Energy>
Vector9d fd_gradient(const Eigen::Matrix3d& X, double eps, Energy energy) {
  Vector9d g;
  for (int i = 0; i < 9; ++i) {
    Eigen::Matrix3d Xp = X, Xm = X;
    Xp(i % 3, i / 3) += eps;
    Xm(i % 3, i / 3) -= eps;
    g(i) = (energy(Xp) - energy(Xm)) / (2.0 * eps);
  }
  return g;
}

template <class Gradient>
Matrix9d fd_hessian(const Eigen::Matrix3d& X, double eps, Gradient gradient) {
  Matrix9d H;
  for (int i = 0; i < 9; ++i) {
    Eigen::Matrix3d Xp = X, Xm = X;
    Xp(i % 3, i / 3) += eps;
    Xm(i % 3, i / 3) -= eps;
    H.col(i) = (gradient(Xp) - gradient(Xm)) / (2.0 * eps);
  }
  return H;
}

inline double min_eigenvalue(const Matrix9d& H) {
  Eigen::SelfAdjointEigenSolver<Matrix9d> es(0.5 * (H + H.transpose()));
  return es.eigenvalues().minCoeff();
}

}  // namespace gp::cloth::testing
