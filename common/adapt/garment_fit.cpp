#include "adapt/garment_fit.h"

#include "core/error.h"

namespace gp::adapt {

FitResult fit_garment(PoseInterpolator& interpolator, const MotionSpec& motion, const Eigen::MatrixXd& V_garment,
                      const Eigen::MatrixXi& F, const GarmentFile& garment, const FitOptions& options,
                      const ProgressCallback& progress) {
  if (options.max_cycles < 1) throw UsageError("at least one fit cycle is needed");
  FitResult fit;
  MotionRunOptions run_options = options.motion;
  for (int cycle = 1;; ++cycle) {
    fit.run = run_garment_motion(interpolator, motion, V_garment, F, garment, run_options, progress);
    FitCycle summary;
    summary.steps = fit.run.steps;
    summary.adaptations = fit.run.adaptations;
    summary.rest_area_growth = fit.run.keys.empty() ? 1.0 : fit.run.keys.back().rest_area_growth;
    if (!options.verify) {
      fit.cycles.push_back(summary);
      return fit;
    }
    // A run that did not adapt is its own fresh simulation.
    fit.verification = run_options.adapt ? verify_fit(interpolator, motion, V_garment, F, garment,
                                                      rest_triangles_of(fit.run.V_rest, F), run_options,
                                                      options.criteria)
                                         : judge_run(fit.run, run_options.adaptation.delta, options.criteria);
    summary.verified = fit.verification->passed();
    fit.cycles.push_back(summary);
    if (summary.verified || cycle >= options.max_cycles || !run_options.adapt) return fit;
    run_options.initial_rest = fit.run.V_rest;
  }
}

}  // namespace gp::adapt
