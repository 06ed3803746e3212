#include "mesh/principal_stretches.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "core/error.h"

namespace gp {
namespace {

Eigen::Matrix3d face_positions(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  Eigen::Matrix3d X;
  for (int k = 0; k < 3; ++k) X.col(k) = V.row(F(f, k)).transpose();
  return X;
}

void check_rest_triangle(const Eigen::Matrix3d& X_rest) {
  const Eigen::Vector3d e1 = X_rest.col(1) - X_rest.col(0), e2 = X_rest.col(2) - X_rest.col(0);
  const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
  if (!X_rest.allFinite() || !(e1.cross(e2).norm() >= 1e-12 * longest2) || !(longest2 > 0.0)) {
    throw GeometryError("degenerate (zero-area) rest triangle");
  }
}

}  // namespace

Eigen::Vector2d singular_values_2x2(const Eigen::Matrix2d& J) {
  const double e = 0.5 * (J(0, 0) + J(1, 1)), f = 0.5 * (J(0, 0) - J(1, 1));
  const double g = 0.5 * (J(1, 0) + J(0, 1)), h = 0.5 * (J(1, 0) - J(0, 1));
  const double q = std::sqrt(e * e + h * h), r = std::sqrt(f * f + g * g);
  return {q + r, std::abs(q - r)};
}

Eigen::Matrix2d triangle_frame_edges(const Eigen::Matrix3d& X) {
  const Eigen::Vector3d e1 = X.col(1) - X.col(0), e2 = X.col(2) - X.col(0);
  const double l1 = e1.norm();
  Eigen::Matrix2d D;
  if (l1 > 0.0) {
    const Eigen::Vector3d u = e1 / l1;
    D << l1, e2.dot(u), 0.0, e2.cross(u).norm();
  } else {
    // x1 on x0: the triangle is at most a segment along e2.
    D << 0.0, e2.norm(), 0.0, 0.0;
  }
  return D;
}

Eigen::Matrix2d deformation_gradient(const Eigen::Matrix3d& X_rest, const Eigen::Matrix3d& X_def) {
  check_rest_triangle(X_rest);
  const Eigen::Matrix2d D_rest = triangle_frame_edges(X_rest);
  // D_rest is upper triangular with a positive diagonal: invert directly.
  Eigen::Matrix2d D_inv;
  D_inv << 1.0 / D_rest(0, 0), -D_rest(0, 1) / (D_rest(0, 0) * D_rest(1, 1)), 0.0, 1.0 / D_rest(1, 1);
  return triangle_frame_edges(X_def) * D_inv;
}

Eigen::MatrixXd principal_stretches(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_def,
                                    const Eigen::MatrixXi& F) {
  Eigen::MatrixXd S(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix2d G;
    try {
      G = deformation_gradient(face_positions(V_rest, F, f), face_positions(V_def, F, f));
    } catch (const GeometryError& e) {
      throw GeometryError(e.what(), "face " + std::to_string(f));
    }
    S.row(f) = singular_values_2x2(G).transpose();
  }
  return S;
}

}  // namespace gp
