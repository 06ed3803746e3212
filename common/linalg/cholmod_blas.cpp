// The dense kernels of CHOLMOD's supernodal factorization and solves, with
// the BLAS/LAPACK interface CHOLMOD calls (dgemm_, dsyrk_, dtrsm_, dtrsv_,
// dgemv_, dpotrf_), computed by Eigen's compiled kernels instead of the
// system BLAS. OpenBLAS picks its kernels at run time by CPU (blocking,
// AVX2 or AVX-512, FMA), so the same factorization gave different last bits
// on different machines, which the cloth simulation amplifies into a
// different fit (see README.md, "Reproducibility"). Eigen's kernels are fixed
// when this file is compiled, so every x86-64 CPU computes the same bits.
//
// The executable defines these symbols and exports them (see
// common/linalg/CMakeLists.txt), so the dynamic linker binds CHOLMOD's
// references to them ahead of the BLAS library CHOLMOD was linked against.
// Only the operations CHOLMOD uses are needed, but each routine implements
// its whole interface (every transpose and side flag), as a BLAS must.
#include "linalg/cholmod_blas.h"

#include <atomic>
#include <cmath>

#include <Eigen/Core>

namespace {

using Stride = Eigen::OuterStride<>;
using ConstMatrix = Eigen::Map<const Eigen::MatrixXd, 0, Stride>;
using Matrix = Eigen::Map<Eigen::MatrixXd, 0, Stride>;
using ConstVector = Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<>>;
using Vector = Eigen::Map<Eigen::VectorXd, 0, Eigen::InnerStride<>>;

std::atomic<long> g_calls{0};

bool is(const char* flag, char c) { return (*flag | 0x20) == (c | 0x20); }

// op(A) for a stored rows x cols matrix A.
ConstMatrix map(const double* a, int rows, int cols, int ld) { return ConstMatrix(a, rows, cols, Stride(ld)); }

// Lower-triangular Cholesky of the n by n block A (column-major, leading
// dimension lda) in place, column by column (left-looking). Returns 0, or the
// 1-based column whose pivot is not positive, as LAPACK's dpotrf.
int cholesky_lower(double* a, int n, int lda) {
  Matrix A(a, n, n, Stride(lda));
  for (int j = 0; j < n; ++j) {
    double d = A(j, j);
    if (j > 0) d -= A.row(j).head(j).squaredNorm();
    if (!(d > 0.0)) {
      A(j, j) = d;
      return j + 1;
    }
    const double l = std::sqrt(d);
    A(j, j) = l;
    const int below = n - j - 1;
    if (below > 0) {
      if (j > 0) A.col(j).tail(below).noalias() -= A.bottomLeftCorner(below, j) * A.row(j).head(j).transpose();
      A.col(j).tail(below) /= l;
    }
  }
  return 0;
}

}  // namespace

namespace gp {

long cholmod_blas_calls() { return g_calls.load(std::memory_order_relaxed); }

}  // namespace gp

extern "C" {

// C = alpha op(A) op(B) + beta C, C m by n, op(A) m by k.
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  if (*m <= 0 || *n <= 0) return;
  Matrix C(c, *m, *n, Stride(*ldc));
  if (*beta == 0.0)
    C.setZero();
  else if (*beta != 1.0)
    C *= *beta;
  if (*k <= 0 || *alpha == 0.0) return;
  const bool ta = !is(transa, 'N'), tb = !is(transb, 'N');
  const ConstMatrix A = ta ? map(a, *k, *m, *lda) : map(a, *m, *k, *lda);
  const ConstMatrix B = tb ? map(b, *n, *k, *ldb) : map(b, *k, *n, *ldb);
  if (!ta && !tb)
    C.noalias() += *alpha * A * B;
  else if (!ta && tb)
    C.noalias() += *alpha * A * B.transpose();
  else if (ta && !tb)
    C.noalias() += *alpha * A.transpose() * B;
  else
    C.noalias() += *alpha * A.transpose() * B.transpose();
}

// C = alpha op(A) op(A)^T + beta C on the uplo triangle of the n by n C.
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  if (*n <= 0) return;
  Matrix C(c, *n, *n, Stride(*ldc));
  const bool lower = is(uplo, 'L');
  if (*beta != 1.0) {
    for (int j = 0; j < *n; ++j) {
      auto column = lower ? C.col(j).tail(*n - j) : C.col(j).head(j + 1);
      if (*beta == 0.0)
        column.setZero();
      else
        column *= *beta;
    }
  }
  if (*k <= 0 || *alpha == 0.0) return;
  const bool t = !is(trans, 'N');
  const ConstMatrix A = t ? map(a, *k, *n, *lda) : map(a, *n, *k, *lda);
  if (lower) {
    if (t)
      C.triangularView<Eigen::Lower>() += *alpha * A.transpose() * A;
    else
      C.triangularView<Eigen::Lower>() += *alpha * A * A.transpose();
  } else {
    if (t)
      C.triangularView<Eigen::Upper>() += *alpha * A.transpose() * A;
    else
      C.triangularView<Eigen::Upper>() += *alpha * A * A.transpose();
  }
}

