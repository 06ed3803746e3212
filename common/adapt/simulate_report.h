#pragma once
// What simulate-adapt writes besides its meshes: report.json (written last; export-rest and
// fit-report read it back), timing.json (varies between runs), the drape files' names, and the
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

// verified_* after an adaptation; draped_* without one (its run is the fresh simulation).
std::string verified_drape_file_name(const KeyPoseResult& k, bool adapted);

// "worst_frame_<transition, two digits>_<from>_to_<to>.ply".
std::string worst_frame_file_name(const TransitionCheck& t);

// rest.ply, the run's and (after an adaptation) the verification's key drapes and each
// transition's worst in-between frame, in writing order; drapes carry face field max_stretch.
std::vector<std::pair<std::string, Mesh>> fit_meshes(const FitResult& fit, const Eigen::MatrixXi& F, bool adapted);

// The held key pose and the least opening that frees it (choose_opening), for make fit's
// fallback; null when no pose is held.
OrderedJson held_json(const FitResult& fit, const MotionSpec& motion, PoseInterpolator& interpolator,
                      const GarmentFile& garment, const MotionRunOptions& options, OpeningOptions opening);

struct SimulateReportInputs {
  std::string poses_path;
  std::string motion_path;
  std::string garment_path;
  int threads = 1;  // --threads
};

// report.json: options (FitOptionFields), carry, counts, hulls, key poses, cycles, held,
// verification and the run's figures.
OrderedJson simulate_report(const SimulateReportInputs& where, const FitInputs& in, const FitOptions& options,
                            const FitResult& fit, const OrderedJson& held);

// timing.json: time per phase, work counters, rejected steps' reasons, total_s.
OrderedJson simulate_timing(const FitResult& fit, int threads, int workers, double total_s);

// A failed further cycle, a garment starting through the body, cloth through the body.
std::vector<std::string> fit_warnings(const FitResult& fit, const MotionRunOptions& options);

// The error line of a fit ending in exit 8 (held pose and opening, or the first failing key
// pose or transition); nothing when it passes.
std::optional<std::string> fit_failure(const FitResult& fit, const OrderedJson& held, const FitOptions& options);

}  // namespace gp::adapt
