#pragma once
// As-rigid-as-possible stitching of per-triangle 2D targets into one 3D rest
// mesh (Wolff et al. 2023, appendix B; local/global iterations of Sorkine and
// Alexa 2007 with one rotation per triangle, Liu et al. 2008):
//   E(X, R) = sum_f sum_{edges (i,j) of f} w_fe |(x_j - x_i) - R_f (t_j - t_i)|^2
// t the 2D target corners, R_f 3x2 with orthonormal columns. Local step: R_f
// = polar factor of sum w (x_j - x_i)(t_j - t_i)^T. Global step: (L + eps D)
// X = B(R) + eps D X_k, L the weighted graph Laplacian, D its diagonal, eps =
// 1e-5 (a proximal term fixing the translation, zero at the fixed point).
// w_fe = A_f / l_fe^2 from the design, fixed, so L is factored once per
// connectivity; E is the area-weighted squared relative edge misfit.
//
// Smoothing (length kappa > 0): + kappa^2 sum_v |(L d)_v|^2 / A_v over inner
// vertices, d = X - X_0 the displacement from the start: a bilaplacian that
// resists changes of form shorter than kappa, so that growth becomes a smooth
// bulge instead of mesh-sized tucks. Constant, so it joins the factor.
//
// Convergence: the largest edge-length change in one iteration over the mean
// target edge length (the embedding may drift along isometric bending modes,
// which a displacement criterion would chase).
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "linalg/cholmod_solver.h"

namespace gp::adapt {

// The 3x2 matrix with orthonormal columns closest to S (Frobenius): the polar
// factor S (S^T S)^-1/2; one of the closest where S has rank < 2.
Eigen::Matrix<double, 3, 2> closest_orthonormal(const Eigen::Matrix<double, 3, 2>& S);

struct ArapOptions {
  double tolerance = 1e-5;  // max edge-length change per iteration / mean target edge length
  // > 0: stop instead when no face's principal stretch changes by more than
  // this in one iteration (what the clipping acts on); 0: the edge rule.
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
  // Weights from V_reference (#V by 3), F (#F by 3) and the smoothing length
  // (m; 0: none); factors the global matrix. Throws GeometryError for a
  // degenerate reference triangle, NumericalError if factoring fails.
  ArapStitcher(const Eigen::MatrixXd& V_reference, const Eigen::MatrixXi& F, double smoothing_length = 0.0);

  // Stitches `targets` (#F edge matrices [t1-t0, t2-t0], 2D) starting from V (the
  // current rest shape, #V by 3); V is overwritten with the result. Throws
  // UsageError for mismatched sizes, NumericalError for non-finite input.
  ArapReport stitch(const std::vector<Eigen::Matrix2d>& targets, Eigen::MatrixXd& V,
                    const ArapOptions& options = {}) const;

  // E(X, R) (m^2) at the optimal rotations, plus the smoothing term when
  // `anchor` (the stitching's start, #V by 3) is given; `gradient` gets dE/dX
  // (#V by 3; the rotations' derivative drops out at their optimum): the
  // stationarity residual, zero at a converged stitching.
  double energy(const std::vector<Eigen::Matrix2d>& targets, const Eigen::MatrixXd& V,
                const Eigen::MatrixXd* anchor = nullptr, Eigen::MatrixXd* gradient = nullptr) const;

  const Eigen::MatrixXi& faces() const { return F_; }
  int factorizations() const { return factorizations_; }

 private:
  using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  Eigen::MatrixXi F_;
  RowMatrixX3i corners_;  // row-major for the per-face loops
  RowMatrixX3d weights_;  // #F by 3: weight of edge k = (corner k -> corner k+1)
  Eigen::VectorXd diagonal_;  // D (#V)
  Eigen::SparseMatrix<double> smoothing_;  // kappa^2 L_w^T A^-1 L_w (#V by #V), empty without smoothing
  double epsilon_ = 1e-5;
  // Simplicial: factored once, solved every iteration; supernodal BLAS calls
  // cost more than they save on this small Laplacian (README.md).
  CholmodSolver solver_{CholmodOptions{CholmodOptions::Method::simplicial}};
  int factorizations_ = 0;
  int n_ = 0;
};

}  // namespace gp::adapt
