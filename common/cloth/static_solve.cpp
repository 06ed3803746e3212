#include "cloth/static_solve.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <Eigen/Eigenvalues>

#include "cloth/contact_set.h"
#include "cloth/system_assembly.h"
#include "cloth/system_solver.h"
#include "core/error.h"
#include "core/stopwatch.h"

namespace gp::cloth {
namespace {

// Sufficient decrease of the line search (Nocedal & Wright, "Numerical Optimization", eq. 3.4).
constexpr double kArmijo = 1e-4;
constexpr int kMaxTrials = 40;
// A vertex that starts at or inside its comfort offset gets its wall this fraction of the band
// below where it is, so that the barrier is finite there and pushes it out.
constexpr double kStartBelowWall = 0.1;

// The body at one vertex of the current iterate.
struct VertexContact {
  double distance = std::numeric_limits<double>::infinity();  // signed distance [m]
  Eigen::Vector3d outward = Eigen::Vector3d::UnitY();
  double wall = -std::numeric_limits<double>::infinity();     // w [m]
  bool has_wall = false;  // the wall of the last iterate applies (the vertex was near the body)
  bool outside = false;   // outside the body at the iterate: a barrier per body triangle (StaticBody)
};

// The barrier of one vertex at p against the walls of `c`: adds its energy and, with `derivatives`,
// its gradient and Gauss-Newton Hessian (static_solve.h). False when p is at or behind the wall.
struct VertexBarrier {
  double energy = 0.0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  int terms = 0;  // distances within the band
};

// The symmetric 3x3 matrix with its negative eigenvalues set to zero.
Eigen::Matrix3d project_psd(const Eigen::Matrix3d& H) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (H + H.transpose()));
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace

double barrier_phi(double s) {
  if (s >= 1.0) return 0.0;
  if (!(s > 0.0)) return std::numeric_limits<double>::infinity();
  return -(s - 1.0) * (s - 1.0) * std::log(s);
}

double barrier_phi_d1(double s) {
  if (s >= 1.0) return 0.0;
  return -2.0 * (s - 1.0) * std::log(s) - (s - 1.0) * (s - 1.0) / s;
}

double barrier_phi_d2(double s) {
  if (s >= 1.0) return 0.0;
  return -2.0 * std::log(s) - 4.0 * (s - 1.0) / s + (s - 1.0) * (s - 1.0) / (s * s);
}

struct StaticSolver::Impl {
  StaticSolveOptions options;
  SystemAssembly system;
  std::optional<SystemSolver> solver;
  std::vector<int> pattern_pins;
  long pattern_vertices = -1;
  ContactSet no_constraints;  // contact is the barrier here, not a constraint
  SolverCounters counters;
  PhaseTimes times;
  double tau = -1.0;  // the pseudo time step the last solve ended with [s]

  void build_pattern(const ClothSimulator& sim) {
    if (solver && pattern_pins == sim.pinned() && pattern_vertices == sim.positions().rows()) return;
    system.build(sim.faces(), sim.rest_state().Q, static_cast<int>(sim.positions().rows()), sim.pinned());
    SimulatorOptions o = sim.options();
    // Every Newton matrix differs: a reused factor would be stale at once.
    o.strategy = SolverStrategy::refactor_every_step;
    solver.emplace(o);
    solver->reset(system, sim.faces());
    pattern_pins = sim.pinned();
    pattern_vertices = sim.positions().rows();
  }

  mutable std::vector<BodyFeature> features;  // work buffer of the body's feature query

  // One distance d within the band above the wall w: kappa a g phi(s), s = (d - w) / g, along the
  // unit direction u from the body to the vertex, the distance's curvature `curvature`.
  void add_term(double d, const Eigen::Vector3d& u, const Eigen::Matrix3d& curvature, double wall, double area,
                bool derivatives, VertexBarrier& b) const {
    const double g = options.barrier_band;
    const double sv = (d - wall) / g;
    if (sv >= 1.0) return;
    const double k = options.barrier_pressure * area;
    b.energy += k * g * barrier_phi(sv);
    ++b.terms;
    if (!derivatives) return;
    b.gradient += k * barrier_phi_d1(sv) * u;
    b.hessian += k * barrier_phi_d2(sv) / g * u * u.transpose() + k * barrier_phi_d1(sv) * curvature;
  }

