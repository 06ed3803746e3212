#include "cloth/cloth_simulator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "cloth/contact_set.h"
#include "cloth/step_validation.h"
#include "cloth/system_assembly.h"
#include "cloth/system_solver.h"
#include "core/error.h"
#include "core/stopwatch.h"

namespace gp::cloth {

const std::vector<std::pair<SolverStrategy, const char*>>& solver_strategy_names() {
  static const std::vector<std::pair<SolverStrategy, const char*>> names = {
      {SolverStrategy::pcg_reused_factor, "pcg_reused_factor"},
      {SolverStrategy::refactor_every_step, "refactor_every_step"},
      {SolverStrategy::pcg_jacobi, "pcg_jacobi"}};
  return names;
}

std::vector<std::pair<int, long>> most_inverted_faces(const SolverCounters& counters, int count) {
  std::vector<std::pair<int, long>> faces;
  for (size_t f = 0; f < counters.inverted_faces.size(); ++f) {
    if (counters.inverted_faces[f] > 0) faces.emplace_back(static_cast<int>(f), counters.inverted_faces[f]);
  }
  std::stable_sort(faces.begin(), faces.end(),
                   [](const std::pair<int, long>& a, const std::pair<int, long>& b) { return a.second > b.second; });
  if (faces.size() > static_cast<size_t>(std::max(count, 0))) faces.resize(static_cast<size_t>(std::max(count, 0)));
  return faces;
}

// The state of the simulation and the step driver: assembly (system_assembly.h),
// linear solve (system_solver.h), contacts (contact_set.h) and the step checks
// (step_validation.h) are each their own part.
struct ClothSimulator::Impl {
  explicit Impl(const SimulatorOptions& o) : options(o), solver(o) {}

  Eigen::MatrixXd V_rest, X, Vel;
  Eigen::MatrixXi F;
  ClothParameters params;
  SimulatorOptions options;
  ClothRestState rest;

  std::vector<int> pinned_ids;
  Eigen::MatrixXd pin_targets;  // #pinned by 3
  double damping_scale = 1.0;

  SystemAssembly system;
  SystemSolver solver;
  ContactSet contacts;

  StepContact* body = nullptr;  // set_contact
  std::vector<VelocityConstraint> candidates;  // work buffer of body->constraints
  PhaseTimes times;
  SolverCounters counters;

  Eigen::MatrixXd V_prescribed;  // work buffer
  Eigen::VectorXd sol;           // the solved velocities of the free vertices (3 #free)
  std::string last_failure;      // the detail of the last rejection, for the error message
  bool in_fold_streak = false;   // the last step accepted folds (SimulatorOptions::fold_streaks)

  // A new pin set: the system's pattern and the solver's.
  void build_pattern() {
    system.build(F, rest.Q, static_cast<int>(X.rows()), pinned_ids);
    solver.reset(system, F);
  }

  // Solves the step's system from the current velocities.
  void solve_system() {
    const Eigen::VectorXi& free_id = system.free_ids();
    sol.resize(3 * system.free_count());
    for (int v = 0; v < X.rows(); ++v) {
      if (free_id(v) >= 0) sol.segment<3>(3 * free_id(v)) = Vel.row(v).transpose();
    }
    solver.solve(system, contacts, X, F, sol, counters, times);
  }

