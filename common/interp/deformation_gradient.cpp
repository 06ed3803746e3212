#include "interp/deformation_gradient.h"

#include <Eigen/Dense>

#include <cmath>


#include "mesh/measures.h"

namespace gp {

Eigen::Matrix3d triangle_frame(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d v0 = V.row(F(f, 0)).transpose();
  const Eigen::Vector3d e1 = V.row(F(f, 1)).transpose() - v0;
  const Eigen::Vector3d e2 = V.row(F(f, 2)).transpose() - v0;
  const Eigen::Vector3d c = e1.cross(e2);
  const double len = c.norm();
  Eigen::Matrix3d W;
  W.col(0) = e1;
  W.col(1) = e2;
  // Sumner & Popovic 2004, Eq. 1: the normal scaled by 1/sqrt(|e1 x e2|).
  W.col(2) = len > 0.0 ? Eigen::Vector3d(c / std::sqrt(len)) : Eigen::Vector3d::Zero();
  return W;
}

double degenerate_double_area(const Eigen::MatrixXd& V, double relative) {
  const double d = bounding_box_diagonal(V);
  return relative * d * d;
}

void deformation_gradients(const Eigen::MatrixXd& V_A, const Eigen::MatrixXd& V_B,
                           const Eigen::MatrixXi& F, std::vector<Eigen::Matrix3d>& Q,
                           std::vector<bool>& valid) {
  const double tiny_A = degenerate_double_area(V_A);
  const double tiny_B = degenerate_double_area(V_B);
  Q.assign(F.rows(), Eigen::Matrix3d::Identity());
  valid.assign(F.rows(), false);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix3d W_A = triangle_frame(V_A, F, f);
    const Eigen::Matrix3d W_B = triangle_frame(V_B, F, f);
    const double area2_A = W_A.col(0).cross(W_A.col(1)).norm();
    const double area2_B = W_B.col(0).cross(W_B.col(1)).norm();
    if (!(area2_A > tiny_A) || !(area2_B > tiny_B)) continue;
    Q[f] = W_B * W_A.inverse();
    valid[f] = Q[f].allFinite();
    if (!valid[f]) Q[f].setIdentity();
  }
}

}  // namespace gp
