#include "adapt/garment_fit.h"

#include <algorithm>

#include "core/error.h"

namespace gp::adapt {

FitResult fit_garment(PoseInterpolator& interpolator, const MotionSpec& motion, const Eigen::MatrixXd& V_garment,
                      const Eigen::MatrixXi& F, const GarmentFile& garment, const FitOptions& options,
                      const ProgressCallback& progress) {
  if (options.max_cycles < 1) throw UsageError("at least one fit cycle is needed");
  FitResult fit;
  MotionRunOptions run_options = options.motion;
  if (options.frame_stride < 0) throw UsageError("the verification's frame stride must be non-negative");
  // A run without adaptation is its own verification, in-between frames included.
  if (!run_options.adaptation.enabled && options.verify) run_options.schedule.frame_stride = options.frame_stride;
  MotionRunOptions verify_options = run_options;
  verify_options.schedule.frame_stride = options.frame_stride;
  verify_options.adaptation.frames.clear();
  for (int cycle = 1;; ++cycle) {
    MotionRunResult run;
    std::optional<FitVerification> verification;
    try {
      run = run_garment_motion(interpolator, motion, V_garment, F, garment, run_options, progress);
      // A pose the body holds ends the fit at once: no rest shape relieves
      // it, so neither a verification nor a further cycle would pass.
      if (run.held_key >= 0) {
        FitCycle summary;
        summary.steps = run.steps;
        summary.adaptations = run.adaptations;
        summary.rest_area_growth = run.keys.empty() ? 1.0 : run.keys.back().rest_area_growth;
        fit.run = std::move(run);
        fit.cycles.push_back(summary);
        return fit;
      }
      if (options.verify) {
        // A run that did not adapt is its own fresh simulation.
        verification = run_options.adaptation.enabled ? verify_fit(interpolator, motion, V_garment, F, garment,
                                                      rest_triangles_of(run.V_rest, F), verify_options,
                                                      options.criteria, progress)
                                         : judge_run(run, run_options.adaptation.adapter.delta, options.criteria);
      }
    } catch (const NumericalError& e) {
      // A further cycle that fails numerically (a runaway growth, a grown
      // rest shape too far from the design's placement to start from) leaves
      // the previous cycle's fit and its failed verdict as the result.
      if (cycle == 1) throw;
      fit.cycle_error = "cycle " + std::to_string(cycle) + ": " + e.message();
      return fit;
    }
    FitCycle summary;
    summary.steps = run.steps;
    summary.adaptations = run.adaptations;
    summary.rest_area_growth = run.keys.empty() ? 1.0 : run.keys.back().rest_area_growth;
    summary.verified = verification && verification->passed();
    fit.run = std::move(run);
    fit.verification = std::move(verification);
    fit.cycles.push_back(summary);
    if (!options.verify || summary.verified || cycle >= options.max_cycles || !run_options.adaptation.enabled) return fit;
    run_options.initial_rest = fit.run.V_rest;
    // The next cycle also adapts where an in-between frame failed, as the paper adapts during the
    // motion; the frames of earlier cycles stay.
    std::vector<int> more = failed_frames(*fit.verification);
    std::vector<int>& frames = run_options.adaptation.frames;
    frames.insert(frames.end(), more.begin(), more.end());
    std::sort(frames.begin(), frames.end());
    frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  }
}

}  // namespace gp::adapt
