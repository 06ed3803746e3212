#pragma once
// Implicit Euler cloth time stepping (Baraff & Witkin 1998, sec. 5), linearized once per step:
//   (M + h D + h^2 H) v' = M v + h f(x),   x' = x + h v'
// with H the PSD-projected membrane Hessian plus k_bend Q, D the damping matrices, f the
// conservative forces (membrane, bending, gravity). The matrix is SPD by construction (mass
// positive, every element block projected PSD), so CHOLMOD never fails on a valid mesh. Pinned
// vertices reach their targets at the end of the step: their degrees of freedom are eliminated,
// their coupling to free ones moved to the right-hand side.
//
// Solver strategies (measured in cloth/README.md, "Solver strategies"):
//  - pcg_reused_factor: CG warm-started from the previous velocity, preconditioned by a CHOLMOD
//    factor of an earlier step's matrix (symbolic analysis once per pin set), refreshed when a
//    step's iterations exceed the average cost per step since the last factorization (which counts
//    as `factorization_cost` iterations); the constant part of the matrix (mass, bending) is
//    assembled once per step size. With `warp_preconditioner`, the stale factor A_old is applied as
//    Q A_old^-1 Q^T, Q the per-vertex rotations of the cloth since the factorization (exact for
//    rigid rotations, which otherwise make this anisotropic system's factor go stale fastest).
//  - refactor_every_step (default): a fresh numeric factorization every step (of the membrane
//    pattern, see membrane_pattern_preconditioner) and CG with it.
//  - pcg_jacobi: conjugate gradients with a diagonal preconditioner (baseline).
//
// Numerical safety: after every step positions and velocities must be finite, no triangle may flip
// (its normal turning by more than 90 degrees within the step), no vertex may exceed `max_speed`,
// and kinetic plus elastic energy may not grow by more than `energy_growth_limit` times (plus a
// floor of 10 J/kg of cloth mass). A failed step is rejected (counters().rejections by reason,
// counters().inverted_faces) and retried as two half steps, at most `max_step_halvings` deep; then
// NumericalError is thrown and the state restored. Triangles that still turn over after
// `max_fold_halvings` halvings are folds forced by contact: accepted and counted
// (counters().accepted_flips), since cloth may fold. With `fold_streaks`, the steps after one that
// accepted folds start at that depth until a step accepts none.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth/cloth_model.h"
#include "cloth/step_contact.h"

