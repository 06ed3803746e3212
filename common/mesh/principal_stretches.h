#pragma once
// Principal stretches of a triangle map: the singular values s1 >= s2 >= 0
// of its deformation gradient, the 2x2 matrix F = D_def D_rest^-1 that takes
// the rest triangle's edge matrix to the deformed one's, each laid out in its
// own plane. They are invariant to rotations and reflections of either
// triangle (Wolff et al. 2023, appendix A; Sorkine and Alexa 2007, sec. 2).
//
// A triangle's own frame: x0 at the origin, x0->x1 along the first axis, x2
// with a non-negative second coordinate, so that D = [x1-x0, x2-x0] is upper
// triangular with det D >= 0.
#include <Eigen/Core>

namespace gp {

// Singular values (s1 >= s2 >= 0) of a 2x2 matrix, in closed form: with
// e, f, g, h the halves of J00 + J11, J00 - J11, J10 + J01, J10 - J01,
// s = sqrt(e^2 + h^2) +- sqrt(f^2 + g^2).
Eigen::Vector2d singular_values_2x2(const Eigen::Matrix2d& J);

// 2D edge matrix of the triangle X = [x0 x1 x2] (columns, metres) in its own
// frame; zero rows for collapsed edges.
Eigen::Matrix2d triangle_frame_edges(const Eigen::Matrix3d& X);

// F = D_def D_rest^-1. Throws GeometryError for a zero-area rest triangle
// (2 A / longest edge^2 < 1e-12) or a non-finite one.
Eigen::Matrix2d deformation_gradient(const Eigen::Matrix3d& X_rest, const Eigen::Matrix3d& X_def);

// (s1, s2) of every face from V_rest to V_def (both #V by 3, metres): #F by
// 2. Throws GeometryError naming the face for a zero-area rest triangle.
Eigen::MatrixXd principal_stretches(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_def,
                                    const Eigen::MatrixXi& F);

}  // namespace gp
