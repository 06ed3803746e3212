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
// active_set: a vertex within this distance [m] above its level touches it (the line search's
// projection leaves vertices at the level up to rounding).
constexpr double kTouchTolerance = 1e-6;
// active_set: a second normal of a vertex in a crease is added when it is at least this far (the
// sine of the angle) from the first, from a body feature within this fraction of the band of the
// level. The time steps' 0.3 (ContactSet) is far too coarse here: on the demo's T-pose a vertex pressed
// with 1,150 vertex weights into a crease of 8 degrees (sine 0.15) met the second side at first
// order wherever it slid, and the line search found no descent for 500 iterations.
constexpr double kCreaseSine = 0.01;
constexpr double kCreaseBand = 0.1;

// The body at one vertex of the current iterate.
struct VertexContact {
  double distance = std::numeric_limits<double>::infinity();  // signed distance [m]
  Eigen::Vector3d outward = Eigen::Vector3d::UnitY();
  double wall = -std::numeric_limits<double>::infinity();     // w [m]
  bool has_wall = false;  // the wall of the last iterate applies (the vertex was near the body)
  bool outside = false;   // outside the body at the iterate: a barrier per body triangle (StaticBody)
  double level = -std::numeric_limits<double>::infinity();  // active_set: the offset held [m]
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

const std::vector<std::pair<StaticContact, const char*>>& static_contact_names() {
  static const std::vector<std::pair<StaticContact, const char*>> names = {{StaticContact::barrier, "barrier"},
                                                                           {StaticContact::active_set, "active_set"}};
  return names;
}

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
  ContactSet no_constraints;  // the barrier's solves: contact is no constraint there
  ContactSet held;            // active_set: the held vertices' constraints and their history
  std::vector<VelocityConstraint> candidates;  // work buffer of gather_held
  bool pushing = false;  // active_set: a held vertex below its level is pushed out in this iteration
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
      c.level = target;
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
      const double floor = options.contact == StaticContact::active_set ? c.level : c.wall;
      const double room = body.distance ? std::max(c.distance - floor, 0.0) : std::numeric_limits<double>::infinity();
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

  // The barrier's terms at the iterate X added to the system of pseudo time step `step` (Hessian
  // step^2 H, force step f); returns the barrier's energy [J] and sets `in_band`, the vertices within the band.
  double add_barrier(const StaticBody& body, const Eigen::MatrixXd& X, const Eigen::VectorXi& free_id,
                     const std::vector<VertexContact>& contact, const Eigen::VectorXd& areas, double step,
                     int& in_band) {
    double energy = 0.0;
    in_band = 0;
    for (Eigen::Index v = 0; v < X.rows() && body.distance; ++v) {
      const VertexContact& c = contact[static_cast<size_t>(v)];
      if (free_id(v) < 0 || !(c.distance - c.wall < options.barrier_band)) continue;
      VertexBarrier b;
      if (!vertex_barrier(body, static_cast<int>(v), X.row(v).transpose(), c, areas(v), true, b)) {
        throw NumericalError("static solve: vertex " + std::to_string(v) + " is behind its wall at the iterate");
      }
      if (b.terms == 0) continue;
      ++in_band;
      energy += b.energy;
      system.add_vertex_terms(static_cast<int>(v), step * step * b.hessian, -step * b.gradient);
    }
    return energy;
  }