namespace gp::cloth {

enum class SolverStrategy { pcg_reused_factor, refactor_every_step, pcg_jacobi };

// Every strategy with its name in reports and options.
const std::vector<std::pair<SolverStrategy, const char*>>& solver_strategy_names();

struct SimulatorOptions {
  double dt = 0.01;  // time step [s]; the paper's 2.5 ms jerks the cloth through transitions (adapt/README.md)
  SolverStrategy strategy = SolverStrategy::refactor_every_step;
  // Relative residual |b - A v'| / |b| of the CG solve; bounds the velocity error by about tol h g
  // sqrt(#V) at rest under contact (cloth/README.md, "CG tolerance").
  double cg_tolerance = 1e-4;
  // Iteration cap of CG on a reused factor (and of pcg_jacobi); beyond it the factor is refreshed
  // and the solve finished with it: about twice a factorization's cost in iterations.
  int cg_max_iterations = 40;
  int fresh_factor_max_iterations = 200;  // cap of the constrained CG on a fresh factor
  double factorization_cost = 20.0;      // cost of one factorization in PCG iterations (refresh rule)
  bool warp_preconditioner = true;       // rotate the reused factor with the cloth's local frames
  int max_step_halvings = 4;             // retry depth on a rejected step
  int max_fold_halvings = 1;             // retry depth when only triangles turned over (then accepted)
  // After a step that accepted folds, start the next ones at that depth (two half steps for one
  // halving) until a step accepts none: a fold the body's contact forces lasts for many steps (an
  // arm closing on the torso), and each full step tried before its halves was thrown away
  // (cloth/README.md, "Fold streaks").
  bool fold_streaks = true;
  double max_speed = 20.0;               // m/s; faster vertices reject the step
  double energy_growth_limit = 10.0;     // rejects a step whose energy grows more than this
  // A contact constraint is released when the body would have to pull the vertex with more than
  // this many times its weight: above the solver's noise, so that cloth resting with a vanishing
  // contact force does not toggle (cloth/README.md, "Contact release").
  double contact_release_fraction = 20.0;
  // Stiffening kappa n n^T of constrained vertices in the factored preconditioner, relative to the
  // vertex's diagonal: large makes the factor exact while the contact set is unchanged, moderate
  // keeps it a good preconditioner as contacts come and go between factorizations.
  double constraint_preconditioner_stiffness = 100.0;
  // Factor only the membrane pattern (one-ring couplings): the bending couplings between the two
  // vertices opposite an edge (the two-ring fill, about 1e-3 of the membrane terms) are dropped and
  // their magnitudes added to the two diagonals (SPD, above A); CG makes up the difference. Where a
  // fresh membrane factor leaves CG short of the tolerance, or twice needs more than
  // membrane_max_iterations, the whole matrix is used for good (counters().membrane_fallbacks).
  bool membrane_pattern_preconditioner = true;
  // See membrane_pattern_preconditioner (counted in counters()). Well-shaped garments need 3-10
  // (cloth/README.md, "Membrane-pattern preconditioner").
  int membrane_max_iterations = 30;
};

// Wall time per phase [s], accumulated over steps.
struct PhaseTimes {
  double forces_assembly = 0.0;
  double factorization = 0.0;
  double solve = 0.0;
  double collisions = 0.0;
  double checks = 0.0;
  double total() const { return forces_assembly + factorization + solve + collisions + checks; }
};

// Why (sub)steps were rejected: one count per rejected attempt, for the first check that failed.
struct RejectionCounts {
  long solve_failed = 0;      // the linear solve threw (CHOLMOD, or CG did not converge)
  long non_finite = 0;        // positions or velocities not finite
  long too_fast = 0;          // a vertex above options.max_speed
  long inverted = 0;          // a triangle turned over within the step
  long energy_growth = 0;     // kinetic plus elastic energy grew beyond options.energy_growth_limit
  long total() const { return solve_failed + non_finite + too_fast + inverted + energy_growth; }
};

struct SolverCounters {
  long steps = 0;            // accepted calls to step()
  long substeps = 0;         // linear solves that were accepted (>= steps when halving)
  long rejected = 0;         // rejected (sub)steps
  RejectionCounts rejections;  // the rejected (sub)steps by reason (sums to `rejected`)
  // Per face, how often a rejected (sub)step found it inverted (#F once a step was rejected for
  // that, empty before): recurring faces point at a cause.
  std::vector<long> inverted_faces;
  long accepted_flips = 0;   // triangles that turned over even in the smallest substep (folds)
  long fold_streak_steps = 0;  // steps started halved because the one before accepted folds
  long factorizations = 0;
  long cg_iterations = 0;
  double last_residual = 0.0;  // relative residual of the last solve
  long constraints = 0;        // velocity constraints applied, summed over (sub)steps
  long released = 0;           // constraints released because the body pulled
  int last_cg_iterations = 0;
  long membrane_fallbacks = 0;  // membrane-pattern factors given up for the whole matrix (0 or 1)
  long slow_membrane_solves = 0;  // fresh membrane-pattern solves above options.membrane_max_iterations
};

// The faces of counters.inverted_faces that rejected (sub)steps found inverted, most often first
// (ties by face id), at most `count`: (face, rejections).
std::vector<std::pair<int, long>> most_inverted_faces(const SolverCounters& counters, int count);

class ClothSimulator {
 public:
  // Rest shape V_rest (also the initial positions, at rest) and faces F. Throws GeometryError /
  // InputError as build_rest_state.
  ClothSimulator(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                 const ClothParameters& params = {}, const SimulatorOptions& options = {});
  ~ClothSimulator();
  ClothSimulator(ClothSimulator&&) noexcept;
  ClothSimulator& operator=(ClothSimulator&&) noexcept;

  // New rest shape with the same connectivity (after adaptation); keeps the state.
  void set_rest_shape(const Eigen::MatrixXd& V_rest);
  // Per-face rest triangles replacing those of the rest shape (the flat pieces of a sewn pattern);
  // keeps the state. Throws as cloth::set_rest_triangles.
  void set_rest_triangles(const std::vector<TriangleRest>& triangles);
  // Pinned vertex ids (distinct, in range); their targets start at their positions.
  void set_pinned(const std::vector<int>& pinned_ids);
  // Positions the pinned vertices reach at the end of the next step (#pinned by 3, set_pinned's order).
  void set_pin_targets(const Eigen::MatrixXd& targets);
  void set_positions(const Eigen::MatrixXd& X);
  void set_velocities(const Eigen::MatrixXd& Vel);
  // The body the cloth meets in every (sub)step (step_contact.h), or none (nullptr). Not owned:
  // it must outlive the steps. Forgets the contact history of the one before.
  void set_contact(StepContact* contact);
  // Scales every damping coefficient (stretch, shear, bending) from the next step on; 1 restores
  // the material's. Relaxes the cloth to its static equilibrium while the body stands still.
  void set_damping_scale(double scale);

  // Advances by options().dt (possibly in halved substeps). Throws NumericalError when even the
  // smallest substep fails (state restored to before the call).
  void step();

  const Eigen::MatrixXd& positions() const;
  const Eigen::MatrixXd& velocities() const;
  const Eigen::MatrixXi& faces() const;
  const ClothRestState& rest_state() const;
  const ClothParameters& parameters() const;
  const SimulatorOptions& options() const;
  const std::vector<int>& pinned() const;
  const PhaseTimes& times() const;
  const SolverCounters& counters() const;
  // Largest vertex speed [m/s] of the current state.
  double max_speed() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::cloth
