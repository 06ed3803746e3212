#pragma once
// As-rigid-as-possible stitching of per-triangle 2D targets into one 3D rest
// mesh (Wolff et al. 2023, appendix B; local/global iterations of Sorkine &
// Alexa 2007, here with one rotation per triangle as in Liu et al. 2008):
//   E(X, R) = sum_f sum_{edges (i,j) of f} w_fe |(x_j - x_i) - R_f (t_j - t_i)|^2
// with t the target corners of face f (2D), R_f a 3x2 matrix with orthonormal
// columns. Local step: R_f = polar factor of sum w (x_j - x_i)(t_j - t_i)^T.
// Global step: a Poisson-like solve (L + eps D) X = B(R) + eps D X_k, where L is
// the weighted graph Laplacian, D its diagonal and eps = 1e-5 (a proximal term
// that fixes the free translation and vanishes at the fixed point).
//
// The weights w_fe = A_f / l_fe^2 come from a reference rest shape (the garment's
// design) and stay fixed, so L does not depend on the targets: it is factored by
// CHOLMOD once per connectivity and reused across iterations and adaptations.
// The energy is then the area-weighted squared relative edge misfit.
//
// Smoothing (smoothing_length kappa > 0): + kappa^2 sum_v |(L d)_v|^2 / A_v
// over inner vertices v (the border's form is free), d = X - X_0 the displacement from the shape the stitching starts from and
// A_v the reference's vertex areas, a bilaplacian that resists changes of
// form shorter than kappa. Per-triangle targets alone do not say where the
// grown cloth goes in 3D, and plain ARAP puts it into mesh-sized folds
// (tucks) and cone points; with the term it becomes a smooth bulge. The term
// is constant, so it joins the factored matrix.
//
// Convergence: iterate until the largest change of an edge length in one
// iteration, divided by the mean target edge length, falls below `tolerance`.
// (The rest shape enters the cloth model only through its triangles' shapes; its
// embedding can keep drifting along nearly isometric bending modes, which a
// displacement criterion would chase without end.)
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "linalg/cholmod_solver.h"

namespace gp::adapt {

// The 3x2 matrix with orthonormal columns closest to S in the Frobenius norm
// (the local step's rotation): the polar factor S (S^T S)^-1/2, unique where S
// has rank two; otherwise one of the equally close ones.
Eigen::Matrix<double, 3, 2> closest_orthonormal(const Eigen::Matrix<double, 3, 2>& S);

struct ArapOptions {
  // Relative: max edge-length change per iteration / mean target edge length.
  // 1e-5 (0.15 micrometres on a 1.5 cm edge) took 58 iterations per adaptation
  // on the shared-body shirt moving T -> A against 266 at 1e-6, with the same
  // stretch figures and rest-area growth within 0.4 %.
  double tolerance = 1e-5;
  // > 0: iterate instead until no face's principal stretch changes by more
  // than this in one iteration (unitless, e.g. 1e-4 = 0.01 % stretch), the
  // quantity the adaptation's clipping acts on; 0: the edge rule above.
  double stretch_tolerance = 0.0;
  int max_iterations = 2000;
};

struct ArapReport {
  int iterations = 0;
  double residual = 0.0;  // last iteration's change: by the edge rule, or the stretch rule's largest stretch change
  double misfit = 0.0;    // sqrt(E / sum w |t_j - t_i|^2): RMS relative edge misfit at the end
  bool converged = false;
};

class ArapStitcher {
 public:
  ArapStitcher() = default;
  // Fixed weights from the reference shape V_reference (#V by 3) with faces F
  // (#F by 3), and the smoothing length [m] (0: none); factors the global
  // matrix. Throws GeometryError for degenerate reference triangles,
  // NumericalError if the factorization fails.
  ArapStitcher(const Eigen::MatrixXd& V_reference, const Eigen::MatrixXi& F, double smoothing_length = 0.0);

  // Stitches `targets` (#F edge matrices [t1-t0, t2-t0], 2D) starting from V (the
  // current rest shape, #V by 3); V is overwritten with the result. Throws
  // UsageError for mismatched sizes, NumericalError for non-finite input.
  ArapReport stitch(const std::vector<Eigen::Matrix2d>& targets, Eigen::MatrixXd& V,
                    const ArapOptions& options = {}) const;

  // E(X, R) at the optimal rotations, plus the smoothing term when `anchor`
  // (the shape a stitching starts from, #V by 3) is given. With `gradient`,
  // also dE/dX (#V by 3; E is in m^2, the weights being unitless): at the
  // optimal rotations the rotations' own derivative drops out, so it is
  // sum_f sum_k 2 w_fk ((x_j - x_i) - R_f dt_k) on x_j (minus on x_i), plus
  // 2 S (X - anchor) for the smoothing matrix S. It is the stitching's
  // stationarity residual: zero exactly at a converged stitching.
  double energy(const std::vector<Eigen::Matrix2d>& targets, const Eigen::MatrixXd& V,
                const Eigen::MatrixXd* anchor = nullptr, Eigen::MatrixXd* gradient = nullptr) const;

  const Eigen::MatrixXi& faces() const { return F_; }
  int factorizations() const { return factorizations_; }

 private:
  using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  Eigen::MatrixXi F_;
  // Row-major copies for the per-face loops of every iteration, which read a
  // face's three corners (and write them in the global step's right-hand side).
  RowMatrixX3i corners_;
  RowMatrixX3d weights_;  // #F by 3: weight of edge k = (corner k -> corner k+1)
  Eigen::VectorXd diagonal_;  // D (#V)
  Eigen::SparseMatrix<double> smoothing_;  // kappa^2 L_w^T A^-1 L_w (#V by #V), empty without smoothing
  double epsilon_ = 1e-5;
  // Simplicial: the factorization happens once, the three-column solve every
  // iteration, and for this small Laplacian the supernodal factor's BLAS calls
  // cost more than they save. Measured on nine adaptations of the 3,829-vertex
  // shirt moving T -> A (one thread): 0.73 against 0.93 ms per iteration.
  CholmodSolver solver_{CholmodOptions{CholmodOptions::Method::simplicial}};
  int factorizations_ = 0;
  int n_ = 0;
};

}  // namespace gp::adapt