  // The line search along dx from X at energy E (static_solve.h): from the largest safe step
  // `alpha_max`, halved until Armijo's decrease holds (active_set: at the projected trial points; a
  // step that pushes vertices out to their level is taken at once, since it is no descent). On
  // success X is the accepted trial point and `alpha` its fraction of dx.
  bool line_search(const StaticBody& body, const Eigen::MatrixXi& F, const ClothRestState& rest,
                   const ClothParameters& params, const Eigen::VectorXi& free_id,
                   const std::vector<VertexContact>& contact, const Eigen::VectorXd& areas,
                   const Eigen::MatrixXd& grad, const Eigen::MatrixXd& dx, double energy, Eigen::MatrixXd& X,
                   double& alpha, double& alpha_max, long& trials) const {
    const bool active_set = options.contact == StaticContact::active_set && static_cast<bool>(body.distance);
    const double slope = (grad.array() * dx.array()).sum();  // < 0 without pushes: the matrix is SPD
    const Eigen::VectorXd step_lengths = dx.rowwise().norm();
    alpha_max = largest_safe_step(body, step_lengths, free_id, contact);
    alpha = alpha_max;
    Eigen::MatrixXd X_trial;
    for (int trial = 0; trial < kMaxTrials; ++trial) {
      X_trial = X + alpha * dx;
      const Eigen::VectorXd moved = alpha * step_lengths;
      ++trials;
      double e_trial = std::numeric_limits<double>::infinity();
      if (active_set) {
        project_trial(body, X_trial, free_id, contact, moved);
        e_trial = cloth_energies(X_trial, F, rest, params).total();
      } else {
        const double e_barrier = barrier_energy(X_trial, areas, contact, moved, body);
        if (std::isfinite(e_barrier)) e_trial = cloth_energies(X_trial, F, rest, params).total() + e_barrier;
      }
      if (std::isfinite(e_trial)) {
        if (active_set && pushing) {
          X = std::move(X_trial);
          return true;
        }
        // Near the equilibrium the decrease is below the energy's rounding: a step the model
        // predicts to change E by less than that is taken as it is.
        const bool rounding = std::abs(slope) * alpha < 1e-13 * std::max(1.0, std::abs(energy));
        if (e_trial <= energy + kArmijo * alpha * slope || (rounding && e_trial <= energy + 1e-12 * std::abs(energy))) {
          X = std::move(X_trial);
          return true;
        }
      }
      alpha *= 0.5;
    }
    return false;
  }

  // active_set: the system's b without its components along the held normals.
  void take_held_normals_out_of_rhs() {
    for (size_t k = 0; k < held.size(); ++k) {
      const VelocityConstraint& c = held.constraint(k);
      const Eigen::Vector3d along = system.rhs().segment<3>(3 * held.free_index(k));
      system.add_vertex_terms(c.vertex, Eigen::Matrix3d::Zero(), -c.normal * c.normal.dot(along));
    }
  }

  // active_set: the vertices held (one or two constraints each, listed together).
  int held_vertices() const {
    int n = 0;
    for (size_t k = 0; k < held.size(); ++k) {
      if (k == 0 || held.constraint(k).vertex != held.constraint(k - 1).vertex) ++n;
    }
    return n;
  }

