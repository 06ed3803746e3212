#pragma once
// A motion's frames interpolated, measured and reported as interp-poses
// writes them: the per-frame shape statistics (frame_measures.h), the linear
// baseline's deviation from the nonlinear method, the manifest of the frames
// (motion-frames/1), the report (interp-poses-report/1) and the timings.
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "interp/frame_measures.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"

namespace gp {

struct FrameRun {
  OrderedJson frames = OrderedJson::array();           // the report's frames, one per motion frame
  OrderedJson manifest_frames = OrderedJson::array();  // the manifest's frames, with their files
  OrderedJson transitions = OrderedJson::array();      // rotation figures per transition
  int frame_count = 0;
  int written = 0;                 // frames handed to `write`
  double edge_excess_max = 0.0;
  double volume_excess_max = 0.0;
  bool compared = false;           // the linear baseline was compared
  FrameDeviation worst;            // of the linear baseline, over all frames
  double deviation_mean_sum = 0.0;
  // Timings [ms]: wall clock unless named cpu.
  std::vector<double> prepare_ms;  // per transition
  double frame_ms_sum = 0.0, frame_ms_max = 0.0, frame_cpu_ms_sum = 0.0;
  int timed = 0;
};

// "frame_<index, five digits>.ply".
std::string frame_file_name(int index);

// Every frame of `spec` from `interpolator`; with `linear` (the same poses,
// the linear method), each frame is compared with the linear baseline.
// Frames with selected[index] are handed to `write` under frame_file_name;
// `progress` receives the frame number and the count.
FrameRun run_frames(PoseInterpolator& interpolator, PoseInterpolator* linear, const PoseSet& poses,
                    const MotionSpec& spec, const std::vector<char>& selected,
                    const std::function<void(const std::string& file, const Eigen::MatrixXd& V)>& write,
                    const std::function<void(int frame, int count)>& progress = {});

// The pose set as the manifest and the report describe it.
OrderedJson pose_set_json(const PoseSet& poses, const PoseInterpolator& interpolator);

// motion.json (motion-frames/1).
OrderedJson frames_manifest(const FrameRun& run, const PoseSet& poses, const PoseInterpolator& interpolator,
                            InterpolationMethod method);

// What the report records of the stage's own options besides the library's.
struct FrameRunInputs {
  std::vector<std::string> poses;  // the inputs as given
  std::string motion;
  std::vector<int> frames;  // --frames
  bool keys_only = false;
  bool float32 = false;
  int threads = 1;
};

// report.json (interp-poses-report/1).
OrderedJson frames_report(const FrameRun& run, const FrameRunInputs& inputs, const InterpolationOptions& options,
                          const PoseSet& poses, const MotionSpec& spec, const PoseInterpolator& interpolator);

// timing.json (timing/1); setup_cpu_ms: the interpolator's construction.
OrderedJson frames_timing(const FrameRun& run, const PoseInterpolator& interpolator, double setup_cpu_ms);

// CPU time of the process [ms]: unlike wall time, not inflated by other jobs
// on a shared machine (with --threads 1 it is the single core's time).
double process_cpu_ms();

}  // namespace gp
