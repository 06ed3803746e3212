#include "adapt/motion_progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gp::adapt {

MotionProgressLine::MotionProgressLine(const MotionRunOptions& options)
    : substeps_(std::max(1, options.schedule.substeps)), settle_cap_(std::max(0, options.settle.max_steps)) {}

double MotionProgressLine::seconds_left(const MotionProgress& p, double elapsed) const {
  if (p.steps <= 0) return -1.0;
  double settle_mean = 0.5 * settle_cap_;
  if (!settled_steps_.empty()) {
    double sum = 0.0;
    for (int s : settled_steps_) sum += s;
    settle_mean = sum / static_cast<double>(settled_steps_.size());
  }
  const double frames_left = p.frames > p.frame + 1 ? static_cast<double>(p.frames - p.frame - 1) : 0.0;
  // Key poses still to settle: the current one counts with what remains of it.
  const int keys_after = std::max(0, p.keys - p.key - 1);
  double settle_left = keys_after * settle_mean;
  if (!p.key_done) settle_left += std::max(0.0, settle_mean - p.settle_steps);
  const double steps_left = frames_left * substeps_ + settle_left;
  return steps_left * elapsed / static_cast<double>(p.steps);
}

std::string MotionProgressLine::line(const MotionProgress& p, double elapsed) {
  if (p.key_done) settled_steps_.push_back(p.settle_steps);
  char what[96];
  if (p.key_done)
    std::snprintf(what, sizeof(what), "settled after %d steps", p.settle_steps);
  else if (p.settle_steps > 0)
    std::snprintf(what, sizeof(what), "settling, %d steps", p.settle_steps);
  else
    std::snprintf(what, sizeof(what), "moving, frame %zu of %zu", p.frame, p.frames > 0 ? p.frames - 1 : 0);
  char out[256];
  const double left = seconds_left(p, elapsed);
  std::snprintf(out, sizeof(out), "pose %d/%d (%s): step %ld, max stretch %.3f, %s elapsed, %s%s", p.key + 1, p.keys,
                what, p.steps, p.max_stretch, format_duration(elapsed).c_str(), left < 0.0 ? "" : "about ",
                left < 0.0 ? "time left unknown" : (format_duration(left) + " left").c_str());
  return out;
}

std::string format_duration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char b[48];
  if (s < 60)
    std::snprintf(b, sizeof(b), "%ld s", s);
  else if (s < 3600)
    std::snprintf(b, sizeof(b), "%ld min %02ld s", s / 60, s % 60);
  else
    std::snprintf(b, sizeof(b), "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  return b;
}

}  // namespace gp::adapt
