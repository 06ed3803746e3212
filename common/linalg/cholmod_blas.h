#pragma once
// CHOLMOD's dense kernels (BLAS, LAPACK's dpotrf), the same bits on every CPU: cholmod_blas.cpp.

namespace gp {

// How often CHOLMOD has called the project's dense kernels in this process, for tests to confirm
// that its supernodal factorization and solves use them rather than the system BLAS.
long cholmod_blas_calls();

}  // namespace gp
