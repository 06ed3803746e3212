// interp-poses: in-between bodies for a motion through registered poses.
// Reads a pose set (poses.json or pose mesh files) and a motion spec
// ("motion/1", see interp/motion_spec.h); writes the frames as binary PLY, a
// manifest motion.json ("motion-frames/1") and report.json
// ("interp-poses-report/1") with shape statistics per frame and the deviation
// of the linear baseline from the nonlinear method, and timing.json.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "interp/frame_measures.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"

namespace fs = std::filesystem;

namespace {

std::string frame_file_name(int index) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "frame_%05d.ply", index);
  return buf;
}

gp::OrderedJson measures_json(const gp::FrameMeasures& m) {
  gp::OrderedJson j;
  j["volume_m3"] = m.volume;
  j["volume_excess"] = m.volume_excess;
  j["edge_ratio_min"] = m.edge_ratio_min;
  j["edge_ratio_max"] = m.edge_ratio_max;
  j["edge_excess_max"] = m.edge_excess_max;
  j["edge_excess_mean"] = m.edge_excess_mean;
  return j;
}

gp::OrderedJson deviation_json(const gp::FrameDeviation& d) {
  gp::OrderedJson j;
  j["edge_deviation_max"] = d.edge_deviation_max;
  j["edge_deviation_mean"] = d.edge_deviation_mean;
  j["volume_error"] = d.volume_error;
  j["vertex_distance_max_m"] = d.vertex_distance_max;
  return j;
}

