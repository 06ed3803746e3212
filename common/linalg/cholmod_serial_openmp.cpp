// The OpenMP entry points of CHOLMOD's supernodal factorization, serial: every
// parallel region runs on the calling thread, as if CHOLMOD had been compiled
// without OpenMP.
//
// Debian's CHOLMOD 3 compiles t_cholmod_super_numeric.c with OpenMP. Its loops
// there (clearing and filling each supernode, the relative maps, the
// descendants' assembly) ask for teams of CHOLMOD_OMP_NUM_THREADS = 4 in a
// num_threads clause that overrides omp_set_num_threads, and the if clauses
// of those pragmas only lower that to one thread: libgomp still builds and
// ends a team around every one of them, once or more per supernode and per
// descendant update. With one thread allowed (omp_set_max_active_levels(0))
// that bookkeeping was still about a third of the factorization time, and
// with more, three extra threads woke thousands of times per factorization
// for loops of a few hundred entries.
//
// The project links CHOLMOD statically (cmake/FindCHOLMOD.cmake) and defines
// here the only three OpenMP symbols that library references (checked by
// linalg's tests): GCC outlines each region into fn(data), and an outlined
// `omp for` with the static schedule gives thread omp_get_thread_num() of
// omp_get_num_threads() its share, so fn(data) with one thread of one runs
// the whole loop, in order. These loops only copy or scatter values, so the
// factor is bit for bit the one the team computed. The symbols are not
// exported from the executables (see common/linalg/CMakeLists.txt): a shared
// library that uses OpenMP still binds to the real runtime.
#include "linalg/cholmod_serial_openmp.h"

#include <atomic>

namespace {

std::atomic<long> g_regions{0};

}  // namespace

namespace gp {

long cholmod_openmp_regions() { return g_regions.load(std::memory_order_relaxed); }

}  // namespace gp

extern "C" {

void GOMP_parallel(void (*fn)(void*), void* data, unsigned /*num_threads*/, unsigned /*flags*/) {
  g_regions.fetch_add(1, std::memory_order_relaxed);
  fn(data);
}

int omp_get_num_threads() { return 1; }

int omp_get_thread_num() { return 0; }

}
