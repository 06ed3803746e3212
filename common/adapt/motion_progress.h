#pragma once
// The progress line of a motion run: key pose k of n, step, the cloth's
// largest stretch now, time elapsed and an estimate of the time left.
//
// The estimate counts the steps still to come, the interpolation frames left
// times the substeps plus, for every key pose not yet settled, the mean
// settling steps of the key poses settled so far (the settle cap halved
// before the first), and charges them at the mean time per step so far.
#include <string>
#include <vector>

#include "adapt/garment_motion.h"

namespace gp::adapt {

class MotionProgressLine {
 public:
  explicit MotionProgressLine(const MotionRunOptions& options);
  // The line for `p`, `elapsed` seconds after the run started, e.g.
  // "pose 3/5 (settling 240 steps): step 1180, max stretch 1.102, 41 s elapsed, about 30 s left".
  std::string line(const MotionProgress& p, double elapsed);
  // Estimated seconds left (negative before the first step).
  double seconds_left(const MotionProgress& p, double elapsed) const;

 private:
  int substeps_;
  int settle_cap_;
  std::vector<int> settled_steps_;  // settling steps of each key pose recorded so far
};

// "42 s", "3 min 05 s", "1 h 02 min".
std::string format_duration(double seconds);

}  // namespace gp::adapt
