#include "linalg/cholmod_solver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include <cholmod.h>

#include "core/error.h"

namespace gp {

// CHOLMOD state: the common block (settings, workspace), the factor and the
// dense workspaces cholmod_solve2 reuses from one solve to the next.
//
// A supernodal factor is of the permuted matrix P A P^T, kept here in lower
// form (S) with the position of each of A's lower entries in it: CHOLMOD,
// given A's lower triangle and its own ordering, transposes the matrix twice
// per factorization to build that (cholmod_factorize: the lower, permuted
// case), 2.6 % of simulate-adapt's time on the 3,829-vertex shirt; given P A
// P^T and a natural ordering it reads it as it is. Solves apply P themselves.
struct CholmodSolver::Impl {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  cholmod_dense* X = nullptr;
  cholmod_dense* Y = nullptr;
  cholmod_dense* E = nullptr;
  bool permuted = false;            // L is the natural-order factor of S = P A P^T
  std::vector<int> perm;            // P: row k of S is row perm[k] of A
  Eigen::SparseMatrix<double> S;    // lower triangle of P A P^T
  std::vector<int> position;        // per lower entry of A, its index in S's values
  Eigen::MatrixXd permuted_rhs;     // P B of a solve

  explicit Impl(const CholmodOptions& options) {
    cholmod_start(&common);
    // Library code never prints (errors are thrown from the status instead).
    common.print = 0;
    common.error_handler = nullptr;
    common.supernodal =
        options.method == CholmodOptions::Method::supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    // Keep an LL^T factor in either method, so that a non-positive pivot is
    // always reported as CHOLMOD_NOT_POSDEF rather than hidden in an LDL^T.
    common.final_ll = 1;
    common.quick_return_if_not_posdef = 1;
    for (int k = 0; k < 3; ++k) common.nrelax[k] = static_cast<size_t>(std::max(options.relax_columns[k], 1));
  }
  ~Impl() {
    free_workspace();
    if (L) cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }
  // After the analysis of `lower` (n by n): a supernodal factor in a
  // fill-reducing order becomes the natural-order factor of S = P A P^T.
  void use_permuted_form(const Eigen::SparseMatrix<double>& lower, int n);
  void free_workspace() {
    if (X) cholmod_free_dense(&X, &common);
    if (Y) cholmod_free_dense(&Y, &common);
    if (E) cholmod_free_dense(&E, &common);
  }
};

namespace {

// Lower triangle of A in compressed column form (what CHOLMOD reads with stype -1).
Eigen::SparseMatrix<double> lower_triangle(const Eigen::SparseMatrix<double>& A) {
  Eigen::SparseMatrix<double> lower = A.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  return lower;
}

// A view of `A` (not a copy) for CHOLMOD, which only reads it; A must stay
// alive and be compressed.
cholmod_sparse view_of(const Eigen::SparseMatrix<double>& A) {
  cholmod_sparse s;
  std::memset(&s, 0, sizeof(s));
  s.nrow = static_cast<size_t>(A.rows());
  s.ncol = static_cast<size_t>(A.cols());
  s.nzmax = static_cast<size_t>(A.nonZeros());
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.i = const_cast<int*>(A.innerIndexPtr());
  s.nz = nullptr;
  s.x = const_cast<double*>(A.valuePtr());
  s.z = nullptr;
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

void check_square(const Eigen::SparseMatrix<double>& A) {
  if (A.rows() != A.cols() || A.rows() == 0)
    throw UsageError("CholmodSolver needs a non-empty square matrix, got " + std::to_string(A.rows()) +
                     " by " + std::to_string(A.cols()));
}

}  // namespace

void CholmodSolver::Impl::use_permuted_form(const Eigen::SparseMatrix<double>& lower, int n) {
  if (!L->is_super || L->ordering == CHOLMOD_NATURAL) return;
  // The lower triangle of P A P^T, and where each entry of A goes in it.
  const int* p = static_cast<const int*>(L->Perm);
  std::vector<int> inverse(n);
  for (int k = 0; k < n; ++k) inverse[p[k]] = k;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(lower.nonZeros());
  for (int col = 0; col < n; ++col) {
    for (int q = lower.outerIndexPtr()[col]; q < lower.outerIndexPtr()[col + 1]; ++q) {
      const int r = inverse[lower.innerIndexPtr()[q]], c = inverse[col];
      entries.emplace_back(std::max(r, c), std::min(r, c), static_cast<double>(q));
    }
  }
  Eigen::SparseMatrix<double> permuted_lower(n, n);
  permuted_lower.setFromTriplets(entries.begin(), entries.end());
  permuted_lower.makeCompressed();
  std::vector<int> entry_position(lower.nonZeros());
  for (Eigen::Index k = 0; k < permuted_lower.nonZeros(); ++k) {
    entry_position[static_cast<size_t>(permuted_lower.valuePtr()[k])] = static_cast<int>(k);
  }
  // The same analysis of it in its own order: the ordering (with its
  // postorder) is already applied, so the elimination tree and the
  // supernodes come out the same.
  const int saved_methods = common.nmethods, saved_ordering = common.method[0].ordering,
            saved_postorder = common.postorder;
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_NATURAL;
  common.postorder = 0;
  cholmod_sparse view = view_of(permuted_lower);
  cholmod_factor* natural = cholmod_analyze(&view, &common);
  common.nmethods = saved_methods;
  common.method[0].ordering = saved_ordering;
  common.postorder = saved_postorder;
  bool identity = natural && natural->is_super && common.status >= CHOLMOD_OK;
  for (int k = 0; identity && k < n; ++k) identity = static_cast<const int*>(natural->Perm)[k] == k;
  if (!identity) {
    if (natural) cholmod_free_factor(&natural, &common);
    return;
  }
  perm.assign(p, p + n);
  cholmod_free_factor(&L, &common);
  L = natural;
  S = std::move(permuted_lower);
  position = std::move(entry_position);
  permuted = true;
}

CholmodSolver::CholmodSolver(CholmodOptions options)
    : impl_(std::make_unique<Impl>(options)), options_(options) {}
CholmodSolver::~CholmodSolver() = default;
CholmodSolver::CholmodSolver(CholmodSolver&& other) noexcept { *this = std::move(other); }

CholmodSolver& CholmodSolver::operator=(CholmodSolver&& other) noexcept {
  if (this == &other) return *this;
  impl_ = std::move(other.impl_);
  options_ = other.options_;
  n_ = other.n_;
  factorized_ = other.factorized_;
  analyze_count_ = other.analyze_count_;
  pattern_outer_ = std::move(other.pattern_outer_);
  pattern_inner_ = std::move(other.pattern_inner_);
  // The moved-from solver is empty but usable: it can analyze a new matrix.
  other.impl_ = std::make_unique<Impl>(other.options_);
  other.n_ = 0;
  other.factorized_ = false;
  other.analyze_count_ = 0;
  return *this;
}

bool CholmodSolver::analyzed() const { return impl_ && impl_->L != nullptr; }

void CholmodSolver::analyze(const Eigen::SparseMatrix<double>& A) {
  check_square(A);
  analyze_lower(lower_triangle(A));
}

void CholmodSolver::analyze_lower(const Eigen::SparseMatrix<double>& lower) {
  cholmod_sparse s = view_of(lower);
  Impl& m = *impl_;
  m.free_workspace();
  if (m.L) cholmod_free_factor(&m.L, &m.common);
  m.permuted = false;
  factorized_ = false;
  m.L = cholmod_analyze(&s, &m.common);
  if (!m.L || m.common.status < CHOLMOD_OK)
    throw NumericalError("CHOLMOD symbolic analysis failed (status " +
                         std::to_string(m.common.status) + ", out of memory?)");
  n_ = static_cast<int>(lower.rows());
  m.use_permuted_form(lower, n_);
  pattern_outer_.assign(lower.outerIndexPtr(), lower.outerIndexPtr() + lower.outerSize() + 1);
  pattern_inner_.assign(lower.innerIndexPtr(), lower.innerIndexPtr() + lower.nonZeros());
  ++analyze_count_;
}

void CholmodSolver::factorize(const Eigen::SparseMatrix<double>& A) {
  check_square(A);
  auto analyzed_pattern = [this](const Eigen::SparseMatrix<double>& M) {
    return analyzed() && M.isCompressed() && M.rows() == n_ &&
           static_cast<size_t>(M.nonZeros()) == pattern_inner_.size() &&
           std::equal(pattern_outer_.begin(), pattern_outer_.end(), M.outerIndexPtr()) &&
           std::equal(pattern_inner_.begin(), pattern_inner_.end(), M.innerIndexPtr());
  };
  // The simulator refactors a lower-triangle matrix of the analyzed pattern
  // every step: it is read in place, saving the copy of its lower triangle
  // (0.35 ms for the 3,829-vertex shirt's 11,268 unknowns, 115,000 entries).
  const bool same_pattern = analyzed_pattern(A);
  Eigen::SparseMatrix<double> lower_copy;
  if (!same_pattern) lower_copy = lower_triangle(A);
  const Eigen::SparseMatrix<double>& lower = same_pattern ? A : lower_copy;
  for (Eigen::Index k = 0; k < lower.nonZeros(); ++k)
    if (!std::isfinite(lower.valuePtr()[k])) {
      int col = 0;
      while (lower.outerIndexPtr()[col + 1] <= k) ++col;
      throw NumericalError("matrix entry (" + std::to_string(lower.innerIndexPtr()[k]) + ", " +
                           std::to_string(col) + ") is not finite");
    }
  if (!same_pattern && !analyzed_pattern(lower_copy)) analyze_lower(lower_copy);
  Impl& m = *impl_;
  if (m.permuted) {
    double* values = m.S.valuePtr();
    const double* from = lower.valuePtr();
    for (size_t q = 0; q < m.position.size(); ++q) values[m.position[q]] = from[q];
  }
  cholmod_sparse s = view_of(m.permuted ? m.S : lower);
  factorized_ = false;
  const int ok = cholmod_factorize(&s, m.L, &m.common);
  if (m.common.status == CHOLMOD_NOT_POSDEF) {
    const size_t k = m.L->minor;
    const int* perm = m.permuted ? m.perm.data() : static_cast<const int*>(m.L->Perm);
    const long original = perm && k < m.L->n ? perm[k] : static_cast<long>(k);
    throw NumericalError("matrix is not positive definite (Cholesky pivot " + std::to_string(k) +
                         " of " + std::to_string(n_) + " fails, at original row " +
                         std::to_string(original) + ")");
  }
  if (!ok || m.common.status < CHOLMOD_OK)
    throw NumericalError("CHOLMOD numeric factorization failed (status " + std::to_string(m.common.status) + ")");
  factorized_ = true;
}

void CholmodSolver::compute(const Eigen::SparseMatrix<double>& A) {
  analyze(A);
  factorize(A);
}

Eigen::MatrixXd CholmodSolver::solve(const Eigen::MatrixXd& B) const {
  Eigen::MatrixXd X;
  solve(B, X);
  return X;
}

void CholmodSolver::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  if (!factorized_) throw UsageError("CholmodSolver::solve called before a successful factorize()");
  if (B.rows() != n_ || B.cols() < 1)
    throw UsageError("right-hand side has " + std::to_string(B.rows()) + " rows and " +
                     std::to_string(B.cols()) + " columns; the matrix has " + std::to_string(n_) +
                     " rows");
  Impl& m = *impl_;
  const double* rhs = B.data();
  if (m.permuted) {
    m.permuted_rhs.resize(B.rows(), B.cols());
    for (Eigen::Index j = 0; j < B.cols(); ++j) {
      for (int k = 0; k < n_; ++k) m.permuted_rhs(k, j) = B(m.perm[k], j);
    }
    rhs = m.permuted_rhs.data();
  }
  cholmod_dense b;
  std::memset(&b, 0, sizeof(b));
  b.nrow = static_cast<size_t>(B.rows());
  b.ncol = static_cast<size_t>(B.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = const_cast<double*>(rhs);
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  const int ok = cholmod_solve2(CHOLMOD_A, m.L, &b, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.common);
  if (!ok || !m.X) throw NumericalError("CHOLMOD solve failed (status " + std::to_string(m.common.status) + ")");
  X.resize(B.rows(), B.cols());
  const double* y = static_cast<const double*>(m.X->x);
  if (m.permuted) {
    for (Eigen::Index j = 0; j < B.cols(); ++j) {
      for (int k = 0; k < n_; ++k) X(m.perm[k], j) = y[j * n_ + k];
    }
  } else {
    std::memcpy(X.data(), y, sizeof(double) * static_cast<size_t>(X.size()));
  }
  if (!X.allFinite()) throw NumericalError("solution of the linear system is not finite");
}

double CholmodSolver::factor_nonzeros() const {
  if (!analyzed()) return 0.0;
  const cholmod_factor* L = impl_->L;
  if (L->is_super) {
    // Supernodal storage holds dense column blocks; count their entries.
    return static_cast<double>(L->xsize);
  }
  return static_cast<double>(L->nzmax);
}

bool CholmodSolver::is_supernodal() const { return analyzed() && impl_->L->is_super; }

}  // namespace gp
