// The one translation unit that instantiates Catch2's runner; every test
// executable links it so that the runner is compiled once. Before it runs,
// Eigen's blocking is fixed as in every stage, so that tests see the bits the
// stages compute on any CPU.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include "linalg/dense_blocking.h"

namespace {
const bool fixed_blocking = (gp::fix_dense_blocking(), true);
}  // namespace