  // One linearized implicit Euler step of size h, kept only if accepted.
  // [s_start, s_end]: the part of the step this (sub)step covers.
  StepOutcome single_step(double h, const Eigen::MatrixXd& pin_end, bool accept_flips, double s_start, double s_end) {
    const Eigen::VectorXi& free_id = system.free_ids();
    auto t0 = Clock::now();
    V_prescribed.setZero(X.rows(), 3);
    for (size_t k = 0; k < pinned_ids.size(); ++k) {
      const int v = pinned_ids[k];
      V_prescribed.row(v) = (pin_end.row(k) - X.row(v)) / h;
    }
    const double energy_before =
        system.assemble(X, Vel, V_prescribed, F, rest, params, damping_scale, h) + kinetic_energy(Vel, rest.masses);
    times.forces_assembly += seconds_since(t0);
    t0 = Clock::now();
    candidates.clear();
    if (body) body->constraints(X, h, candidates);
    counters.constraints += contacts.gather(candidates, static_cast<int>(X.rows()), free_id);
    times.collisions += seconds_since(t0);
    try {
      solve_system();
    } catch (const NumericalError& e) {
      solver.invalidate();
      StepOutcome failed;
      failed.rejection = Rejection::solve_failed;
      failed.detail = std::string("linear solve failed: ") + e.what();
      return failed;
    }
    ContactSet::History history_before = contacts.history();
    counters.released += contacts.update_released(system.matrix(), sol, system.rhs(), rest.masses,
                                                  params.gravity.norm(), options.contact_release_fraction, h,
                                                  static_cast<int>(X.rows()));

    t0 = Clock::now();
    Eigen::MatrixXd X_new = X, V_new = V_prescribed;
    for (int v = 0; v < X.rows(); ++v) {
      const int fi = free_id(v);
      if (fi >= 0) V_new.row(v) = sol.segment<3>(3 * fi).transpose();
    }
    X_new += h * V_new;
    for (size_t k = 0; k < pinned_ids.size(); ++k) X_new.row(pinned_ids[k]) = pin_end.row(k);
    times.checks += seconds_since(t0);

    if (body) {
      t0 = Clock::now();
      const Eigen::MatrixXd X_solved = X_new;
      body->project(X_new, V_new);
      body->sweep(X, X_new, s_start, s_end);
      // A vertex the body moved gets the velocity of its actual displacement
      // over the step (the velocity update of position-based dynamics, Mueller
      // et al. 2007, "Position based dynamics", sec. 3.1): keeping the solved
      // velocity left vertices pressed into a concave part of the body (an
      // armpit crease, where the contact constraint blocks one normal and the
      // projection another) with a velocity they never moved at, pushed back
      // every step (cloth/README.md, "Contacts").
      for (int v = 0; v < X.rows(); ++v) {
        if (free_id(v) >= 0 && X_new.row(v) != X_solved.row(v)) V_new.row(v) = (X_new.row(v) - X.row(v)) / h;
      }
      for (size_t k = 0; k < pinned_ids.size(); ++k) {
        X_new.row(pinned_ids[k]) = pin_end.row(k);
        V_new.row(pinned_ids[k]) = V_prescribed.row(pinned_ids[k]);
      }
      times.collisions += seconds_since(t0);
    }

    t0 = Clock::now();
    StepOutcome outcome = validate_step(X, X_new, V_new, F, rest, params, options, energy_before, accept_flips);
    counters.accepted_flips += outcome.accepted_folds;
    times.checks += seconds_since(t0);
    if (!outcome.accepted()) {
      contacts.restore(std::move(history_before));
      return outcome;
    }
    X = std::move(X_new);
    Vel = std::move(V_new);
    ++counters.substeps;
    return outcome;
  }

  bool advance(double h, const Eigen::MatrixXd& pin_start, const Eigen::MatrixXd& pin_end, int depth, double s_start,
               double s_end) {
    const Eigen::MatrixXd X_saved = X, V_saved = Vel;
    const StepOutcome outcome = single_step(
        h, pin_end, depth >= std::min(options.max_step_halvings, options.max_fold_halvings), s_start, s_end);
    if (outcome.accepted()) return true;
    ++counters.rejected;
    ++count_of(counters.rejections, outcome.rejection);
    if (outcome.rejection == Rejection::inverted) {
      counters.inverted_faces.resize(F.rows(), 0);
      for (int f : outcome.flipped_faces) ++counters.inverted_faces[f];
    }
    X = X_saved;
    Vel = V_saved;
    last_failure = outcome.detail;
    if (depth >= options.max_step_halvings) return false;
    return advance_from(h, pin_start, pin_end, depth, depth + 1, s_start, s_end);  // its two halves
  }

  // The step at `depth` split into halves down to `start_depth` up front, each part attempted
  // (and retried) by advance() at that depth.
  bool advance_from(double h, const Eigen::MatrixXd& pin_start, const Eigen::MatrixXd& pin_end, int depth,
                    int start_depth, double s_start, double s_end) {
    if (depth >= start_depth) return advance(h, pin_start, pin_end, depth, s_start, s_end);
    const Eigen::MatrixXd pin_mid = 0.5 * (pin_start + pin_end);
    const double s_mid = 0.5 * (s_start + s_end);
    return advance_from(0.5 * h, pin_start, pin_mid, depth + 1, start_depth, s_start, s_mid) &&
           advance_from(0.5 * h, pin_mid, pin_end, depth + 1, start_depth, s_mid, s_end);
  }
};

ClothSimulator::ClothSimulator(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                               const ClothParameters& params, const SimulatorOptions& options)
    : impl_(std::make_unique<Impl>(options)) {
  if (!(options.dt > 0.0)) throw UsageError("time step must be positive");
  impl_->V_rest = V_rest;
  impl_->F = F;
  impl_->params = params;
  impl_->rest = build_rest_state(V_rest, F, params);
  impl_->X = V_rest;
  impl_->Vel = Eigen::MatrixXd::Zero(V_rest.rows(), 3);
  impl_->pin_targets.resize(0, 3);
  impl_->build_pattern();
}

ClothSimulator::~ClothSimulator() = default;
ClothSimulator::ClothSimulator(ClothSimulator&&) noexcept = default;
ClothSimulator& ClothSimulator::operator=(ClothSimulator&&) noexcept = default;

void ClothSimulator::set_rest_shape(const Eigen::MatrixXd& V_rest) {
  if (V_rest.rows() != impl_->V_rest.rows() || V_rest.cols() != 3) {
    throw UsageError("new rest shape must have the same vertex count");
  }
  ClothRestState rest = impl_->rest;
  update_rest_state(V_rest, impl_->F, impl_->params, rest);
  // Same connectivity, so Q keeps its pattern and the value indices stay valid.
  impl_->rest = std::move(rest);
  impl_->V_rest = V_rest;
  impl_->system.invalidate_constant_part();
}

void ClothSimulator::set_rest_triangles(const std::vector<TriangleRest>& triangles) {
  ClothRestState rest = impl_->rest;
  cloth::set_rest_triangles(triangles, impl_->F, impl_->params, rest);
  impl_->rest = std::move(rest);
  impl_->system.invalidate_constant_part();
}

void ClothSimulator::set_pinned(const std::vector<int>& pinned_ids) {
  std::vector<int> sorted = pinned_ids;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
    throw UsageError("pinned vertex ids must be distinct");
  }
  for (int v : pinned_ids) {
    if (v < 0 || v >= impl_->X.rows()) throw UsageError("pinned vertex id out of range");
  }
  impl_->pinned_ids = pinned_ids;
  impl_->pin_targets.resize(pinned_ids.size(), 3);
  for (size_t k = 0; k < pinned_ids.size(); ++k) impl_->pin_targets.row(k) = impl_->X.row(pinned_ids[k]);
  impl_->build_pattern();
}

