#include "linalg/dense_blocking.h"

#include <Eigen/Core>

namespace gp {

void fix_dense_blocking() {
  // The L1 size sets the depth of the blocks (and with it the grouping of the
  // sums); the others only their breadth, fixed too so that nothing is left
  // to the machine.
  Eigen::setCpuCacheSizes(32 * 1024, 1024 * 1024, 32 * 1024 * 1024);
}

}  // namespace gp
