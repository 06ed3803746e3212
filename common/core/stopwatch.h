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

// Consecutive phases timed one after another: each lap() returns the seconds
// since the previous lap (or since construction).
class LapTimer {
 public:
  LapTimer() : last_(Clock::now()) {}
  double lap() {
    const Clock::time_point now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return seconds;
  }

 private:
  Clock::time_point last_;
};

}  // namespace gp