  // active_set: the held vertices' constraints at the iterate (static_solve.h) in `held`, from the
  // candidates at or near their level, the contact history deciding (ContactSet::gather). The
  // prescribed normal "velocity" is the displacement over the pseudo time step: sol = dx / step.
  void gather_held(const StaticBody& body, const Eigen::MatrixXd& X, const Eigen::VectorXi& free_id,
                   const std::vector<VertexContact>& contact, double step) {
    candidates.clear();
    for (Eigen::Index v = 0; v < X.rows() && body.distance; ++v) {
      const VertexContact& c = contact[static_cast<size_t>(v)];
      if (free_id(v) < 0 || !(c.distance - c.level < options.barrier_band)) continue;
      const auto candidate = [&](const Eigen::Vector3d& n, double d) {
        VelocityConstraint k;
        k.vertex = static_cast<int>(v);
        k.normal = n;
        // Out to the level, at most max_displacement at a time (a vertex that starts inside its
        // offset is pushed out gradually, as the barrier's rising wall does). A held vertex above
        // its level is never pulled towards the body: such a step is no descent where the cloth
        // pulls away, and the line search then found none (the demo's A-pose stalled at once).
        k.normal_velocity = std::clamp(c.level - d, 0.0, options.max_displacement) / step;
        k.touching = d <= c.level + kTouchTolerance;
        candidates.push_back(k);
      };
      candidate(c.outward, c.distance);
      if (!body.features || !(c.distance > 0.0)) continue;
      // In a crease the closest point's normal turns by a jump from one side to the other; the
      // feature most inclined to it at the level holds the vertex along the second side.
      const Eigen::Vector3d p = X.row(v).transpose();
      features.clear();
      body.features(p, c.level + options.barrier_band, features);
      double best_cos = 1.0, best_d = 0.0;
      Eigen::Vector3d best = Eigen::Vector3d::Zero();
      for (const BodyFeature& f : features) {
        const double d = (p - f.point).norm();
        if (!(d > 0.0) || !(d - c.level < kCreaseBand * options.barrier_band)) continue;
        const Eigen::Vector3d u = (p - f.point) / d;
        const double cosine = std::abs(u.dot(c.outward));
        if (cosine < best_cos) {
          best_cos = cosine;
          best = u;
          best_d = d;
        }
      }
      const double sine = std::sqrt(std::max(0.0, 1.0 - best_cos * best_cos));
      if (!(sine > kCreaseSine)) continue;
      // Made orthogonal to the first here (as ContactSet::gather would, which drops a second normal
      // within its own coarser angle): n2' = (n2 - d n1) / s, its displacement (l - d2 - d a1) / s.
      const VelocityConstraint first = candidates.back();
      const double along = best.dot(c.outward);
      candidate((best - along * c.outward) / sine, best_d);
      VelocityConstraint& second = candidates.back();
      second.normal_velocity = (second.normal_velocity - along * first.normal_velocity) / sine;
    }
    gather(static_cast<int>(X.rows()), free_id, step);
  }

  // The held set from the candidates, the contact history deciding; whether one is pushed out.
  void gather(int vertex_count, const Eigen::VectorXi& free_id, double step) {
    held.gather(candidates, vertex_count, free_id);
    pushing = false;
    for (size_t k = 0; k < held.size(); ++k) pushing = pushing || held.constraint(k).normal_velocity * step > kTouchTolerance;
  }

  // The release rule at the iterate: a held normal along which the vertex's force grad E pulls it
  // away from the body by more than `threshold` [N] is let go, and the set gathered again: the
  // vertex is released where that is the closest point's normal, only the crease's second normal
  // where that is the one (a vertex pressed into one side of a crease and pulled off the other).
  // Returns how many vertices were released. The multiplier estimate at the iterate, not the
  // step's Lagrange force: on the demo's A-pose the step's, from a solve to 1e-4, released vertices
  // that their force pressed onto the body with 10 vertex weights, every other iteration, and the
  // set never settled.
  long release_pulling(const Eigen::MatrixXd& grad, const Eigen::VectorXi& free_id, double threshold, double step) {
    std::vector<char> drop_all(static_cast<size_t>(grad.rows()), 0), drop_second(drop_all);
    long count = 0;
    bool any = false;
    for (size_t k = 0; k < held.size(); ++k) {
      const VelocityConstraint& c = held.constraint(k);
      if (!(grad.row(c.vertex).dot(c.normal.transpose()) < -threshold)) continue;
      const bool first = k == 0 || held.constraint(k - 1).vertex != c.vertex;
      char& flag = first ? drop_all[static_cast<size_t>(c.vertex)] : drop_second[static_cast<size_t>(c.vertex)];
      if (first && !flag) ++count;
      flag = 1;
      any = true;
    }
    if (!any) return 0;
    std::vector<VelocityConstraint> kept;
    kept.reserve(candidates.size());
    for (size_t q = 0; q < candidates.size(); ++q) {
      const int v = candidates[q].vertex;
      const bool second = q > 0 && candidates[q - 1].vertex == v;
      if (drop_all[static_cast<size_t>(v)] || (second && drop_second[static_cast<size_t>(v)])) continue;
      kept.push_back(candidates[q]);
    }
    candidates.swap(kept);
    gather(static_cast<int>(grad.rows()), free_id, step);
    return count;
  }

