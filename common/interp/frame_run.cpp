#include "interp/frame_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <set>

#include "spec/option_fields.h"

namespace gp {

namespace {

OrderedJson measures_json(const FrameMeasures& m) {
  OrderedJson j;
  j["volume_m3"] = m.volume;
  j["volume_excess"] = m.volume_excess;
  j["edge_ratio_min"] = m.edge_ratio_min;
  j["edge_ratio_max"] = m.edge_ratio_max;
  j["edge_excess_max"] = m.edge_excess_max;
  j["edge_excess_mean"] = m.edge_excess_mean;
  return j;
}

OrderedJson deviation_json(const FrameDeviation& d) {
  OrderedJson j;
  j["edge_deviation_max"] = d.edge_deviation_max;
  j["edge_deviation_mean"] = d.edge_deviation_mean;
  j["volume_error"] = d.volume_error;
  j["vertex_distance_max_m"] = d.vertex_distance_max;
  return j;
}

double elapsed_ms(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

double process_cpu_ms() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

std::string frame_file_name(int index) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "frame_%05d.ply", index);
  return buf;
}

FrameRun run_frames(PoseInterpolator& interpolator, PoseInterpolator* linear, const PoseSet& poses,
                    const MotionSpec& spec, const std::vector<char>& selected,
                    const std::function<void(const std::string& file, const Eigen::MatrixXd& V)>& write,
                    const std::function<void(int frame, int count)>& progress) {
  const std::vector<MotionFrame> frames = motion_frames(spec);
  FrameRun run;
  run.frame_count = static_cast<int>(frames.size());
  run.compared = linear != nullptr;
  MotionMeasurer measurer(poses.V, poses.F, interpolator.reference_pose());
  Eigen::MatrixXd V, V_lin;
  std::set<std::pair<int, int>> prepared;
  for (const MotionFrame& fr : frames) {
    if (fr.key != 0 && !prepared.count({fr.from, fr.to})) {
      const auto start = std::chrono::steady_clock::now();
      interpolator.prepare(fr.from, fr.to);
      run.prepare_ms.push_back(elapsed_ms(start));
      prepared.insert({fr.from, fr.to});
    }
    if (fr.key != 0 && static_cast<int>(run.transitions.size()) == fr.transition) {
      const TransitionInfo& info = interpolator.transition_info(fr.from, fr.to);
      OrderedJson t;
      t["from"] = poses.names[static_cast<size_t>(fr.from)];
      t["to"] = poses.names[static_cast<size_t>(fr.to)];
      t["steps"] = spec.keys[static_cast<size_t>(fr.transition) + 1].steps;
      t["max_rotation_deg"] = info.max_rotation_deg;
      t["faces_off_principal_branch"] = info.faces_off_principal_branch;
      t["degenerate_faces"] = info.degenerate_faces;
      run.transitions.push_back(t);
    }
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_ms();
    interpolator.frame(fr.from, fr.to, fr.t, V);
    run.frame_cpu_ms_sum += process_cpu_ms() - cpu_start;
    const double ms = elapsed_ms(start);
    run.frame_ms_sum += ms;
    run.frame_ms_max = std::max(run.frame_ms_max, ms);
    ++run.timed;

    const FrameMeasures m = measurer.measure(V, fr.from, fr.to);
    run.edge_excess_max = std::max(run.edge_excess_max, m.edge_excess_max);
    run.volume_excess_max = std::max(run.volume_excess_max, m.volume_excess);
    OrderedJson fj;
    fj["index"] = fr.index;
    fj["from"] = poses.names[static_cast<size_t>(fr.from)];
    fj["to"] = poses.names[static_cast<size_t>(fr.to)];
    fj["t"] = fr.t;
    const OrderedJson mjson = measures_json(m);
    for (auto it = mjson.begin(); it != mjson.end(); ++it) fj[it.key()] = it.value();
    if (linear) {
      linear->frame(fr.from, fr.to, fr.t, V_lin);
      const FrameDeviation d = measurer.compare(V_lin, V);
      run.worst.edge_deviation_max = std::max(run.worst.edge_deviation_max, d.edge_deviation_max);
      run.worst.vertex_distance_max = std::max(run.worst.vertex_distance_max, d.vertex_distance_max);
      if (std::abs(d.volume_error) > std::abs(run.worst.volume_error)) run.worst.volume_error = d.volume_error;
      run.deviation_mean_sum += d.edge_deviation_mean;
      fj["linear_vs_nonlinear"] = deviation_json(d);
    }
    OrderedJson mj;
    mj["index"] = fr.index;
    mj["from"] = poses.names[static_cast<size_t>(fr.from)];
    mj["to"] = poses.names[static_cast<size_t>(fr.to)];
    mj["t"] = fr.t;
    mj["key"] = fr.key >= 0 ? OrderedJson(spec.keys[static_cast<size_t>(fr.key)].pose) : OrderedJson(nullptr);
    if (selected[static_cast<size_t>(fr.index)]) {
      const std::string name = frame_file_name(fr.index);
      write(name, V);
      mj["file"] = name;
      ++run.written;
    } else {
      mj["file"] = nullptr;
    }
    run.manifest_frames.push_back(mj);
    run.frames.push_back(fj);
    if (progress) progress(fr.index + 1, run.frame_count);
  }
  return run;
}

OrderedJson pose_set_json(const PoseSet& poses, const PoseInterpolator& interpolator) {
  OrderedJson pose_set;
  pose_set["names"] = poses.names;
  pose_set["reference"] = poses.names[static_cast<size_t>(interpolator.reference_pose())];
  pose_set["vertex_count"] = poses.V[0].rows();
  pose_set["face_count"] = poses.F.rows();
  pose_set["topology_sha256"] = topology_checksum(poses.F);
  return pose_set;
}

OrderedJson frames_manifest(const FrameRun& run, const PoseSet& poses, const PoseInterpolator& interpolator,
                            InterpolationMethod method) {
  OrderedJson manifest;
  manifest["schema"] = schema_tag("motion-frames", 1);
  manifest["units"] = "m";
  manifest["up"] = "+y";
  manifest["method"] = to_string(method);
  manifest["pose_set"] = pose_set_json(poses, interpolator);
  manifest["frame_count"] = static_cast<size_t>(run.frame_count);
  manifest["frames_written"] = run.written;
  manifest["frames"] = run.manifest_frames;
  return manifest;
}

OrderedJson frames_report(const FrameRun& run, const FrameRunInputs& inputs, const InterpolationOptions& options,
                          const PoseSet& poses, const MotionSpec& spec, const PoseInterpolator& interpolator) {
  const Eigen::MatrixXd& V_ref = poses.V[static_cast<size_t>(interpolator.reference_pose())];
  OrderedJson report;
  report["schema"] = schema_tag("interp-poses-report", 1);
  report["tool"] = "interp-poses";
  OrderedJson in;
  in["poses"] = inputs.poses;
  in["motion"] = inputs.motion;
  report["inputs"] = in;
  // The library's options, then the stage's own (what it writes).
  OrderedJson opt = write_options(options, InterpolationOptionFields{});
  opt["frames"] = inputs.frames;
  opt["keys_only"] = inputs.keys_only;
  opt["float32"] = inputs.float32;
  opt["compare_linear"] = run.compared;
  opt["threads"] = inputs.threads;
  report["options"] = opt;
  report["motion"] = to_json(spec);
  OrderedJson mesh;
  mesh["pose_set"] = pose_set_json(poses, interpolator);
  mesh["body_height_m"] = V_ref.col(1).maxCoeff() - V_ref.col(1).minCoeff();
  mesh["anchor_vertex_count"] = interpolator.anchor_vertex_ids().size();
  report["mesh"] = mesh;
  report["transitions"] = run.transitions;
  OrderedJson summary;
  summary["frame_count"] = static_cast<size_t>(run.frame_count);
  summary["frames_written"] = run.written;
  summary["edge_excess_max"] = run.edge_excess_max;
  summary["volume_excess_max"] = run.volume_excess_max;
  if (run.compared) {
    OrderedJson d = deviation_json(run.worst);
    d["edge_deviation_mean"] =
        run.frame_count == 0 ? 0.0 : run.deviation_mean_sum / static_cast<size_t>(run.frame_count);
    summary["linear_vs_nonlinear"] = d;
  }
  report["summary"] = summary;
  report["frames"] = run.frames;
  return report;
}

OrderedJson frames_timing(const FrameRun& run, const PoseInterpolator& interpolator, double setup_cpu_ms) {
  // Timings vary from run to run, so they live apart from the report.
  OrderedJson timing;
  timing["schema"] = schema_tag("timing", 1);
  timing["tool"] = "interp-poses";
  timing["factorization_ms"] = interpolator.factorization_seconds() * 1e3;
  timing["setup_cpu_ms"] = setup_cpu_ms;
  timing["prepare_ms_per_transition"] = run.prepare_ms;
  timing["ms_per_frame_mean"] = run.timed > 0 ? run.frame_ms_sum / run.timed : 0.0;
  timing["ms_per_frame_max"] = run.frame_ms_max;
  timing["cpu_ms_per_frame_mean"] = run.timed > 0 ? run.frame_cpu_ms_sum / run.timed : 0.0;
  timing["frames_timed"] = run.timed;
  timing["note"] =
      "wall clock unless named cpu; setup = anchor + Laplacian + factorization; frame times exclude "
      "measuring and writing";
  return timing;
}

}  // namespace gp
