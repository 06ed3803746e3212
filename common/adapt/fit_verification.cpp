#include "adapt/fit_verification.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "adapt/key_pose_report.h"
#include "cloth/cloth_model.h"

namespace gp::adapt {

bool FitVerification::passed() const {
  for (const PoseCheck& p : poses) {
    if (!p.passed()) return false;
  }
  for (const TransitionCheck& t : transitions) {
    if (!t.passed()) return false;
  }
  return true;
}

int TransitionCheck::failed_frames() const {
  int n = 0;
  for (const PoseCheck& f : frames) n += f.passed() ? 0 : 1;
  return n;
}

std::vector<int> failed_frames(const FitVerification& v) {
  std::vector<int> out;
  for (const TransitionCheck& t : v.transitions) {
    for (const PoseCheck& f : t.frames) {
      if (!f.passed()) out.push_back(f.figures.frame);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string failure_line(const TransitionCheck& t) {
  if (t.passed()) return "";
  const PoseCheck& w = t.frames[static_cast<size_t>(t.worst)];
  return std::to_string(t.failed_frames()) + " of " + std::to_string(t.frames.size()) + " in-between frames from " +
         t.from + " to " + t.to + " fail, the worst at frame " + std::to_string(w.figures.frame) + " (" +
         w.figures.pose + "): " + w.failures.front();
}

OrderedJson to_json(const TransitionCheck& check, const std::string& mesh) {
  OrderedJson j;
  j["transition"] = check.transition;
  j["from"] = check.from;
  j["to"] = check.to;
  j["frames_solved"] = check.frames.size();
  j["frames_failed"] = check.failed_frames();
  j["verdict"] = check.passed() ? "pass" : "fail";
  // The worst value of each figure over the frames, and the frame it is at.
  OrderedJson worst_of = OrderedJson::object();
  auto worst_figure = [&](const char* name, auto figure) {
    int at = -1;
    double value = 0.0;
    for (size_t k = 0; k < check.frames.size(); ++k) {
      const double x = static_cast<double>(figure(check.frames[k].figures));
      if (at < 0 || x > value) {
        value = x;
        at = static_cast<int>(k);
      }
    }
    if (at < 0) return;
    worst_of[name] = {{"value", value}, {"frame", check.frames[static_cast<size_t>(at)].figures.frame},
                      {"t", check.frames[static_cast<size_t>(at)].figures.t}};
  };
  worst_figure("max_stretch", [](const KeyPoseResult& k) { return k.max_stretch; });
  worst_figure("p99_stretch", [](const KeyPoseResult& k) { return k.p99_stretch; });
  worst_figure("mean_stretch", [](const KeyPoseResult& k) { return k.mean_stretch; });
  worst_figure("area_fraction_above_limit", [](const KeyPoseResult& k) { return k.area_fraction_above; });
  worst_figure("deepest_penetration_m", [](const KeyPoseResult& k) { return k.deepest_penetration; });
  worst_figure("crossings", [](const KeyPoseResult& k) { return k.crossings.crossings(); });
  worst_figure("force_residual", [](const KeyPoseResult& k) { return k.force_residual; });
  j["worst_of_each"] = std::move(worst_of);
  if (check.worst >= 0) j["worst_frame"] = to_json(check.frames[static_cast<size_t>(check.worst)], mesh);
  return j;
}

OrderedJson to_json(const PoseCheck& check, const std::string& mesh) {
  return key_pose_json(check.figures, mesh, &check.failures, check.area_fraction_torn);
}

std::vector<cloth::TriangleRest> rest_triangles_of(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F) {
  return cloth::build_rest_state(V_rest, F, cloth::ClothParameters{}).triangles;
}

FitVerification verify_fit(PoseInterpolator& interpolator, const MotionSpec& motion,
                           const Eigen::MatrixXd& V_start, const Eigen::MatrixXi& F, const GarmentFile& garment,
                           const std::vector<cloth::TriangleRest>& rest_triangles, MotionRunOptions options,
                           const FitCriteria& criteria, const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  options.adaptation.enabled = false;
  options.rest_triangles = rest_triangles;
  options.initial_rest.resize(0, 0);
  ProgressCallback labelled;
  if (progress) {
    labelled = [&progress](const MotionProgress& p) {
      MotionProgress q = p;
      q.message = "verification: " + p.message;
      progress(q);
    };
  }
  FitVerification v = judge_run(run_garment_motion(interpolator, motion, V_start, F, garment, options, labelled),
                                options.adaptation.adapter.delta, criteria);
  v.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return v;
}

namespace {

// A key pose or an in-between frame judged by the bounds.
PoseCheck judged(const KeyPoseResult& k, double delta, const FitCriteria& criteria) {
  PoseCheck check;
  check.failures = check_pose(k, delta, criteria);
  check.area_fraction_torn = area_fraction_above(k, criteria.tear_stretch);
  check.figures = k;
  return check;
}

}  // namespace

FitVerification judge_run(const MotionRunResult& run, double delta, const FitCriteria& criteria) {
  FitVerification v;
  v.steps = run.steps;
  v.rejected_steps = run.solver.rejected;
  for (const KeyPoseResult& k : run.keys) v.poses.push_back(judged(k, delta, criteria));
  for (const KeyPoseResult& f : run.frames) {
    if (v.transitions.empty() || v.transitions.back().transition != f.transition) {
      TransitionCheck t;
      t.transition = f.transition;
      const size_t from = static_cast<size_t>(f.transition), to = static_cast<size_t>(f.key);
      if (from < run.keys.size()) t.from = run.keys[from].pose;
      if (to < run.keys.size()) t.to = run.keys[to].pose;
      v.transitions.push_back(std::move(t));
    }
    v.transitions.back().frames.push_back(judged(f, delta, criteria));
  }
  for (TransitionCheck& t : v.transitions) {
    auto worse = [](const PoseCheck& a, const PoseCheck& b) {  // a worse than b
      if (a.failures.size() != b.failures.size()) return a.failures.size() > b.failures.size();
      if (a.figures.area_fraction_above != b.figures.area_fraction_above) {
        return a.figures.area_fraction_above > b.figures.area_fraction_above;
      }
      return a.figures.p99_stretch > b.figures.p99_stretch;
    };
    for (size_t k = 0; k < t.frames.size(); ++k) {
      if (t.worst < 0 || worse(t.frames[k], t.frames[static_cast<size_t>(t.worst)])) t.worst = static_cast<int>(k);
    }
    // Only the worst frame's drape and per-face figures are kept (the report shows it).
    for (size_t k = 0; k < t.frames.size(); ++k) {
      if (static_cast<int>(k) == t.worst) continue;
      KeyPoseResult& f = t.frames[k].figures;
      f.V_draped.resize(0, 0);
      f.face_max_stretch.resize(0);
      f.face_rest_area.resize(0);
    }
  }
  return v;
}

}  // namespace gp::adapt
