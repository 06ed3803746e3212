// In-between frames (MotionRunOptions::schedule.frame_stride, FitOptions::frame_stride): solved to their
// static equilibrium, recorded, judged by the key poses' bounds, and reported by the verification.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include "adapt/fit_verification.h"
#include "adapt/garment_motion.h"
#include "hard_case_scene.h"
#include "motion_test_helpers.h"

using namespace gp::adapt;
namespace hc = gp::hard_cases;

namespace {

// A frame's figures as a judge sees them: n faces of unit rest area, all at `stretch`, and
// `above` of them at `high`.
KeyPoseResult figures(int transition, int frame, double stretch, int above, double high) {
  const int n = 100;
  KeyPoseResult k;
  k.key = transition + 1;
  k.transition = transition;
  k.frame = frame;
  k.pose = "frame " + std::to_string(frame);
  k.settled = true;
  Eigen::VectorXd s = Eigen::VectorXd::Constant(n, stretch);
  for (int f = 0; f < above; ++f) s(f) = high;
  stretch_figures(s, Eigen::VectorXd::Ones(n), 1.1, k);
  return k;
}

}  // namespace

TEST_CASE("an in-between frame over the bounds fails the verification, and is the one reported",
          "[adapt][verification][frames]") {
  MotionRunResult run;
  for (int key = 0; key < 2; ++key) {
    KeyPoseResult k = figures(-1, -1, 1.02, 0, 1.0);
    k.key = key;
    k.frame = -1;
    k.pose = key == 0 ? "apose" : "tpose";
    run.keys.push_back(k);
  }
  // Three frames of transition 0: the middle one has 5 % of its area at 1.3 (bounds: under 1 %
  // above 1.1, p99 at most 1.12); the others are within them.
  run.frames = {figures(0, 3, 1.03, 0, 1.0), figures(0, 6, 1.04, 5, 1.3), figures(0, 9, 1.06, 0, 1.0)};
  const FitVerification v = judge_run(run, 0.1);
  REQUIRE(v.poses.size() == 2);
  CHECK(v.poses[0].passed());
  CHECK(v.poses[1].passed());
  REQUIRE(v.transitions.size() == 1);
  const TransitionCheck& t = v.transitions[0];
  CHECK(t.from == "apose");
  CHECK(t.to == "tpose");
  REQUIRE(t.frames.size() == 3);
  CHECK(t.failed_frames() == 1);
  CHECK(t.worst == 1);
  CHECK(t.frames[1].failures.size() == 2);  // area above and p99
  CHECK(!v.passed());
  CHECK(failed_frames(v) == std::vector<int>{6});
  CHECK(failure_line(t).rfind("1 of 3 in-between frames from apose to tpose fail, the worst at frame 6 (frame 6): ", 0) == 0);
  // Only the worst frame keeps its per-face figures.
  CHECK(t.frames[1].figures.face_max_stretch.size() == 100);
  CHECK(t.frames[0].figures.face_max_stretch.size() == 0);
  const gp::OrderedJson j = to_json(t, "worst.ply");
  CHECK(j["frames_failed"] == 1);
  CHECK(j["verdict"] == "fail");
  CHECK(j["worst_frame"]["frame"] == 6);
  CHECK(j["worst_of_each"]["max_stretch"]["value"].get<double>() == Approx(1.3));
  CHECK(j["worst_of_each"]["mean_stretch"]["frame"] == 9);

  // Within the bounds everywhere, the same run passes.
  run.frames[1] = figures(0, 6, 1.04, 0, 1.0);
  CHECK(judge_run(run, 0.1).passed());
}

TEST_CASE("in-between frames are solved to equilibrium and recorded at the stride", "[adapt][body][static][frames]") {
  // A-pose -> T-pose in 12 frames on the generated shirt, the rest shape fixed (a verification).
  const hc::Loaded l = hc::load(hc::default_scene());
  const gp::MotionSpec motion = hc::motion_of(l.poses, {"apose", "tpose"}, 12);
  MotionRunOptions o = hc::run_options(600);
  o.settle.equilibrium = Equilibrium::static_solve;
  o.adaptation.enabled = false;
  o.schedule.frame_stride = 4;
  const MotionRunResult r = hc::run(l, motion, l.mesh.V, o);
  REQUIRE(r.keys.size() == 2);
  // Frames 4 and 8; frame 12 is the key pose.
  REQUIRE(r.frames.size() == 2);
  for (size_t k = 0; k < r.frames.size(); ++k) {
    const KeyPoseResult& f = r.frames[k];
    INFO("frame " << f.frame << " (" << f.pose << "): " << f.newton_iterations << " Newton iterations, residual "
                  << f.force_residual << ", max stretch " << f.max_stretch);
    CHECK(f.frame == 4 * static_cast<int>(k + 1));
    CHECK(f.transition == 0);
    CHECK(f.key == 1);
    CHECK(f.t == Approx(f.frame / 12.0));
    CHECK(f.solved_static);
    CHECK(f.settled);
    CHECK(f.force_residual < o.settle.statics.tolerance);
    CHECK(f.deepest_penetration == 0.0);
    CHECK(f.V_draped.rows() == l.mesh.V.rows());
  }
  const FitVerification v = judge_run(r, o.adaptation.adapter.delta);
  REQUIRE(v.transitions.size() == 1);
  CHECK(v.transitions[0].frames.size() == 2);
  // Observed frames leave the motion as it is: the key poses are the same bits without them.
  MotionRunOptions unobserved = o;
  unobserved.schedule.frame_stride = 0;
  const MotionRunResult u = hc::run(l, motion, l.mesh.V, unobserved);
  CHECK(u.frames.empty());
  REQUIRE(u.keys.size() == 2);
  for (size_t k = 0; k < 2; ++k) CHECK(u.keys[k].V_draped == r.keys[k].V_draped);
  // The frame between the poses is not one of them: its drape differs from both key poses'.
  CHECK((r.frames[0].V_draped - r.keys[0].V_draped).rowwise().norm().maxCoeff() > 1e-3);
  CHECK((r.frames[0].V_draped - r.keys[1].V_draped).rowwise().norm().maxCoeff() > 1e-3);

  // An adaptation frame settles and adapts there as a key pose does.
  MotionRunOptions a = hc::run_options(600);
  a.settle.equilibrium = Equilibrium::static_solve;
  a.adaptation.frames = {6};
  const MotionRunResult ra = hc::run(l, motion, l.mesh.V, a);
  REQUIRE(ra.frames.size() == 1);
  CHECK(ra.frames[0].frame == 6);
  CHECK(ra.frames[0].settled);
  // A key pose is no adaptation frame.
  a.adaptation.frames = {12};
  CHECK_THROWS_AS(hc::run(l, motion, l.mesh.V, a), gp::UsageError);
  o.schedule.frame_stride = -1;
  CHECK_THROWS_AS(hc::run(l, motion, l.mesh.V, o), gp::UsageError);
}
