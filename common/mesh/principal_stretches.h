#pragma once
// Principal stretches of a triangle map: the singular values s1 >= s2 >= 0
// of F = D_def D_rest^-1, with D = [x1-x0, x2-x0] each triangle's edge matrix
// in its own frame (x0 at the origin, x1 on the first axis, x2 above it), so
// invariant to rotations and reflections (Wolff et al. 2023, appendix A).
#include <Eigen/Core>

namespace gp {

// Singular values (s1 >= s2 >= 0) of a 2x2 matrix, in closed form.
Eigen::Vector2d singular_values_2x2(const Eigen::Matrix2d& J);

// D of X = [x0 x1 x2] (columns, metres); zero rows for collapsed edges.
Eigen::Matrix2d triangle_frame_edges(const Eigen::Matrix3d& X);

// F; GeometryError for a non-finite or zero-area (2A / L^2 < 1e-12) rest triangle.
Eigen::Matrix2d deformation_gradient(const Eigen::Matrix3d& X_rest, const Eigen::Matrix3d& X_def);

// (s1, s2) of every face from V_rest to V_def (both #V by 3, metres): #F by
// 2. Throws GeometryError naming the face for a zero-area rest triangle.
Eigen::MatrixXd principal_stretches(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_def,
                                    const Eigen::MatrixXi& F);

}  // namespace gp
