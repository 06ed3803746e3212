#include <catch2/catch.hpp>

#include <thread>

#include "core/stopwatch.h"

TEST_CASE("seconds_since counts forward from its start", "[core]") {
  const gp::Clock::time_point start = gp::Clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double first = gp::seconds_since(start);
  // A sleep lasts at least what it asked for; the upper side is left open, as
  // a busy machine may deschedule the thread for any time.
  CHECK(first >= 0.020);
  CHECK(gp::seconds_since(start) >= first);
  CHECK(gp::seconds_since(gp::Clock::now()) < first);
}
