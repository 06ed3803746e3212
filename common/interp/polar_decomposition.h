#pragma once
// Polar decomposition Q = R S of a 3x3 matrix into a rotation R (det +1) and
// a symmetric S, from the singular value decomposition Q = U Sigma V^T:
// R = U V^T, S = V Sigma V^T (Shoemake & Duff 1992). R is the rotation closest
// to Q in the Frobenius norm. If det Q < 0 (a reflection, which triangle
// frames never produce) the smallest singular direction is flipped so that R
// stays a proper rotation; S then has one negative eigenvalue.
#include <Eigen/Core>

namespace gp {

void polar_decomposition(const Eigen::Matrix3d& Q, Eigen::Matrix3d& R, Eigen::Matrix3d& S);

}  // namespace gp