void ClothSimulator::set_pin_targets(const Eigen::MatrixXd& targets) {
  if (targets.rows() != static_cast<Eigen::Index>(impl_->pinned_ids.size()) || targets.cols() != 3) {
    throw UsageError("pin targets must be #pinned by 3");
  }
  impl_->pin_targets = targets;
}

void ClothSimulator::set_positions(const Eigen::MatrixXd& X) {
  if (X.rows() != impl_->X.rows() || X.cols() != 3) throw UsageError("positions must be #V by 3");
  impl_->X = X;
  for (size_t k = 0; k < impl_->pinned_ids.size(); ++k) impl_->pin_targets.row(k) = X.row(impl_->pinned_ids[k]);
  impl_->in_fold_streak = false;  // another state: its folds are not the last step's
}

void ClothSimulator::set_velocities(const Eigen::MatrixXd& Vel) {
  if (Vel.rows() != impl_->X.rows() || Vel.cols() != 3) throw UsageError("velocities must be #V by 3");
  impl_->Vel = Vel;
}

void ClothSimulator::set_contact(StepContact* contact) {
  impl_->body = contact;
  impl_->contacts.clear_history();
}

void ClothSimulator::set_damping_scale(double scale) {
  if (!(scale >= 0.0) || !std::isfinite(scale)) throw UsageError("damping scale must be finite and non-negative");
  if (scale == impl_->damping_scale) return;
  impl_->damping_scale = scale;
  impl_->system.invalidate_constant_part();
}

void ClothSimulator::step() {
  Impl& s = *impl_;
  const Eigen::MatrixXd X0 = s.X, V0 = s.Vel;
  Eigen::MatrixXd pin_start(s.pinned_ids.size(), 3);
  for (size_t k = 0; k < s.pinned_ids.size(); ++k) pin_start.row(k) = s.X.row(s.pinned_ids[k]);
  // A fold streak: the step before accepted folds, which the halves of a full step tried first
  // would have done again (cloth/README.md, "Fold streaks").
  const int fold_depth = std::min(s.options.max_step_halvings, s.options.max_fold_halvings);
  const int start_depth = s.options.fold_streaks && s.in_fold_streak ? fold_depth : 0;
  if (start_depth > 0) ++s.counters.fold_streak_steps;
  const long folds_before = s.counters.accepted_flips;
  if (!s.advance_from(s.options.dt, pin_start, s.pin_targets, 0, start_depth, 0.0, 1.0)) {
    s.X = X0;
    s.Vel = V0;
    s.in_fold_streak = false;
    throw NumericalError("cloth step failed after " + std::to_string(s.options.max_step_halvings) +
                             " halvings of the time step: " + s.last_failure,
                         "step " + std::to_string(s.counters.steps));
  }
  s.in_fold_streak = s.counters.accepted_flips > folds_before;
  ++s.counters.steps;
}

const Eigen::MatrixXd& ClothSimulator::positions() const { return impl_->X; }
const Eigen::MatrixXd& ClothSimulator::velocities() const { return impl_->Vel; }
const Eigen::MatrixXi& ClothSimulator::faces() const { return impl_->F; }
const ClothRestState& ClothSimulator::rest_state() const { return impl_->rest; }
const ClothParameters& ClothSimulator::parameters() const { return impl_->params; }
const SimulatorOptions& ClothSimulator::options() const { return impl_->options; }
const std::vector<int>& ClothSimulator::pinned() const { return impl_->pinned_ids; }
const PhaseTimes& ClothSimulator::times() const { return impl_->times; }
const SolverCounters& ClothSimulator::counters() const { return impl_->counters; }

double ClothSimulator::max_speed() const {
  return impl_->Vel.rows() ? impl_->Vel.rowwise().norm().maxCoeff() : 0.0;
}

}  // namespace gp::cloth
