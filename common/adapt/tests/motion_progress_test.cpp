#include <catch2/catch.hpp>

#include "adapt/motion_progress.h"

using gp::adapt::MotionProgress;

TEST_CASE("the progress line counts the steps left at the pace so far", "[adapt][progress]") {
  gp::adapt::MotionRunOptions options;
  options.schedule.substeps = 1;
  options.settle.max_steps = 400;
  gp::adapt::MotionProgressLine progress(options);
  // Three key poses, 60 frames between each: frames 0, 60, 120 are the keys.
  MotionProgress p;
  p.keys = 3;
  p.frames = 121;
  CHECK(progress.seconds_left(p, 0.0) < 0.0);  // no step yet: unknown
  // The first key pose settled after 100 steps in 10 s.
  p.key = 0;
  p.steps = 100;
  p.settle_steps = 100;
  p.key_done = true;
  const std::string first = progress.line(p, 10.0);
  CHECK(first.find("pose 1/3") != std::string::npos);
  CHECK(first.find("settled after 100 steps") != std::string::npos);
  // Moving towards pose 2, frame 30 of 120: 90 frames and two settlings of
  // 100 steps left, at 0.1 s per step.
  p.key = 1;
  p.frame = 30;
  p.steps = 130;
  p.settle_steps = 0;
  p.key_done = false;
  p.max_stretch = 1.0876;
  CHECK(progress.seconds_left(p, 13.0) == Approx(0.1 * (90 + 200)));
  const std::string moving = progress.line(p, 13.0);
  CHECK(moving.find("pose 2/3 (moving, frame 30 of 120): step 130, max stretch 1.088, 13 s elapsed, about 29 s left") !=
        std::string::npos);
  // Settling at the last pose past the mean: nothing left but what is unknown.
  p.key = 2;
  p.frame = 120;
  p.steps = 400;
  p.settle_steps = 150;
  CHECK(progress.seconds_left(p, 40.0) == Approx(0.0));
}

TEST_CASE("durations read in seconds, minutes or hours", "[adapt][progress]") {
  CHECK(gp::adapt::format_duration(0.4) == "0 s");
  CHECK(gp::adapt::format_duration(59.4) == "59 s");
  CHECK(gp::adapt::format_duration(185) == "3 min 05 s");
  CHECK(gp::adapt::format_duration(3720) == "1 h 02 min");
  CHECK(gp::adapt::format_duration(-5) == "0 s");
}
