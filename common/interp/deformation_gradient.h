#pragma once
// Per-triangle frames and deformation gradients between two poses of one mesh, as in deformation
// transfer (Sumner & Popovic 2004, Sec. 3): triangle (v0, v1, v2) gets the frame W = [e1 e2 n],
//   e1 = v1 - v0, e2 = v2 - v0, n = (e1 x e2) / sqrt(|e1 x e2|)   (n grows like an edge),
// and Q = W_B W_A^-1 maps A's edges onto B's and A's normal onto B's scaled normal; det W =
// |e1 x e2|^(3/2) > 0, so Q is never a reflection for non-degenerate triangles.
#include <vector>

#include <Eigen/Core>

namespace gp {

// Frame [e1 e2 n] (columns) of triangle f of (V, F); V is #V by 3, F #F by 3.
Eigen::Matrix3d triangle_frame(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f);

// Twice the area below which a triangle is degenerate here: `relative` x V's squared bbox diagonal.
double degenerate_double_area(const Eigen::MatrixXd& V, double relative = 1e-14);

// Deformation gradients Q_f = W_B(f) W_A(f)^-1 for every triangle, #F entries.
// `valid[f]` is false (and Q_f the identity) where the triangle is degenerate
// in A or B (twice its area below degenerate_double_area of that pose).
void deformation_gradients(const Eigen::MatrixXd& V_A, const Eigen::MatrixXd& V_B,
                           const Eigen::MatrixXi& F, std::vector<Eigen::Matrix3d>& Q,
                           std::vector<bool>& valid);

}  // namespace gp