  bool vertex_barrier(const StaticBody& body, int v, const Eigen::Vector3d& p, const VertexContact& c, double area,
                      bool derivatives, VertexBarrier& b) const {
    const double reach = c.wall + options.barrier_band;
    if (c.outside && body.features) {
      features.clear();
      body.features(p, reach, features);
      for (const BodyFeature& f : features) {
        const double d = (p - f.point).norm();
        if (!(d > c.wall)) return false;
        const Eigen::Vector3d u = (p - f.point) / d;
        Eigen::Matrix3d curvature = Eigen::Matrix3d::Zero();
        if (derivatives && f.kind > 0) {
          curvature = (Eigen::Matrix3d::Identity() - u * u.transpose()) / d;
          if (f.kind == 1) curvature -= f.edge * f.edge.transpose() / d;
        }
        add_term(d, u, curvature, c.wall, area, derivatives, b);
      }
      if (derivatives) b.hessian = project_psd(b.hessian);
      return true;
    }
    const BodyDistance q = body.distance(v, p, false);
    if (!(q.signed_distance > c.wall)) return false;
    add_term(q.signed_distance, q.outward, Eigen::Matrix3d::Zero(), c.wall, area, derivatives, b);
    return true;
  }

  // The body at the iterate X, and each free vertex's wall: the comfort offset (at most half the
  // room in a pinch), lower only where the vertex is not outside it yet.
  void update_walls(const StaticBody& body, const Eigen::MatrixXd& X, const Eigen::VectorXd& offsets,
                    const Eigen::VectorXi& free_id, std::vector<VertexContact>& contact) const {
    const double band = options.barrier_band;
    for (Eigen::Index v = 0; v < X.rows() && body.distance; ++v) {
      VertexContact& c = contact[static_cast<size_t>(v)];
      if (free_id(v) < 0) continue;
      const BodyDistance q = body.distance(static_cast<int>(v), X.row(v).transpose(), true);
      // The barrier's band straddles the comfort offset: cloth pressed onto the body rests near it
      // (s about 1/2), loose cloth lies on it, as the damped steps' hard offset holds them.
      double target = offsets(v);
      if (std::isfinite(q.room)) target = std::min(target, 0.5 * q.room);
      target -= 0.5 * band;
      c.distance = q.signed_distance;
      c.outward = q.outward;
      // The wall never falls (but with the target) and stays below the vertex: it rises to the
      // target as a vertex that started inside the offset is pushed out.
      const double previous = c.has_wall && c.wall < c.distance ? c.wall : -std::numeric_limits<double>::infinity();
      // Within a fifth of the band of the surface (or inside) the signed distance decides alone.
      c.outside = c.distance > 2.0 * kStartBelowWall * band;
      // Outside, the distances to the body's triangles are unsigned: the wall stays above the surface.
      const double floor = c.outside ? 0.5 * c.distance : -std::numeric_limits<double>::infinity();
      c.wall = std::min(target, std::max({previous, c.distance - kStartBelowWall * band, floor}));
      c.has_wall = true;
    }
  }

  // The largest fraction of the step (vertex step lengths `step_lengths`) that cannot carry a vertex
  // through the body: a vertex moving less than its distance to the wall stays in a ball free of it;
  // one that could reach it moves at most max_displacement, its end checked against the wall.
  double largest_safe_step(const StaticBody& body, const Eigen::VectorXd& step_lengths, const Eigen::VectorXi& free_id,
                           const std::vector<VertexContact>& contact) const {
    double alpha = 1.0;
    for (Eigen::Index v = 0; v < step_lengths.size(); ++v) {
      const double length = step_lengths(v);
      if (free_id(v) < 0 || length == 0.0) continue;
      const VertexContact& c = contact[static_cast<size_t>(v)];
      const double room = body.distance ? c.distance - c.wall : std::numeric_limits<double>::infinity();
      const double cap = std::max(0.9 * room, options.max_displacement);
      if (length > cap) alpha = std::min(alpha, cap / length);
    }
    return alpha;
  }

