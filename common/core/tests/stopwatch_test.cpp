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

TEST_CASE("laps split the time between them", "[core]") {
  const gp::Clock::time_point start = gp::Clock::now();
  gp::LapTimer timer;
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const double first = timer.lap();
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const double second = timer.lap();
  CHECK(first >= 0.010);
  CHECK(second >= 0.010);
  // Consecutive laps do not overlap: together no longer than the whole.
  CHECK(first + second <= gp::seconds_since(start));
}
