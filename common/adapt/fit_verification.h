#pragma once
// The honest figure of a fit: a rest shape (or a sewn pattern's flat pieces)
// simulated afresh, from the garment as designed, through the whole motion
// with no adaptation, and judged at every key pose. The adaptation's own
// figures cannot show a fit: it clips every stretch above 1 + delta, so its
// "max stretch 1.1" holds by construction; this pass measures whether the
// final rest shape still fits the earlier poses.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapt/garment_motion.h"
#include "cloth/cloth_energy.h"
#include "spec/json_file.h"

namespace gp::adapt {

struct PoseCheck {
  KeyPoseResult figures;              // drape, stretch and penetration figures of the key pose
  std::vector<std::string> failures;  // one sentence per bound exceeded (empty: passed)
  double area_fraction_torn = 0.0;    // rest-area fraction stretched beyond the criteria's tear_stretch
  bool passed() const { return failures.empty(); }
};

// The in-between frames of one transition (keys[transition] -> keys[transition + 1]) that the
// run solved to equilibrium (MotionRunOptions::schedule.frame_stride), each judged by the key poses' bounds.
struct TransitionCheck {
  int transition = 0;
  std::string from, to;               // the key poses' names
  std::vector<PoseCheck> frames;      // in order; only the worst keeps its drape and per-face figures
  // Index into frames of the worst: the most bounds exceeded, then the largest area above
  // 1 + delta, then the largest p99 stretch. -1: no frames.
  int worst = -1;
  int failed_frames() const;
  bool passed() const { return failed_frames() == 0; }
};

struct FitVerification {
  std::vector<PoseCheck> poses;       // one per key pose of the motion
  std::vector<TransitionCheck> transitions;  // those with frames solved (in order); empty: none were
  long steps = 0;
  long rejected_steps = 0;
  double seconds = 0.0;               // wall time of the simulation
  bool passed() const;
};

// Simulates the garment through `motion` with the given rest triangles (one
// per face of F) and no adaptation, starting at V_start (#V by 3: the garment
// as designed, at the comfort offset), and checks every key pose. `options`
// are the fit's (time step, settling, contacts, threads); adapt and
// rest_triangles are set here. `progress` receives the run's progress, its
// lines prefixed with "verification: ". Throws as run_garment_motion.
FitVerification verify_fit(PoseInterpolator& interpolator, const MotionSpec& motion,
                           const Eigen::MatrixXd& V_start, const Eigen::MatrixXi& F, const GarmentFile& garment,
                           const std::vector<cloth::TriangleRest>& rest_triangles, MotionRunOptions options,
                           const FitCriteria& criteria = {}, const ProgressCallback& progress = {});

// The checks of a run without adaptation (its key poses are already a fresh
// simulation of its rest shape); seconds is left 0.
FitVerification judge_run(const MotionRunResult& run, double delta, const FitCriteria& criteria = {});

// The in-between frames over the bounds, as frame indices of the motion (ascending): where a
// further fit cycle adapts (MotionRunOptions::adaptation.frames).
std::vector<int> failed_frames(const FitVerification& v);

// A failing transition in one line: how many of its frames fail, and the worst frame's first
// failure ("2 of 5 in-between frames from apose to tpose fail, the worst at frame 6 (...): ...").
std::string failure_line(const TransitionCheck& check);

// A transition's check as the stages report it: its frames' count, how many failed, the worst
// frame's check (to_json of a PoseCheck, with its drape's file `mesh`, "" for none) and the worst
// value of each figure over the frames.
OrderedJson to_json(const TransitionCheck& check, const std::string& mesh);

// A key pose's check as the stages report it: key, pose, `mesh` (the drape's
// file), verdict, failures, stretch figures, penetration, crossings and
// settling.
OrderedJson to_json(const PoseCheck& check, const std::string& mesh);

// The rest triangles of a rest shape (#V by 3, same connectivity as F), with
// the material's warp direction, as the simulator builds them.
std::vector<cloth::TriangleRest> rest_triangles_of(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F);

}  // namespace gp::adapt
