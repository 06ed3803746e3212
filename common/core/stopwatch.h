#pragma once
// Wall-clock timing of a pipeline phase, for timing.json (never for results).
#include <chrono>

namespace gp {

// Monotonic: unaffected by changes of the system clock.
using Clock = std::chrono::steady_clock;

// Seconds elapsed since `start`.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace gp
