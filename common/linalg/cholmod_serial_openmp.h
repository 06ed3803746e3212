#pragma once
// CHOLMOD's OpenMP parallel regions run serially on the calling thread: cholmod_serial_openmp.cpp.

namespace gp {

// How many of CHOLMOD's OpenMP parallel regions this process has run (on the calling thread), for
// tests to confirm that CHOLMOD binds to the serial entry points rather than an OpenMP runtime.
long cholmod_openmp_regions();

}  // namespace gp