  // After the step: the vertices held in it are in contact for the next iteration; none is released
  // ahead (release_pulling decides at each iterate).
  void remember_held(int vertex_count) {
    ContactSet::History h;
    h.released.assign(static_cast<size_t>(vertex_count), 0);
    h.in_contact.assign(static_cast<size_t>(vertex_count), 0);
    for (size_t k = 0; k < held.size(); ++k) h.in_contact[static_cast<size_t>(held.constraint(k).vertex)] = 1;
    held.restore(std::move(h));
  }

  // active_set: moves every free vertex of the trial X that ended below its level (or, for one that
  // started inside it, below where its push this iteration takes it) out along the body's normal
  // there; `moved` bounds how far each moved from where `contact` was measured.
  void project_trial(const StaticBody& body, Eigen::MatrixXd& X, const Eigen::VectorXi& free_id,
                     const std::vector<VertexContact>& contact, const Eigen::VectorXd& moved) const {
    for (Eigen::Index v = 0; v < X.rows() && body.distance; ++v) {
      const VertexContact& c = contact[static_cast<size_t>(v)];
      if (free_id(v) < 0 || !(c.distance - c.level < moved(v) + kTouchTolerance)) continue;
      const double floor = std::min(c.level, c.distance + options.max_displacement);
      const BodyDistance q = body.distance(static_cast<int>(v), X.row(v).transpose(), false);
      if (q.signed_distance < floor) X.row(v) += (floor - q.signed_distance) * q.outward.transpose();
    }
  }

  // The force residual's gradient: grad E with, at each held vertex, the part pressing it onto the
  // body left out (the body bears it).
  void leave_out_borne(Eigen::MatrixXd& G, const Eigen::VectorXi& free_id) const {
    std::vector<int> vertex_of(static_cast<size_t>(free_id.maxCoeff() + 1), -1);
    for (Eigen::Index v = 0; v < free_id.size(); ++v) {
      if (free_id(v) >= 0) vertex_of[static_cast<size_t>(free_id(v))] = static_cast<int>(v);
    }
    for (size_t k = 0; k < held.size(); ++k) {
      const int v = vertex_of[static_cast<size_t>(held.free_index(k))];
      const Eigen::Vector3d& n = held.constraint(k).normal;
      const double pressing = G.row(v).dot(n.transpose());  // grad E along n > 0: the force is into the body
      if (pressing > 0.0) G.row(v) -= pressing * n.transpose();
    }
  }
};

