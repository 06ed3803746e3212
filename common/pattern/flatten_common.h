#pragma once
// What the flattening methods (flatten.h) share. Internal to pattern/.
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/cholmod_solver.h"
#include "pattern/flatten.h"

namespace gp::flatten_detail {

using Triplet = Eigen::Triplet<double>;

// Simplicial: it calls no BLAS, so a flattening is bitwise the same whichever
// kernels OpenBLAS picks for the CPU (and faster here: README.md).
inline const CholmodOptions kFlattenSolver{CholmodOptions::Method::simplicial};

// A triangle in an orthonormal frame of its own plane: corner 0 at the origin,
// corner 1 on the x axis. D maps corner values (3) to the gradient (2), so the
// Jacobian of the flat map with corner positions U (3 by 2) is J = (D U)^T.
struct LocalTriangle {
  Eigen::Matrix<double, 2, 3> D = Eigen::Matrix<double, 2, 3>::Zero();
  double area = 0.0;
  bool degenerate = true;
};

std::vector<LocalTriangle> local_triangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// local_triangles with every area raised to at least `fraction` of the
// mean: the weights of the flattening energies. The thin triangles a cut
// leaves where it passes close to a vertex would otherwise turn over at no
// cost (and make LSCM's system numerically singular); a stiff small triangle
// keeps its shape, so its share of the energy still vanishes with its size.
// `face_weight` (#F, optional) multiplies each weight (limit_weights, flatten.h).
std::vector<LocalTriangle> weighted_triangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double fraction,
                                              const Eigen::VectorXd* face_weight = nullptr);

// A boundary edge i -> j of 3D length `length` and the weight of keeping it
// (the boundary-length term of flattening_energy).
struct BoundaryEdge {
  int i, j;
  double length, weight;
};

// The boundary edges of the non-degenerate triangles T (weighted_triangles),
// weighted relative to the edge's own triangle at its true area: a thin
// triangle's raised weight must not make its short edge a hard constraint.
std::vector<BoundaryEdge> boundary_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                         const std::vector<LocalTriangle>& T, double boundary_weight);

Eigen::Matrix2d jacobian(const LocalTriangle& t, const Eigen::MatrixXd& UV, const Eigen::Vector3i& f);

double signed_area_2d(const Eigen::MatrixXd& UV, const Eigen::Vector3i& f);

// The local step of the energy sum_i f(s_i) over the singular values s_i of
// J, f(s) = (1 - s)^2 below 1 and ease_weight (s - 1)^2 above: the target
// T = J - grad / 2 = U diag(t(s)) V^T with t(s) = 1 below 1 and
// 1 + (1 - ease_weight)(s - 1) above (J = U diag(s) V^T in closed form,
// s_y < 0 when J flips). With ease_weight <= 1 the quadratic |J - T|^2 about
// the current J majorizes the energy, so the global step never raises it
// (local/global as majorization-minimization). A flipped J goes to its
// closest rotation, as in ARAP. Returns T; `energy` gets sum_i f(s_i).
Eigen::Matrix2d local_target(const Eigen::Matrix2d& J, double ease_weight, double& energy);

// Dirichlet matrix L = sum_t A_t D_t^T D_t (the cotangent Laplacian, PSD by construction).
Eigen::SparseMatrix<double> dirichlet_matrix(const std::vector<LocalTriangle>& T,
                                             const Eigen::MatrixXi& F, int n);

// Solves the quadratic problem min 1/2 x^T H x with the variables in `fixed`
// (value per variable, NaN when free) held: H_ff x_f = -H_fp x_p.
Eigen::VectorXd solve_with_fixed(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& fixed);

// Two boundary vertices far apart (the first one farthest from the loop's
// first vertex, the second farthest from it), to pin LSCM's similarity freedom.
std::pair<int, int> far_pair(const Eigen::MatrixXd& V, const std::vector<int>& loop);

int count_flips(const Eigen::MatrixXd& UV, const Eigen::MatrixXi& F);

// Largest t in (0, t_cap] such that every triangle keeps a positive area on
// UV + t dUV: the smallest positive root of each triangle's area, a quadratic
// in t (Smith and Schaefer 2015, section 4.2).
double max_flip_free_step(const Eigen::MatrixXd& UV, const Eigen::MatrixXd& dUV,
                          const Eigen::MatrixXi& F, double t_cap);

// Untangles the few flipped triangles a plain flattening can leave (sharp
// concave corners, thin triangles along a cut) by Jacobi smoothing of the
// rings around them (outline vertices along the outline), growing the region
// while flips remain. Whether no flip is left.
bool repair_flips(const Eigen::MatrixXi& F, const std::vector<std::vector<int>>& neighbors,
                  const std::vector<int>& loop, Eigen::MatrixXd& UV);

}  // namespace gp::flatten_detail
