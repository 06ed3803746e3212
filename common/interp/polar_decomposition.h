#pragma once
// Polar decomposition Q = R S of a 3x3 matrix into the rotation R (det +1) closest to Q in the
// Frobenius norm and a symmetric S, from the SVD Q = U Sigma V^T: R = U V^T, S = V Sigma V^T
// (Shoemake & Duff 1992). If det Q < 0 (never for triangle frames) the smallest singular
// direction is flipped so that R stays a rotation; S then has one negative eigenvalue.
#include <Eigen/Core>

namespace gp {

void polar_decomposition(const Eigen::Matrix3d& Q, Eigen::Matrix3d& R, Eigen::Matrix3d& S);

}  // namespace gp