StaticSolver::StaticSolver(const StaticSolveOptions& options) : impl_(std::make_unique<Impl>()) {
  const StaticSolveOptions& o = options;
  if (!(o.tolerance > 0.0) || o.max_iterations < 0 || !(o.barrier_pressure > 0.0) || !(o.barrier_band > 0.0) ||
      !(o.max_displacement > 0.0) || !(o.min_step > 0.0) || !(o.initial_step >= o.min_step) ||
      !(o.max_step >= o.initial_step) || !std::isfinite(o.max_step) || !(o.release_force >= 0.0)) {
    throw UsageError("static solve options: tolerance, pressure, band, displacement and steps must be positive, "
                     "min_step <= initial_step <= max_step (finite), the release force non-negative");
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

void StaticSolver::restart() {
  impl_->tau = impl_->options.initial_step;
  impl_->held.clear_history();
}

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
  const bool active_set = o.contact == StaticContact::active_set && static_cast<bool>(body.distance);

  // Units of the residual: the mean weight of a free vertex.
  double mass_sum = 0.0;
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (free_id(v) >= 0) mass_sum += rest.masses(v);
  }
  const double g_norm = params.gravity.norm() > 0.0 ? params.gravity.norm() : 9.81;
  const int free_count = s.system.free_count();
  const double weight = free_count ? mass_sum / free_count * g_norm : 1.0;
  const Eigen::VectorXd areas = rest.masses / params.density;

  StaticSolveReport report;
  std::vector<VertexContact> contact(static_cast<size_t>(nv));
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(nv, 3);
  Eigen::VectorXd sol;
  Eigen::MatrixXd dx(nv, 3), grad(nv, 3);

  for (int iteration = 0;; ++iteration) {
    auto t0 = Clock::now();
    s.update_walls(body, X, offsets, free_id, contact);
    if (active_set) s.gather_held(body, X, free_id, contact, tau);
    s.times.collisions += seconds_since(t0);
    t0 = Clock::now();
    s.system.assemble(X, zero, zero, F, rest, params, 0.0, tau);  // b = tau f
    s.times.forces_assembly += seconds_since(t0);
    t0 = Clock::now();
    const double barrier = active_set ? 0.0 : s.add_barrier(body, X, free_id, contact, areas, tau, report.contacts);
    s.times.collisions += seconds_since(t0);
    t0 = Clock::now();

    // grad E of the free vertices: -b / tau.
    const Eigen::VectorXd& b = s.system.rhs();
    grad.setZero();
    for (Eigen::Index v = 0; v < nv; ++v) {
      const int fi = free_id(v);
      if (fi >= 0) grad.row(v) = -b.segment<3>(3 * fi).transpose() / tau;
    }
    if (active_set) report.released += s.release_pulling(grad, free_id, o.release_force * weight, tau);
    if (active_set) report.contacts = s.held_vertices();
    Eigen::MatrixXd unbalanced = grad;
    if (active_set) s.leave_out_borne(unbalanced, free_id);
    double sum_squares = 0.0;
    for (Eigen::Index v = 0; v < nv; ++v) sum_squares += unbalanced.row(v).squaredNorm();
    const double residual = free_count ? std::sqrt(sum_squares / free_count) / weight : 0.0;
    report.residuals.push_back(residual);
    report.residual = residual;
    report.iterations = iteration;
    // The model's energy as the trial points' is computed (not the assembly's sum), so that the
    // line search compares like with like.
    const double energy = cloth_energies(X, F, rest, params).total() + barrier;
    report.energy = energy;
    s.times.forces_assembly += seconds_since(t0);
    // A vertex still below its level is not at rest yet, whatever the forces.
    if (residual < o.tolerance && !(active_set && s.pushing)) {
      report.converged = true;
      break;
    }
    if (iteration >= max_iterations) break;

    sol.setZero(3 * free_count);
    const ContactSet& constraints = active_set ? s.held : s.no_constraints;
    // The body's push on the held normals stays in b while the free forces vanish towards the
    // equilibrium; CG measures its tolerance relative to |b|, so those components, which the
    // filtered solve never reads, are taken out of it (else it stops at once, at sol = 0, with the
    // free forces below 1e-4 of the push).
    if (active_set) s.take_held_normals_out_of_rhs();
    s.solver->solve(s.system, constraints, X, F, sol, s.counters, s.times);
    ContactSet::History history_before;
    if (active_set) {
      history_before = s.held.history();
      s.remember_held(static_cast<int>(nv));
    }
    dx.setZero();
    for (Eigen::Index v = 0; v < nv; ++v) {
      if (free_id(v) >= 0) dx.row(v) = tau * sol.segment<3>(3 * free_id(v)).transpose();
    }
    t0 = Clock::now();
    double alpha = 0.0, alpha_max = 0.0;
    const bool accepted = s.line_search(body, F, rest, params, free_id, contact, areas, grad, dx, energy, X, alpha,
                                        alpha_max, report.line_search_trials);
    s.times.checks += seconds_since(t0);
    if (!accepted) {
      if (active_set) s.held.restore(std::move(history_before));
      if (tau <= o.min_step) break;
      tau = std::max(0.25 * tau, o.min_step);
      continue;
    }
    if (alpha == 1.0 && alpha_max == 1.0) {
      tau = std::min(2.0 * tau, o.max_step);
    } else if (alpha < 0.1 * alpha_max) {
      tau = std::max(0.25 * tau, o.min_step);
    }
  }
  return report;
}

}  // namespace gp::cloth
