#pragma once
// The simulate-adapt run: a garment simulated on a body moving through a
// motion's key poses, its rest shape adapted while the cloth settles at each
// key pose (Wolff et al. 2023, sec. 5, there also while the body moves), or
// kept fixed (no_adapt) to evaluate a design or a sewn pattern.
//
// Per interpolation frame the body comes from the pose interpolator; pinned
// boundary vertices follow their body binding (garment_file.h) as hard
// constraints, kept clear of the body (pin_targets.h);
// body collisions push the cloth out to the garment's comfort offset. At
// every key pose the body stops and the cloth settles until it is slow, its
// largest stretch steady and (adapting) its rest area a fixed point, or a
// step cap; then the key pose's drape and figures are recorded.
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "adapt/body_contact.h"
#include "adapt/key_pose.h"
#include "adapt/pin_targets.h"
#include "adapt/rest_adapter.h"
#include "cloth/cloth_simulator.h"
#include "cloth/static_solve.h"
#include "collision/body_collider.h"
#include "collision/contact_surface.h"
#include "collision/continuous_contact.h"
#include "collision/crossings.h"
#include "garment/garment_file.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"

namespace gp::adapt {

// How a key pose reaches its rest state (adapt/README.md, "The static solve").
//  - static_solve: the equilibrium solved directly (cloth/static_solve.h); with adaptation, the rest
//    shape is adapted at each equilibrium and the equilibrium solved again until the rest area is a
//    fixed point (SettleOptions::fixed_point_area_change).
//  - dynamic: damped implicit Euler steps until the cloth is slow (SettleOptions), the way
//    before the static solve, kept for comparison and for the dynamic benchmark.
// The transitions between key poses are stepped dynamically either way.
enum class Equilibrium { static_solve, dynamic };
// Each way with its name in reports and options ("static", "dynamic").
const std::vector<std::pair<Equilibrium, const char*>>& equilibrium_names();

// The static solve at a key pose (Equilibrium::static_solve): the solver's options, max_iterations
// the cap on all its Newton iterations at one key pose, adaptations included.
struct StaticSettleOptions : cloth::StaticSolveOptions {
  StaticSettleOptions() { max_iterations = 600; }
  // With adaptation: the rest shape is adapted every adaptation.every iterations once no vertex moved
  // more than this over the last of them [m] (the dynamic settling's adaptation.speed), or the largest
  // stretch changed by less than settle.stretch_change over them: the stretch of cloth still on its way is
  // transient. The force residual is no gate: a few vertices pressed into a crease hold it high
  // until the adaptation relieves them.
  double adapt_displacement = 0.002;
  // Held cloth: stretched beyond held_stretch without the largest stretch falling by
  // held_improvement (relative) for this many iterations (the dynamic settling's held_steps).
  int held_iterations = 64;
};

// The frames of a run and the threads that step them (MotionRunOptions::schedule).
struct ScheduleOptions {
  int substeps = 1;  // simulation steps per interpolation frame (paper: one)
  // In-between frames solved to their static equilibrium and recorded (MotionRunResult::frames):
  // every frame_stride-th frame of each transition (its key poses excepted), 0: none. The cloth
  // goes on from that equilibrium, at rest, so that the frame's figures and the rest of the
  // transition carry no inertia: the motion is judged as a sequence of held poses, the way a
  // garment has to allow each position of the movement (Wolff et al. 2023, sec. 1). The
  // verification sets it (FitOptions::frame_stride).
  int frame_stride = 0;
  // Steps between an adaptation's positions and its application, so that it
  // can run beside those steps on a second thread; 0 applies it at once (the
  // paper). Cut to adaptation.every - 1. The adaptation at the end of each key
  // pose is always immediate (its figures are measured with it).
  int adaptation_lag = 2;
  // 1: every phase in turn. 2 or more: the body stages (interpolation, pin
  // targets, collision tree) are prepared one step ahead, the lagging
  // adaptations computed and half the body contacts queried on a second
  // thread. The work and its inputs are the same, so are the outputs.
  int threads = 1;
};

// How a key pose comes to rest, and when it counts as settled or held (MotionRunOptions::settle).
struct SettleOptions {
  // Dynamic by default until the static solve is faster through a whole fit (adapt/README.md, "The
  // static solve": today it needs as many adaptations, and so as much work).
  Equilibrium equilibrium = Equilibrium::dynamic;
  StaticSettleOptions statics;  // the static solve at a key pose
  double speed = 0.05;  // m/s: largest net vertex speed over a settle check (adaptation.every steps) of a settled cloth
  double stretch_change = 1e-3;  // largest change of the largest stretch between settle checks
  int max_steps = 1000;          // cap on the settling steps at each key pose
  // A key pose the body holds fails fast: once some cloth is stretched beyond
  // held_stretch and the largest stretch has not fallen by held_improvement
  // (relative) for held_steps settling steps, the settling stops and the pose
  // is reported held, with the patches and the body's room there
  // (KeyPoseResult::held_cloth); the run stops after it. 0: settle to the cap.
  int held_steps = 160;
  double held_stretch = 1.5;  // beyond this cloth tears (as FitCriteria::tear_stretch)
  double held_improvement = 0.01;
  // Damping while settling, as a fraction of the material's: the static
  // equilibrium does not depend on it, the way there does (a hugging garment
  // gets there sooner with less, a loose skirt swings).
  double damping = 1.0;
  int fixed_point_steps = 100;  // with adaptation: window of the fixed-point test [steps]
  double fixed_point_area_change = 1e-3;  // largest relative rest-area change over that window
};

// When the rest shape grows, and by which rule (MotionRunOptions::adaptation).
struct AdaptationOptions {
  bool enabled = true;  // false: evaluate the fixed rest shape (--no-adapt)
  // Frames (indices into motion_frames) that the adaptation treats as key poses: settled, adapted
  // there, and recorded in MotionRunResult::frames. A fit cycle adapts at the in-between frames that
  // its verification found over the bounds.
  std::vector<int> frames;
  // Adapt only while the cloth settles at a key pose (the body still), not
  // while the body moves: stretch in a transition is mostly transient (the
  // cloth lagging behind the body), and growing the rest shape after it made
  // the fit depend on the time step and left 1.40 times the area against 1.22.
  // true: the paper's adaptation every `every` steps throughout.
  bool during_transitions = false;
  int every = 8;  // steps between adaptations (paper value)
  // m/s: at a key pose, adaptation starts once the cloth's largest net vertex
  // speed over a settle check falls below this, and goes on to the end of the
  // pose. The stretch of a cloth still swinging into place is transient; grown
  // after, the rest shape depended on the settling damping (x1.05 against
  // x1.12 with a hundredth of it on the generated shirt).
  double speed = 0.1;
  // A run whose rest area exceeds this multiple of the design's fails
  // (NumericalError): growth that far is a runaway (a snagged cloth whose
  // stretch the growth cannot relieve), never a fit.
  double max_area_growth = 3.0;
  AdaptOptions adapter;  // one adaptation: stretch limit, clipping, stitching (rest_adapter.h)
};

// Options of a motion run, by concern. Defaults are the project's; the
// measurements behind them are in common/adapt/README.md.
struct MotionRunOptions {
  ScheduleOptions schedule;       // frames, substeps, recorded frames, threads
  SettleOptions settle;           // key poses: static or damped, settled, held
  BodyContactOptions contact;     // how the cloth meets the body (body_contact.h)
  AdaptationOptions adaptation;   // when the rest shape grows, and its rule
  cloth::SimulatorOptions solver;  // time step, strategy, tolerances
  // When non-empty (one per garment face): rest triangles used instead of the
  // rest shape's, e.g. a sewn pattern's flat pieces. Requires adaptation off.
  std::vector<cloth::TriangleRest> rest_triangles;
  // When non-empty (#V by 3): the rest shape the run starts from instead of the
  // design, which stays the reference of the stitching (a later fit cycle).
  Eigen::MatrixXd initial_rest;
};

struct MotionRunTimes {               // wall seconds
  double forces_assembly = 0.0;
  double factorization = 0.0;
  double solve = 0.0;
  double collisions = 0.0;            // responses and tree rebuilds
  double adaptation = 0.0;
  // Interpolation, normals, pin targets (on the worker with threads > 1; the
  // targets' clearance from the body on the stepping thread).
  double body = 0.0;
  double setup = 0.0;                 // before the first step: culling, collision tree, simulator, ARAP factor, initial distances
  // With threads > 1: time the stepping thread waited for the worker. The
  // phases above are then each thread's own time, and they overlap.
  double waiting = 0.0;
  double total = 0.0;
};

struct ArapTotals {                   // the stitchings of a run
  long iterations = 0;
  int max_iterations = 0;
  double max_residual = 0.0;
  bool converged = true;              // every stitching reached its tolerance
};

struct MotionRunResult {
  Eigen::MatrixXd V_rest;             // final rest shape (same connectivity as the garment)
  std::vector<KeyPoseResult> keys;    // up to the first held one (KeyPoseResult::held), where the run stops
  // The in-between frames solved to equilibrium (MotionRunOptions::schedule.frame_stride, adaptation.frames), in
  // order; each KeyPoseResult's key is the transition's target key, frame its frame index.
  std::vector<KeyPoseResult> frames;
  int held_key = -1;                  // index into keys of the pose the body holds, -1: none
  long steps = 0;
  int adaptations = 0;                // adaptations that changed the rest shape
  ArapTotals arap;
  bool all_settled = true;
  size_t culled_body_faces = 0;       // body faces kept for collisions
  double initial_min_distance = 0.0;  // m, smallest signed distance of the design garment to the body
  // The static solves at key poses (Equilibrium::static_solve): Newton iterations and line-search
  // trials, and their time [s] (also counted in `times` by phase).
  long newton_iterations = 0;
  long line_search_trials = 0;
  double static_seconds = 0.0;
  cloth::SolverCounters solver;       // steps, rejections, folds, factorizations, CG, contact constraints
  collision::CollisionStats collisions;  // body queries, projections, pinches, creases
  collision::CrossingReport initial_crossings;  // the design garment against the contact surface in the first frame
  collision::ContactSurface contact_surface;  // the body and its hand hulls (contact_surface.h)
  bool continuous_contact = false;    // the intersection-free contact was active
  collision::ContinuousContactStats contact;
  PinClearanceStats pins;             // pin targets moved out to their clearance (BodyContactOptions::pin_clearance)
  MotionRunTimes times;
};

// A progress report of a motion run: where it is, and a line saying so.
// Sent every 5 interpolation frames, every 40 settling steps and at the end of
// every key pose.
struct MotionProgress {
  std::string message;       // one line with the figures of the moment
  int key = 0;               // the key pose being approached or settled (0-based)
  int keys = 0;              // key poses in the motion
  size_t frame = 0;          // interpolation frames done
  size_t frames = 0;         // interpolation frames in all (the first is the start pose)
  long steps = 0;            // simulation steps so far
  int settle_steps = 0;      // settling steps at the current key pose (0 while moving)
  bool key_done = false;     // the key pose's figures were recorded
  double max_stretch = 0.0;  // largest principal stretch of the cloth now
};
using ProgressCallback = std::function<void(const MotionProgress&)>;

// The adaptation lag a run applies: schedule.adaptation_lag cut to
// adaptation.every - 1 (and to 0 from below).
int applied_adaptation_lag(const MotionRunOptions& options);

// A motion run: the garment simulated through the motion's frames, settled
// and recorded at every key pose, its rest shape adapted while settling.
// Construction sets up the body, the collider, the cloth and the stitching;
// run() steps through the motion once.
class GarmentMotion {
 public:
  // V_garment/F_garment: the garment's design rest shape (also its initial
  // drape, on the first key pose). Throws UsageError for bad options,
  // GeometryError for a garment whose loops name vertices out of range.
  GarmentMotion(PoseInterpolator& interpolator, const MotionSpec& motion, const Eigen::MatrixXd& V_garment,
                const Eigen::MatrixXi& F_garment, const GarmentFile& garment, const MotionRunOptions& options);
  ~GarmentMotion();
  GarmentMotion(const GarmentMotion&) = delete;
  GarmentMotion& operator=(const GarmentMotion&) = delete;
  // Throws NumericalError when a step cannot be recovered. Call once.
  MotionRunResult run(const ProgressCallback& progress = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Runs the motion. V_garment/F_garment: the garment's design rest shape (also
// its initial drape, on the first key pose). Throws GeometryError for a garment
// whose loops name vertices out of range, NumericalError when a step cannot be
// recovered.
MotionRunResult run_garment_motion(PoseInterpolator& interpolator, const MotionSpec& motion,
                                   const Eigen::MatrixXd& V_garment, const Eigen::MatrixXi& F_garment,
                                   const GarmentFile& garment, const MotionRunOptions& options,
                                   const ProgressCallback& progress = {});

}  // namespace gp::adapt
