#pragma once
// Positions from per-triangle target edges by a Poisson (least-squares gradient) solve, as in
// deformation transfer (Sumner & Popovic 2004, Sec. 4) and Poisson shape interpolation (Xu et al.
// 2005): minimize sum_f A_f || grad_f(x) - G_f ||_F^2 over x, G_f mapping the rest edges
// E_f = [r1 r2] (3x2) of a fixed rest mesh onto the target edges T_f = [e1_f e2_f]; per face,
// with D_f(x) = [x1 - x0, x2 - x0],
//   A_f tr((D_f(x) - T_f) M_f (D_f(x) - T_f)^T),   M_f = (E_f^T E_f)^-1.
// Normal equations L x = b: L = sum_f C_f^T (A_f M_f) C_f, the rest mesh's cotangent Laplacian (C_f
// the 2x3 edge-difference matrix), b = sum_f C_f^T (A_f M_f) T_f^T. L is factored once; a solve is
// one assembly of b and a back-substitution with 3 right-hand sides.
//
// The energy ignores each connected component's translation, so the lowest vertex id of every
// component is pinned at the origin (callers place the result, e.g. by an anchor); vertices in no
// face stay at 0.
#include <vector>

#include <Eigen/Core>

#include "linalg/cholmod_solver.h"

namespace gp {

// Target edges per face: row f = (e1.x, e1.y, e1.z, e2.x, e2.y, e2.z) with
// e1 = x1 - x0, e2 = x2 - x0 over the corners of F.row(f).
using FaceEdges = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

// Edges of every triangle of (V, F) in the FaceEdges layout.
FaceEdges face_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

class GradientPoissonSolver {
 public:
  // Builds and factors L from the rest mesh (V_rest #V by 3, F #F by 3).
  // Throws GeometryError naming the first degenerate rest triangle (twice its
  // area below 1e-14 of the squared bounding-box diagonal), NumericalError if
  // the factorization fails.
  GradientPoissonSolver(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                        CholmodOptions options = {});

  // Solves for positions (#V by 3) whose triangles best match `target`
  // (#F rows); pinned vertices at the origin. Reuses internal buffers.
  void solve(const FaceEdges& target, Eigen::MatrixXd& V_out);

  int vertex_count() const { return n_vertices_; }
  // Component id per vertex (-1 for vertices in no face), and their count.
  const Eigen::VectorXi& vertex_component() const { return vertex_component_; }
  int component_count() const { return n_components_; }
  // Wall-clock seconds of building L and of its symbolic + numeric factorization.
  double factorization_seconds() const { return factorization_seconds_; }
  const CholmodSolver& solver() const { return solver_; }

 private:
  Eigen::MatrixXi F_;
  int n_vertices_ = 0;
  int n_components_ = 0;
  Eigen::VectorXi vertex_component_;
  Eigen::VectorXi reduced_id_;  // vertex -> unknown index, -1 if pinned or unused
  Eigen::MatrixXd weights_;     // #F by 3: A_f M_f as (m11, m12, m22)
  CholmodSolver solver_;
  double factorization_seconds_ = 0.0;
  Eigen::MatrixXd rhs_, x_;
};

}  // namespace gp
