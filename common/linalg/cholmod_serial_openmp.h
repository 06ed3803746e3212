#pragma once
// CHOLMOD's OpenMP parallel regions run serially on the calling thread: see
// cholmod_serial_openmp.cpp.

namespace gp {

// How many of CHOLMOD's OpenMP parallel regions this process has run (on the
// calling thread): lets tests confirm that CHOLMOD's supernodal factorization
// binds to the serial entry points rather than to an OpenMP runtime.
long cholmod_openmp_regions();

}  // namespace gp
