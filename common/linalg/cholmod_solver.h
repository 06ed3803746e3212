#pragma once
// Sparse Cholesky factorization A = L L^T of a symmetric positive definite
// matrix with CHOLMOD (SuiteSparse), in the "factor once, solve many times"
// shape of libigl's arap precomputation/solve:
//   CholmodSolver solver;
//   solver.analyze(A);      // fill-reducing ordering + symbolic factor, once per pattern
//   solver.factorize(A);    // numeric factor; reuses the analysis while the pattern is unchanged
//   X = solver.solve(B);    // #n by k right-hand sides, as often as needed
// Only the lower triangle of A is read (the upper one may be present or not).
// Errors are thrown, never printed: NumericalError when A is not positive
// definite or holds non-finite values, UsageError when called out of order or
// with mismatched sizes.
//
// Not thread-safe: one solver must not be used from several threads at once
// (solve() reuses internal workspace). Distinct solvers are independent.
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace gp {

struct CholmodOptions {
  enum class Method {
    supernodal,  // dense BLAS blocks (OpenBLAS); fastest factorization for meshes
    simplicial,  // column by column, LL^T; fewer overheads for tiny systems
  };
  Method method = Method::supernodal;
  // Supernodal amalgamation (CHOLMOD's Common->nrelax): supernodes merge up to relax_columns[0]
  // columns, and up to [1] / [2] while few added entries are zero, trading explicit zeros for
  // fewer, larger BLAS calls. Ours factors the cloth matrix faster than CHOLMOD's {4, 16, 48}
  // (linalg/README.md).
  int relax_columns[3] = {8, 32, 96};
};

class CholmodSolver {
 public:
  explicit CholmodSolver(CholmodOptions options = {});
  ~CholmodSolver();
  // Moving transfers the factor; the source is left empty (not factorized) but usable.
  CholmodSolver(CholmodSolver&&) noexcept;
  CholmodSolver& operator=(CholmodSolver&&) noexcept;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  // Symbolic analysis of the n by n pattern of A (values are ignored).
  // Throws UsageError if A is not square or is empty.
  void analyze(const Eigen::SparseMatrix<double>& A);

  // Numeric factorization of A. If A's pattern (lower triangle) differs from the
  // analyzed one, or nothing was analyzed yet, analyze(A) is called first.
  // Throws NumericalError naming the failing column if A is not positive
  // definite, or the first non-finite entry.
  void factorize(const Eigen::SparseMatrix<double>& A);

  // analyze(A) then factorize(A).
  void compute(const Eigen::SparseMatrix<double>& A);

  // X = A^-1 B for B of size n by k (k >= 1 right-hand sides at once).
  // Throws UsageError if nothing is factorized or B has the wrong row count,
  // NumericalError if the solution is not finite.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  // Same, writing into X (resized to n by k); reuses X's storage and the
  // solver's workspace, so a loop of solves allocates nothing after the first.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const;

  int size() const { return n_; }
  bool analyzed() const;
  bool factorized() const { return factorized_; }
  // How often analyze() ran (directly or from factorize()); lets callers and
  // tests confirm that refactorizations reuse the symbolic analysis.
  int analyze_count() const { return analyze_count_; }
  // Entries of the factor L (a measure of memory and solve cost).
  double factor_nonzeros() const;
  // True when CHOLMOD chose/kept a supernodal factor.
  bool is_supernodal() const;

 private:
  struct Impl;
  // analyze() of A's lower triangle (compressed), which factorize() has made already.
  void analyze_lower(const Eigen::SparseMatrix<double>& lower);
  std::unique_ptr<Impl> impl_;
  CholmodOptions options_;
  int n_ = 0;
  bool factorized_ = false;
  int analyze_count_ = 0;
  std::vector<int> pattern_outer_;  // lower-triangle pattern of the analyzed matrix
  std::vector<int> pattern_inner_;
};

}  // namespace gp
