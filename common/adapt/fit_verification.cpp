#include "adapt/fit_verification.h"

#include <chrono>
#include <cstdio>

#include "adapt/key_pose_report.h"
#include "cloth/cloth_model.h"

namespace gp::adapt {

bool FitVerification::passed() const {
  for (const PoseCheck& p : poses) {
    if (!p.passed()) return false;
  }
  return true;
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
  options.adapt = false;
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
                                options.adaptation.delta, criteria);
  v.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return v;
}

FitVerification judge_run(const MotionRunResult& run, double delta, const FitCriteria& criteria) {
  FitVerification v;
  v.steps = run.steps;
  v.rejected_steps = run.solver.rejected;
  for (const KeyPoseResult& k : run.keys) {
    PoseCheck check;
    check.failures = check_pose(k, delta, criteria);
    check.area_fraction_torn = area_fraction_above(k, criteria.tear_stretch);
    check.figures = k;
    v.poses.push_back(std::move(check));
  }
  return v;
}

}  // namespace gp::adapt
