// interp-poses: in-between bodies for a motion through registered poses.
// Reads a pose set (poses.json or pose mesh files) and a motion spec
// ("motion/1", see interp/motion_spec.h); writes the frames as binary PLY, a
// manifest motion.json ("motion-frames/1") and report.json
// ("interp-poses-report/1") with shape statistics per frame and the deviation
// of the linear baseline from the nonlinear method, and timing.json.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "interp/frame_run.h"
#include "io/mesh_io.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  gp::Tool tool("interp-poses",
                "In-between bodies for a motion through registered poses: nonlinear interpolation of "
                "per-triangle deformation gradients (rotation log + stretch) with a Poisson solve, or "
                "a linear blend for comparison.");
  std::vector<std::string> inputs;
  std::string motion_path, method_name = "nonlinear", solver_name = "simplicial";
  std::vector<int> frame_list;
  bool keys_only = false, float32 = false, no_compare = false;
  auto& app = tool.app();
  app.add_option("inputs", inputs, "poses.json (pose-set/1) or pose mesh files, .ply/.obj [m]")
      ->required();
  app.add_option("-m,--motion", motion_path, "Motion spec (motion/1 JSON)")->required();
  app.add_option("--method", method_name, "Interpolation method: nonlinear or linear (baseline) [name]")
      ->check(CLI::IsMember({"nonlinear", "linear"}));
  app.add_option("--frames", frame_list, "Write only these frames, comma separated, numbered from 0 [frame index]")
      ->delimiter(',');
  app.add_flag("--keys-only", keys_only, "Write only the frames that are key poses");
  app.add_flag("--float32", float32, "Write positions as 32-bit floats (half the size; not exact)");
  app.add_option("--solver", solver_name, "CHOLMOD factorization of the Poisson system [name]")
      ->check(CLI::IsMember({"supernodal", "simplicial"}));
  app.add_flag("--no-compare", no_compare,
               "Skip the linear-baseline comparison per frame (nonlinear method only)");
  tool.add_common_options();

  return tool.run(argc, argv, [&]() {
    auto& log = tool.log();
    if (keys_only && !frame_list.empty())
      throw gp::UsageError("--keys-only and --frames exclude each other");

    // Inputs.
    gp::PoseSet poses;
    std::vector<std::string> input_files;
    if (inputs.size() == 1 && fs::path(inputs[0]).extension() == ".json") {
      poses = gp::load_pose_set(inputs[0]);
    } else {
      std::vector<fs::path> files(inputs.begin(), inputs.end());
      poses = gp::load_pose_files(files);
    }
    const gp::MotionSpec spec = gp::read_motion_spec(motion_path, poses);
    const std::vector<gp::MotionFrame> frames = gp::motion_frames(spec);
    std::vector<char> selected(frames.size(), 0);
    for (const auto& fr : frames)
      selected[static_cast<size_t>(fr.index)] = keys_only ? fr.key >= 0 : frame_list.empty();
    for (int i : frame_list) {
      if (i < 0 || i >= static_cast<int>(frames.size()))
        throw gp::UsageError("--frames: frame " + std::to_string(i) + " does not exist (the motion has " +
                             std::to_string(frames.size()) + " frames, 0 to " +
                             std::to_string(frames.size() - 1) + ")");
      selected[static_cast<size_t>(i)] = 1;
    }

    gp::InterpolationOptions options;
    options.method = gp::parse_interpolation_method(method_name);
    options.anchor = spec.anchor;
    options.solver.method = solver_name == "simplicial" ? gp::CholmodOptions::Method::simplicial
                                                        : gp::CholmodOptions::Method::supernodal;
    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);

    const double factor_cpu_start = gp::process_cpu_ms();
    gp::PoseInterpolator interpolator(poses, options);
    const double factor_cpu_ms = gp::process_cpu_ms() - factor_cpu_start;
    const bool compare = options.method == gp::InterpolationMethod::nonlinear && !no_compare;
    std::unique_ptr<gp::PoseInterpolator> linear;
    if (compare) {
      gp::InterpolationOptions lin = options;
      lin.method = gp::InterpolationMethod::linear;
      linear = std::make_unique<gp::PoseInterpolator>(poses, lin);
    }
    log.detail("factorized the Poisson system in " +
               std::to_string(interpolator.factorization_seconds() * 1e3) + " ms");

    gp::MeshWriteOptions write_options;
    write_options.double_precision = !float32;
    const auto write_frame = [&](const std::string& file, const Eigen::MatrixXd& V) {
      gp::Mesh mesh;
      mesh.V = V;
      mesh.F = poses.F;
      gp::write_mesh(out.file(file), mesh, write_options);
    };
    const gp::FrameRun run = gp::run_frames(interpolator, linear.get(), poses, spec, selected, write_frame,
                                            [&](int frame, int count) {
                                              log.progress("frame " + std::to_string(frame) + " of " +
                                                           std::to_string(count));
                                            });
    log.progress_done();

    gp::write_json_file(out.file("motion.json"), gp::frames_manifest(run, poses, interpolator, options.method));
    gp::write_json_file(out.file("timing.json"), gp::frames_timing(run, interpolator, factor_cpu_ms));
    const gp::FrameRunInputs where{inputs, motion_path, frame_list, keys_only, float32, tool.common().threads};
    gp::write_json_file(out.file("report.json"), gp::frames_report(run, where, options, poses, spec, interpolator));
    out.commit();
    log.info("wrote " + std::to_string(run.written) + " of " + std::to_string(frames.size()) + " frames to " +
             out.final_path().string());
    return 0;
  });
}