  // The barrier's energy at positions X over the vertices whose band they can have reached: `moved`
  // bounds how far each moved from where `contact` was measured. Infinity when a vertex is at or
  // behind its wall.
  double barrier_energy(const Eigen::MatrixXd& X, const Eigen::VectorXd& areas, const std::vector<VertexContact>& contact,
                        const Eigen::VectorXd& moved, const StaticBody& body) const {
    if (!body.distance) return 0.0;
    double e = 0.0;
    for (size_t v = 0; v < contact.size(); ++v) {
      const VertexContact& c = contact[v];
      const Eigen::Index i = static_cast<Eigen::Index>(v);
      if (!c.has_wall || c.distance - c.wall >= options.barrier_band + moved(i)) continue;
      VertexBarrier b;
      if (!vertex_barrier(body, static_cast<int>(v), X.row(i).transpose(), c, areas(i), false, b)) {
        return std::numeric_limits<double>::infinity();
      }
      e += b.energy;
    }
    return e;
  }
};

StaticSolver::StaticSolver(const StaticSolveOptions& options) : impl_(std::make_unique<Impl>()) {
  const StaticSolveOptions& o = options;
  if (!(o.tolerance > 0.0) || o.max_iterations < 0 || !(o.barrier_pressure > 0.0) || !(o.barrier_band > 0.0) ||
      !(o.max_displacement > 0.0) || !(o.min_step > 0.0) || !(o.initial_step >= o.min_step) ||
      !(o.max_step >= o.initial_step) || !std::isfinite(o.max_step)) {
    throw UsageError("static solve options: tolerance, pressure, band, displacement and steps must be positive, "
                     "min_step <= initial_step <= max_step (finite)");
  }
  impl_->options = options;
}

StaticSolver::~StaticSolver() = default;
StaticSolver::StaticSolver(StaticSolver&&) noexcept = default;
StaticSolver& StaticSolver::operator=(StaticSolver&&) noexcept = default;

const StaticSolveOptions& StaticSolver::options() const { return impl_->options; }
const PhaseTimes& StaticSolver::times() const { return impl_->times; }
const SolverCounters& StaticSolver::counters() const { return impl_->counters; }

StaticSolveReport StaticSolver::solve(const ClothSimulator& sim, const StaticBody& body,
                                      const Eigen::VectorXd& offsets, Eigen::MatrixXd& X) {
  restart();
  return resume(sim, body, offsets, X, impl_->options.max_iterations);
}

void StaticSolver::restart() { impl_->tau = impl_->options.initial_step; }

StaticSolveReport StaticSolver::resume(const ClothSimulator& sim, const StaticBody& body,
                                       const Eigen::VectorXd& offsets, Eigen::MatrixXd& X, int max_iterations) {
  Impl& s = *impl_;
  const StaticSolveOptions& o = s.options;
  if (max_iterations < 0) throw UsageError("static solve: the iteration cap must be non-negative");
  double& tau = s.tau;
  if (!(tau > 0.0)) tau = o.initial_step;
  const Eigen::MatrixXi& F = sim.faces();
  const ClothRestState& rest = sim.rest_state();
  const ClothParameters& params = sim.parameters();
  const Eigen::Index nv = sim.positions().rows();
  if (X.rows() != nv || X.cols() != 3) throw UsageError("static solve: positions must be #V by 3");
  if (offsets.size() != nv) throw UsageError("static solve: offsets must have one entry per vertex");
  if (!X.allFinite()) throw NumericalError("static solve: the starting positions are not finite");
  s.build_pattern(sim);
  s.system.invalidate_constant_part();  // the rest state may have changed since the last solve
  const Eigen::VectorXi& free_id = s.system.free_ids();

  // Units of the residual: the mean weight of a free vertex.
  double mass_sum = 0.0;
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (free_id(v) >= 0) mass_sum += rest.masses(v);
  }
  const double g_norm = params.gravity.norm() > 0.0 ? params.gravity.norm() : 9.81;
  const double weight = s.system.free_count() ? mass_sum / s.system.free_count() * g_norm : 1.0;
  const Eigen::VectorXd areas = rest.masses / params.density;
  const double band = o.barrier_band;

  StaticSolveReport report;
  std::vector<VertexContact> contact(static_cast<size_t>(nv));
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(nv, 3);
  Eigen::VectorXd sol, moved;
  Eigen::MatrixXd dx(nv, 3), grad(nv, 3);

