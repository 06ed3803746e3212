#pragma once
// CHOLMOD's dense kernels (BLAS and LAPACK's dpotrf) computed with the same
// bits on every CPU: see cholmod_blas.cpp.

namespace gp {

// How often CHOLMOD has called the project's dense kernels in this process:
// lets tests confirm that CHOLMOD's supernodal factorization and solves use
// them rather than the system BLAS.
long cholmod_blas_calls();

}  // namespace gp
