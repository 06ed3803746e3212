#include "cloth/step_validation.h"

#include <Eigen/Dense>

#include "cloth/system_assembly.h"
#include "core/error.h"

namespace gp::cloth {

long& count_of(RejectionCounts& counts, Rejection r) {
  switch (r) {
    case Rejection::solve_failed: return counts.solve_failed;
    case Rejection::non_finite: return counts.non_finite;
    case Rejection::too_fast: return counts.too_fast;
    case Rejection::inverted: return counts.inverted;
    case Rejection::energy_growth: return counts.energy_growth;
    case Rejection::none: break;
  }
  throw Error(ExitCode::internal, "an accepted step has no rejection counter");
}

StepOutcome validate_step(const Eigen::MatrixXd& X, const Eigen::MatrixXd& X_new, const Eigen::MatrixXd& V_new,
                          const Eigen::MatrixXi& F, const ClothRestState& rest, const ClothParameters& params,
                          const SimulatorOptions& options, double energy_before, bool accept_flips) {
  StepOutcome outcome;
  if (!X_new.allFinite() || !V_new.allFinite()) {
    outcome.rejection = Rejection::non_finite;
    outcome.detail = "non-finite positions or velocities";
    return outcome;
  }
  if (V_new.rowwise().norm().maxCoeff() > options.max_speed) {
    outcome.rejection = Rejection::too_fast;
    outcome.detail = "vertex speed above " + std::to_string(options.max_speed) + " m/s";
    return outcome;
  }
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d x0 = X.row(F(f, 0)), x1 = X.row(F(f, 1)), x2 = X.row(F(f, 2));
    const Eigen::Vector3d y0 = X_new.row(F(f, 0)), y1 = X_new.row(F(f, 1)), y2 = X_new.row(F(f, 2));
    const Eigen::Vector3d n_old = (x1 - x0).cross(x2 - x0);
    const Eigen::Vector3d n_new = (y1 - y0).cross(y2 - y0);
    if (n_old.dot(n_new) < 0.0) outcome.flipped_faces.push_back(f);
  }
  // A triangle turned over within one step is a symptom of a too large step
  // and is retried; if it survives the smallest step, it is a fold forced by
  // the body (cloth squeezed between two body parts), which cloth may do: it
  // is accepted and counted rather than ending the run.
  const long flipped = static_cast<long>(outcome.flipped_faces.size());
  if (flipped > 0 && !accept_flips) {
    outcome.rejection = Rejection::inverted;
    outcome.detail = std::to_string(flipped) + " triangle(s) inverted, first " +
                     std::to_string(outcome.flipped_faces.front());
    return outcome;
  }
  outcome.accepted_folds = flipped;
  const double energy_after = membrane_energy(X_new, F, rest, params) + quadratic_bending_energy(X_new, rest, params) +
                              kinetic_energy(V_new, rest.masses);
  const double floor = 10.0 * rest.masses.sum();
  if (energy_after > options.energy_growth_limit * energy_before + floor) {
    outcome.rejection = Rejection::energy_growth;
    outcome.detail = "energy exploded (" + std::to_string(energy_before) + " J -> " + std::to_string(energy_after) +
                     " J)";
  }
  return outcome;
}

}  // namespace gp::cloth