  for (int iteration = 0;; ++iteration) {
    auto t0 = Clock::now();
    s.update_walls(body, X, offsets, free_id, contact);
    s.times.collisions += seconds_since(t0);
    t0 = Clock::now();
    s.system.assemble(X, zero, zero, F, rest, params, 0.0, tau);  // b = tau f
    s.times.forces_assembly += seconds_since(t0);
    t0 = Clock::now();
    double barrier = 0.0;
    int in_band = 0;
    for (Eigen::Index v = 0; v < nv && body.distance; ++v) {
      const VertexContact& c = contact[static_cast<size_t>(v)];
      if (free_id(v) < 0 || !(c.distance - c.wall < band)) continue;
      VertexBarrier b;
      if (!s.vertex_barrier(body, static_cast<int>(v), X.row(v).transpose(), c, areas(v), true, b)) {
        throw NumericalError("static solve: vertex " + std::to_string(v) + " is behind its wall at the iterate");
      }
      if (b.terms == 0) continue;
      ++in_band;
      barrier += b.energy;
      s.system.add_vertex_terms(static_cast<int>(v), tau * tau * b.hessian, -tau * b.gradient);
    }
    report.contacts = in_band;
    s.times.collisions += seconds_since(t0);
    t0 = Clock::now();

    // grad E of the free vertices: -b / tau.
    const Eigen::VectorXd& b = s.system.rhs();
    double sum_squares = 0.0;
    grad.setZero();
    for (Eigen::Index v = 0; v < nv; ++v) {
      const int fi = free_id(v);
      if (fi < 0) continue;
      grad.row(v) = -b.segment<3>(3 * fi).transpose() / tau;
      sum_squares += grad.row(v).squaredNorm();
    }
    const double residual = s.system.free_count() ? std::sqrt(sum_squares / s.system.free_count()) / weight : 0.0;
    report.residuals.push_back(residual);
    report.residual = residual;
    report.iterations = iteration;
    // The model's energy as the trial points' is computed (not the assembly's sum), so that the
    // line search compares like with like.
    const double energy = cloth_energies(X, F, rest, params).total() + barrier;
    report.energy = energy;
    s.times.forces_assembly += seconds_since(t0);
    if (residual < o.tolerance) {
      report.converged = true;
      break;
    }
    if (iteration >= max_iterations) break;

    sol.setZero(3 * s.system.free_count());
    s.solver->solve(s.system, s.no_constraints, X, F, sol, s.counters, s.times);
    dx.setZero();
    for (Eigen::Index v = 0; v < nv; ++v) {
      if (free_id(v) >= 0) dx.row(v) = tau * sol.segment<3>(3 * free_id(v)).transpose();
    }
    const double slope = (grad.array() * dx.array()).sum();  // < 0: the matrix is SPD
    const Eigen::VectorXd step_lengths = dx.rowwise().norm();

    const double alpha_max = s.largest_safe_step(body, step_lengths, free_id, contact);
    double alpha = alpha_max;

    t0 = Clock::now();
    bool accepted = false;
    Eigen::MatrixXd X_trial;
    for (int trial = 0; trial < kMaxTrials; ++trial) {
      X_trial = X + alpha * dx;
      moved = alpha * step_lengths;
      ++report.line_search_trials;
      const double e_barrier = s.barrier_energy(X_trial, areas, contact, moved, body);
      if (std::isfinite(e_barrier)) {
        const double e_trial = cloth_energies(X_trial, F, rest, params).total() + e_barrier;
        // Near the equilibrium the decrease is below the energy's rounding: a step the model
        // predicts to change E by less than that is taken as it is.
        const bool rounding = std::abs(slope) * alpha < 1e-13 * std::max(1.0, std::abs(energy));
        if (e_trial <= energy + kArmijo * alpha * slope || (rounding && e_trial <= energy + 1e-12 * std::abs(energy))) {
          accepted = true;
          break;
        }
      }
      alpha *= 0.5;
    }
    s.times.checks += seconds_since(t0);
    if (!accepted) {
      if (tau <= o.min_step) break;
      tau = std::max(0.25 * tau, o.min_step);
      continue;
    }
    X = std::move(X_trial);
    if (alpha == 1.0 && alpha_max == 1.0) {
      tau = std::min(2.0 * tau, o.max_step);
    } else if (alpha < 0.1 * alpha_max) {
      tau = std::max(0.25 * tau, o.min_step);
    }
  }
  return report;
}

}  // namespace gp::cloth
