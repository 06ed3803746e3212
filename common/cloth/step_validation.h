#pragma once
// The checks that accept or reject a (sub)step of the cloth simulator (cloth_simulator.h): the new
// positions and velocities must be finite, no vertex faster than options.max_speed, no triangle
// turned over within the step (its normal turning by more than 90 degrees), and kinetic plus
// elastic energy not grown beyond options.energy_growth_limit times plus a floor of 10 J per kg of
// cloth. The first failed check is the step's typed outcome.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth/cloth_model.h"
#include "cloth/cloth_simulator.h"

namespace gp::cloth {

// Why a (sub)step was rejected; none: it was accepted.
enum class Rejection { none, solve_failed, non_finite, too_fast, inverted, energy_growth };

struct StepOutcome {
  Rejection rejection = Rejection::none;
  std::string detail;              // what was wrong, for the error message when no halving helps
  std::vector<int> flipped_faces;  // the faces that turned over within the step (ascending)
  // Turned-over faces accepted as folds (accept_flips): counted even when the energy check then
  // rejects the step.
  long accepted_folds = 0;
  bool accepted() const { return rejection == Rejection::none; }
};

// The counter of `r` in `counts` (r is a rejection, not none; throws Error otherwise).
long& count_of(RejectionCounts& counts, Rejection r);

// Checks the step from X to X_new with velocities V_new (#V by 3, faces F); energy_before [J] is the
// kinetic plus elastic energy at the start. With accept_flips, turned-over faces are folds and do
// not reject the step.
StepOutcome validate_step(const Eigen::MatrixXd& X, const Eigen::MatrixXd& X_new, const Eigen::MatrixXd& V_new,
                          const Eigen::MatrixXi& F, const ClothRestState& rest, const ClothParameters& params,
                          const SimulatorOptions& options, double energy_before, bool accept_flips);

}  // namespace gp::cloth
