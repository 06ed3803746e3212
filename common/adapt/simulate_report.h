#pragma once
// What simulate-adapt writes besides its meshes: report.json
// (simulate-adapt-report/1, written last; the sewn-fit check and the fit
// report read it back), timing.json (timing/1: times and work counters, which
// differ between runs and machines), the names of the drape files, and the
// messages of a run that ends in a check's verdict.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "adapt/fit_inputs.h"
#include "adapt/garment_fit.h"
#include "adapt/open_pose.h"
#include "interp/pose_interpolator.h"
#include "io/mesh.h"
#include "spec/json_file.h"

namespace gp::adapt {

// "<prefix>_<key, two digits>_<pose>.ply", e.g. draped_01_tpose.ply.
std::string drape_file_name(const std::string& prefix, const KeyPoseResult& k);

// The drape file of a verification's key pose: its own verified_* file, or,
// for a run without adaptation (whose drapes are the fresh simulation), the
// run's draped_* file.
std::string verified_drape_file_name(const KeyPoseResult& k, bool adapted);

// The drape file of a transition's worst in-between frame in a verification:
// "worst_frame_<transition, two digits>_<from>_to_<to>.ply".
std::string worst_frame_file_name(const TransitionCheck& t);

// The meshes of a fit, by file name, in the order they are written:
// rest.ply (the adapted rest shape), the run's drape at every key pose and,
// after an adaptation, the verification's; each drape with its largest
// principal stretch per face (face field max_stretch), and the worst
// in-between frame of each transition the verification solved. F: the
// garment's faces.
std::vector<std::pair<std::string, Mesh>> fit_meshes(const FitResult& fit, const Eigen::MatrixXi& F, bool adapted);

// The key pose the body holds (fit.run.held_key), or null: where the cloth is
// held, and the least opening of the pose that frees it (choose_opening with
// `opening` and the run's contact surface options), for make fit's fallback.
OrderedJson held_json(const FitResult& fit, const MotionSpec& motion, PoseInterpolator& interpolator,
                      const GarmentFile& garment, const MotionRunOptions& options, OpeningOptions opening);

// Where the run came from, as the report records it.
struct SimulateReportInputs {
  std::string poses_path;
  std::string motion_path;
  std::string garment_path;
  int threads = 1;  // --threads
};

// report.json: the options (the inputs, the fit's options as FitOptionFields
// writes them, the effective motion, material and comfort offset), the other
// body's carry, counts, hand hulls, every key pose, the cycles, `held`
// (held_json), the verification and the run's figures.
OrderedJson simulate_report(const SimulateReportInputs& where, const FitInputs& in, const FitOptions& options,
                            const FitResult& fit, const OrderedJson& held);

// timing.json: steps per second, milliseconds per step by phase, work
// counters, the reasons of rejected steps, and the whole stage's `total_s`.
OrderedJson simulate_timing(const FitResult& fit, int threads, int workers, double total_s);

// Warnings of a finished fit: a further cycle that failed, a garment that
// starts through the body with the continuous contact asked for, key poses
// whose cloth passes through the body.
std::vector<std::string> fit_warnings(const FitResult& fit, const MotionRunOptions& options);

// The one error line of a fit that ends with a check's verdict (exit 8): the
// held key pose and the opening proposed (from `held`), or the first key pose
// the verification fails; nothing when the fit passes.
std::optional<std::string> fit_failure(const FitResult& fit, const OrderedJson& held, const FitOptions& options);

}  // namespace gp::adapt
