#include <catch2/catch.hpp>

#include <Eigen/Core>

#include "linalg/dense_blocking.h"

// Eigen's dense products depend on the cache sizes it blocks for; with them
// fixed, the product of a deep pair of matrices is the same whatever the CPU.

namespace {

// A 60 by 2000 by 60 product: deep enough to be cut into several blocks.
Eigen::MatrixXd deep_product() {
  Eigen::MatrixXd A(60, 2000), B(2000, 60);
  for (Eigen::Index j = 0; j < A.cols(); ++j)
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      A(i, j) = std::sin(0.37 * static_cast<double>(i) + 1.3 * static_cast<double>(j));
      B(j, i) = std::cos(0.91 * static_cast<double>(i) - 0.7 * static_cast<double>(j));
    }
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(60, 60);
  C.noalias() += A * B;
  return C;
}

}  // namespace

TEST_CASE("fixed cache sizes make Eigen's products the same bits on any CPU", "[linalg]") {
  gp::fix_dense_blocking();
  CHECK(Eigen::l1CacheSize() == 32 * 1024);
  CHECK(Eigen::l2CacheSize() == 1024 * 1024);
  CHECK(Eigen::l3CacheSize() == 32 * 1024 * 1024);
  const Eigen::MatrixXd fixed = deep_product();

  // A CPU with a 48 KiB L1 data cache groups the sums otherwise: the last
  // bits differ (this is what the fixed sizes prevent) ...
  Eigen::setCpuCacheSizes(48 * 1024, 2 * 1024 * 1024, 64 * 1024 * 1024);
  const Eigen::MatrixXd larger_l1 = deep_product();
  CHECK((larger_l1.array() != fixed.array()).count() > 0);
  CHECK((larger_l1 - fixed).cwiseAbs().maxCoeff() < 1e-11);

  // ... and fixing them again gives the first bits back, as on a 32 KiB CPU.
  gp::fix_dense_blocking();
  CHECK((deep_product().array() == fixed.array()).all());
}