// B = alpha op(A)^-1 B (side L) or alpha B op(A)^-1 (side R), A triangular.
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  if (*m <= 0 || *n <= 0) return;
  Matrix B(b, *m, *n, Stride(*ldb));
  if (*alpha != 1.0) B *= *alpha;
  if (*alpha == 0.0) return;
  const bool left = is(side, 'L'), lower = is(uplo, 'L'), t = !is(transa, 'N'), unit = is(diag, 'U');
  const int na = left ? *m : *n;
  const ConstMatrix A = map(a, na, na, *lda);
  // op(A) is lower triangular when A is lower and not transposed, or upper and transposed.
  const bool op_lower = lower != t;
  auto solve = [&](const auto& T) {
    if (left)
      T.solveInPlace(B);
    else
      T.template solveInPlace<Eigen::OnTheRight>(B);
  };
  if (t) {
    const auto At = A.transpose();
    if (op_lower)
      unit ? solve(At.triangularView<Eigen::UnitLower>()) : solve(At.triangularView<Eigen::Lower>());
    else
      unit ? solve(At.triangularView<Eigen::UnitUpper>()) : solve(At.triangularView<Eigen::Upper>());
  } else {
    if (op_lower)
      unit ? solve(A.triangularView<Eigen::UnitLower>()) : solve(A.triangularView<Eigen::Lower>());
    else
      unit ? solve(A.triangularView<Eigen::UnitUpper>()) : solve(A.triangularView<Eigen::Upper>());
  }
}

// x = op(A)^-1 x, A n by n triangular.
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a, const int* lda,
            double* x, const int* incx) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  if (*n <= 0) return;
  const int one = 1;
  if (*incx == 1) {
    const double unit_alpha = 1.0;
    dtrsm_("L", uplo, trans, diag, n, &one, &unit_alpha, a, lda, x, n);
    return;
  }
  // A strided vector: solve on a copy.
  Eigen::VectorXd y(*n);
  const int step = *incx, start = step > 0 ? 0 : (1 - *n) * step;
  for (int i = 0; i < *n; ++i) y(i) = x[start + i * step];
  const double unit_alpha = 1.0;
  dtrsm_("L", uplo, trans, diag, n, &one, &unit_alpha, a, lda, y.data(), n);
  for (int i = 0; i < *n; ++i) x[start + i * step] = y(i);
}

// y = alpha op(A) x + beta y, A m by n.
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  const bool t = !is(trans, 'N');
  const int ny = t ? *n : *m, nx = t ? *m : *n;
  if (*m <= 0 || *n <= 0) return;
  // BLAS steps backwards through a vector with a negative increment.
  const double* x0 = *incx > 0 ? x : x + (1 - nx) * *incx;
  double* y0 = *incy > 0 ? y : y + (1 - ny) * *incy;
  Vector Y(y0, ny, Eigen::InnerStride<>(*incy));
  if (*beta == 0.0)
    Y.setZero();
  else if (*beta != 1.0)
    Y *= *beta;
  if (*alpha == 0.0) return;
  const ConstVector X(x0, nx, Eigen::InnerStride<>(*incx));
  const ConstMatrix A = map(a, *m, *n, *lda);
  if (t)
    Y.noalias() += *alpha * A.transpose() * X;
  else
    Y.noalias() += *alpha * A * X;
}

// Cholesky factorization of the n by n matrix A in place (uplo L: A = L L^T,
// U: A = U^T U). info: 0, or the 1-based column of the first non-positive pivot.
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  *info = 0;
  if (*n <= 0) return;
  if (is(uplo, 'L')) {
    *info = cholesky_lower(a, *n, *lda);
    return;
  }
  // Upper: U^T is the lower factor of A; factor the transposed copy.
  Matrix A(a, *n, *n, Stride(*lda));
  Eigen::MatrixXd lower = A.transpose();
  *info = cholesky_lower(lower.data(), *n, *n);
  A.triangularView<Eigen::Upper>() = lower.transpose();
}

}  // extern "C"