double elapsed_ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// CPU time of the process [ms]: unlike wall time, not inflated by other jobs
// on a shared machine (with --threads 1 it is the single core's time).
double cpu_ms() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

}  // namespace

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

    const double factor_cpu_start = cpu_ms();
    gp::PoseInterpolator interpolator(poses, options);
    const double factor_cpu_ms = cpu_ms() - factor_cpu_start;
    const bool compare = options.method == gp::InterpolationMethod::nonlinear && !no_compare;
    std::unique_ptr<gp::PoseInterpolator> linear;
    if (compare) {
      gp::InterpolationOptions lin = options;
      lin.method = gp::InterpolationMethod::linear;
      linear = std::make_unique<gp::PoseInterpolator>(poses, lin);
    }
    gp::MotionMeasurer measurer(poses.V, poses.F, interpolator.reference_pose());
    log.detail("factorized the Poisson system in " +
               std::to_string(interpolator.factorization_seconds() * 1e3) + " ms");

    // Frames.
    gp::OrderedJson frames_report = gp::OrderedJson::array();
    gp::OrderedJson manifest_frames = gp::OrderedJson::array();
    gp::OrderedJson transitions = gp::OrderedJson::array();
    std::vector<double> prepare_ms;
    double frame_ms_sum = 0.0, frame_ms_max = 0.0, frame_cpu_ms_sum = 0.0;
    int timed = 0;
    double edge_excess_max = 0.0, volume_excess_max = 0.0;
    gp::FrameDeviation worst;
    double deviation_mean_sum = 0.0;
    int written = 0;
    Eigen::MatrixXd V, V_lin;
    gp::MeshWriteOptions write_options;
    write_options.double_precision = !float32;
    std::set<std::pair<int, int>> prepared;
    for (const gp::MotionFrame& fr : frames) {
      if (fr.key != 0 && !prepared.count({fr.from, fr.to})) {
        const auto start = std::chrono::steady_clock::now();
        interpolator.prepare(fr.from, fr.to);
        prepare_ms.push_back(elapsed_ms(start));
        prepared.insert({fr.from, fr.to});
      }
      if (fr.key != 0 && static_cast<int>(transitions.size()) == fr.transition) {
        const gp::TransitionInfo& info = interpolator.transition_info(fr.from, fr.to);
        gp::OrderedJson t;
        t["from"] = poses.names[static_cast<size_t>(fr.from)];
        t["to"] = poses.names[static_cast<size_t>(fr.to)];
        t["steps"] = spec.keys[static_cast<size_t>(fr.transition) + 1].steps;
        t["max_rotation_deg"] = info.max_rotation_deg;
        t["faces_off_principal_branch"] = info.faces_off_principal_branch;
        t["degenerate_faces"] = info.degenerate_faces;
        transitions.push_back(t);
      }
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = cpu_ms();
      interpolator.frame(fr.from, fr.to, fr.t, V);
      frame_cpu_ms_sum += cpu_ms() - cpu_start;
      const double ms = elapsed_ms(start);
      frame_ms_sum += ms;
      frame_ms_max = std::max(frame_ms_max, ms);
      ++timed;

      const gp::FrameMeasures m = measurer.measure(V, fr.from, fr.to);
      edge_excess_max = std::max(edge_excess_max, m.edge_excess_max);
      volume_excess_max = std::max(volume_excess_max, m.volume_excess);
      gp::OrderedJson fj;
      fj["index"] = fr.index;
      fj["from"] = poses.names[static_cast<size_t>(fr.from)];
      fj["to"] = poses.names[static_cast<size_t>(fr.to)];
      fj["t"] = fr.t;
      const gp::OrderedJson mjson = measures_json(m);
      for (auto it = mjson.begin(); it != mjson.end(); ++it) fj[it.key()] = it.value();
      if (compare) {
        linear->frame(fr.from, fr.to, fr.t, V_lin);
        const gp::FrameDeviation d = measurer.compare(V_lin, V);
        worst.edge_deviation_max = std::max(worst.edge_deviation_max, d.edge_deviation_max);
        worst.vertex_distance_max = std::max(worst.vertex_distance_max, d.vertex_distance_max);
        if (std::abs(d.volume_error) > std::abs(worst.volume_error)) worst.volume_error = d.volume_error;
        deviation_mean_sum += d.edge_deviation_mean;
        fj["linear_vs_nonlinear"] = deviation_json(d);
      }
      gp::OrderedJson mj;
      mj["index"] = fr.index;
      mj["from"] = poses.names[static_cast<size_t>(fr.from)];
      mj["to"] = poses.names[static_cast<size_t>(fr.to)];
      mj["t"] = fr.t;
      mj["key"] = fr.key >= 0 ? gp::OrderedJson(spec.keys[static_cast<size_t>(fr.key)].pose)
                              : gp::OrderedJson(nullptr);
      if (selected[static_cast<size_t>(fr.index)]) {
        const std::string name = frame_file_name(fr.index);
        gp::Mesh mesh;
        mesh.V = V;
        mesh.F = poses.F;
        gp::write_mesh(out.file(name), mesh, write_options);
        mj["file"] = name;
        ++written;
      } else {
        mj["file"] = nullptr;
      }
      manifest_frames.push_back(mj);
      frames_report.push_back(fj);
      log.progress("frame " + std::to_string(fr.index + 1) + " of " + std::to_string(frames.size()));
    }
    log.progress_done();

    gp::OrderedJson pose_set;
    pose_set["names"] = poses.names;
    pose_set["reference"] = poses.names[static_cast<size_t>(interpolator.reference_pose())];
    pose_set["vertex_count"] = poses.V[0].rows();
    pose_set["face_count"] = poses.F.rows();
    pose_set["topology_sha256"] = gp::topology_checksum(poses.F);

    gp::OrderedJson manifest;
    manifest["schema"] = gp::schema_tag("motion-frames", 1);
    manifest["units"] = "m";
    manifest["up"] = "+y";
    manifest["method"] = gp::to_string(options.method);
    manifest["pose_set"] = pose_set;
    manifest["frame_count"] = frames.size();
    manifest["frames_written"] = written;
    manifest["frames"] = manifest_frames;
    gp::write_json_file(out.file("motion.json"), manifest);

    const Eigen::MatrixXd& V_ref = poses.V[static_cast<size_t>(interpolator.reference_pose())];
    gp::OrderedJson report;
    report["schema"] = gp::schema_tag("interp-poses-report", 1);
    report["tool"] = "interp-poses";
    gp::OrderedJson in;
    in["poses"] = inputs;
    in["motion"] = motion_path;
    report["inputs"] = in;
    // The library's options, then the stage's own (what it writes).
    gp::OrderedJson opt = gp::write_options(options, gp::InterpolationOptionFields{});
    opt["frames"] = frame_list;
    opt["keys_only"] = keys_only;
    opt["float32"] = float32;
    opt["compare_linear"] = compare;
    opt["threads"] = tool.common().threads;
    report["options"] = opt;
    report["motion"] = gp::to_json(spec);
    gp::OrderedJson mesh;
    mesh["pose_set"] = pose_set;
    mesh["body_height_m"] = V_ref.col(1).maxCoeff() - V_ref.col(1).minCoeff();
    mesh["anchor_vertex_count"] = interpolator.anchor_vertex_ids().size();
    report["mesh"] = mesh;
    report["transitions"] = transitions;
    {
      // Timings vary from run to run, so they live apart from the report.
      gp::OrderedJson timing;
      timing["schema"] = gp::schema_tag("timing", 1);
      timing["tool"] = "interp-poses";
      timing["factorization_ms"] = interpolator.factorization_seconds() * 1e3;
      timing["setup_cpu_ms"] = factor_cpu_ms;
      timing["prepare_ms_per_transition"] = prepare_ms;
      timing["ms_per_frame_mean"] = timed > 0 ? frame_ms_sum / timed : 0.0;
      timing["ms_per_frame_max"] = frame_ms_max;
      timing["cpu_ms_per_frame_mean"] = timed > 0 ? frame_cpu_ms_sum / timed : 0.0;
      timing["frames_timed"] = timed;
      timing["note"] =
          "wall clock unless named cpu; setup = anchor + Laplacian + factorization; frame times exclude "
          "measuring and writing";
      gp::write_json_file(out.file("timing.json"), timing);
    }
    gp::OrderedJson summary;
    summary["frame_count"] = frames.size();
    summary["frames_written"] = written;
    summary["edge_excess_max"] = edge_excess_max;
    summary["volume_excess_max"] = volume_excess_max;
    if (compare) {
      gp::OrderedJson d = deviation_json(worst);
      d["edge_deviation_mean"] = frames.empty() ? 0.0 : deviation_mean_sum / frames.size();
      summary["linear_vs_nonlinear"] = d;
    }
    report["summary"] = summary;
    report["frames"] = frames_report;
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    log.info("wrote " + std::to_string(written) + " of " + std::to_string(frames.size()) + " frames to " +
             out.final_path().string());
    return 0;
  });
}
