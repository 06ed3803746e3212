#include "cloth/system_solver.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/stopwatch.h"

namespace gp::cloth {

struct SystemSolver::Solve {
  const Eigen::SparseMatrix<double>& A;
  const Eigen::VectorXd& b;
  const SystemAssembly& system;
  const ContactSet& contacts;
  const Eigen::MatrixXd& X;
  const Eigen::MatrixXi& F;
  Eigen::VectorXd& sol;
  SolverCounters& counters;
  PhaseTimes& times;
};

SystemSolver::SystemSolver(const SimulatorOptions& options)
    : options_(options), membrane_active_(options.membrane_pattern_preconditioner) {}

void SystemSolver::reset(const SystemAssembly& system, const Eigen::MatrixXi& F) {
  const Eigen::SparseMatrix<double>& A = system.matrix();
  const Eigen::VectorXi& free_id = system.free_ids();
  n_free_ = system.free_count();
  const int n = 3 * n_free_;
  // P: A's pattern restricted to vertex pairs that share a face (the membrane's
  // one-ring), and the maps from A's entries into it.
  std::vector<std::vector<int>> ring(n_free_);
  for (int f = 0; f < F.rows(); ++f) {
    for (int li = 0; li < 3; ++li) {
      for (int lj = 0; lj < 3; ++lj) {
        const int fi = free_id(F(f, li)), fj = free_id(F(f, lj));
        if (fi >= 0 && fj >= 0) ring[fi].push_back(fj);
      }
    }
  }
  for (auto& neighbours : ring) {
    std::sort(neighbours.begin(), neighbours.end());
    neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
  }
  auto shares_face = [&ring](int fi, int fj) { return std::binary_search(ring[fi].begin(), ring[fi].end(), fj); };
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(A.nonZeros());
  for (int col = 0; col < n; ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it) {
      const int row = static_cast<int>(it.row());
      if (row == col || shares_face(row / 3, col / 3)) triplets.emplace_back(row, col, 0.0);
    }
  }
  P_.resize(n, n);
  P_.setFromTriplets(triplets.begin(), triplets.end());
  P_.makeCompressed();
  p_position_.assign(A.nonZeros(), -1);
  p_diagonal_row_.assign(A.nonZeros(), -1);
  p_diagonal_col_.assign(A.nonZeros(), -1);
  for (int col = 0; col < n; ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it) {
      const int q = static_cast<int>(&it.value() - A.valuePtr());
      const int row = static_cast<int>(it.row());
      p_position_[q] = entry_index(P_, row, col);
      if (p_position_[q] < 0) {
        p_diagonal_row_[q] = entry_index(P_, row, row);
        p_diagonal_col_[q] = entry_index(P_, col, col);
      }
    }
  }
  neighbour_ids_ = Eigen::VectorXi::Constant(free_id.size(), -1);
  for (int f = F.rows() - 1; f >= 0; --f) {
    for (int k = 0; k < 3; ++k) neighbour_ids_(F(f, k)) = F(f, (k + 1) % 3);
  }
  factor_valid_ = false;
  refresh_needed_ = true;
}

// Per-vertex orthonormal frames [t, n x t, n] of positions X: n the (area
// weighted) vertex normal, t the direction to a fixed neighbour projected into
// the tangent plane. Used to rotate a stale factor along with the cloth.
void SystemSolver::vertex_frames(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F,
                                 std::vector<Eigen::Matrix3d>& frames) const {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(X.rows(), 3);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::RowVector3d x0 = X.row(F(f, 0)), x1 = X.row(F(f, 1)), x2 = X.row(F(f, 2));
    const Eigen::RowVector3d n = (x1 - x0).cross(x2 - x0);
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n;
  }
  frames.resize(X.rows());
  for (int v = 0; v < X.rows(); ++v) {
    Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
    const double ln = N.row(v).norm();
    const int neighbour = neighbour_ids_(v);
    if (ln > 0.0 && neighbour >= 0) {
      const Eigen::Vector3d n = N.row(v).transpose() / ln;
      Eigen::Vector3d t = (X.row(neighbour) - X.row(v)).transpose();
      t -= t.dot(n) * n;
      const double lt = t.norm();
      if (lt > 0.0) {
        t /= lt;
        B.col(0) = t;
        B.col(1) = n.cross(t);
        B.col(2) = n;
      }
    }
    frames[v] = B;
  }
}

// The factored matrix: A plus, for the constrained vertices, a stiff
// kappa n n^T on their diagonal blocks. As kappa grows, S (A + kappa N)^-1 S
// tends to the inverse of the filtered system on the unconstrained subspace,
// so the factor stays an accurate preconditioner for the filtered CG.
void SystemSolver::factorize(const Solve& s) {
  const auto t0 = Clock::now();
  if (s.contacts.empty() && !membrane_active_) {
    solver_.factorize(s.A);
  } else {
    // The matrix to factor: P, refilled from A at every factorization and so
    // stiffened in place, or a copy of A.
    Eigen::SparseMatrix<double>* factored = &P_;
    if (membrane_active_) {
      // Dropped entries go to both diagonals by magnitude: P - A is then
      // diagonally dominant, so P >= A > 0.
      P_.coeffs().setZero();
      double* pv = P_.valuePtr();
      const double* av = s.A.valuePtr();
      for (Eigen::Index q = 0; q < s.A.nonZeros(); ++q) {
        if (p_position_[q] >= 0) {
          pv[p_position_[q]] += av[q];
        } else {
          pv[p_diagonal_row_[q]] += std::abs(av[q]);
          pv[p_diagonal_col_[q]] += std::abs(av[q]);
        }
      }
    } else {
      A_factored_ = s.A;
      factored = &A_factored_;
    }
    double* vals = factored->valuePtr();
    for (size_t k = 0; k < s.contacts.size(); ++k) {
      const int fi = s.contacts.free_index(k);
      const Eigen::Vector3d& n = s.contacts.constraint(k).normal;
      double diagonal = 0.0;
      for (int a = 0; a < 3; ++a) diagonal += vals[entry_index(*factored, 3 * fi + a, 3 * fi + a)];
      const double kappa = options_.constraint_preconditioner_stiffness * diagonal / 3.0;
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c <= a; ++c) vals[entry_index(*factored, 3 * fi + a, 3 * fi + c)] += kappa * n(a) * n(c);
      }
    }
    solver_.factorize(*factored);
  }
  // The frames rotate a factor reused over later steps (update_warp); a
  // factor made for one step only needs none.
  if (options_.warp_preconditioner && options_.strategy == SolverStrategy::pcg_reused_factor) {
    vertex_frames(s.X, s.F, frames_at_factor_);
  }
  s.times.factorization += seconds_since(t0);
  ++s.counters.factorizations;
  factor_valid_ = true;
  factor_h_ = s.system.step_size();
  refresh_needed_ = false;
  iterations_since_factor_ = 0;
  steps_since_factor_ = 0;
}

void SystemSolver::apply_factor(const Eigen::VectorXd& in, Eigen::VectorXd& out) {
  rhs_buffer_ = in;
  if (warp_active_) {
    // P^-1 = Q A_old^-1 Q^T with Q = blockdiag(R_i): under a rigid rotation of
    // the cloth the system matrix transforms exactly like this (every term is
    // rotation invariant and the mass isotropic), so the stale factor follows
    // the cloth's local rotations instead of going stale with them.
    for (int i = 0; i < n_free_; ++i) rhs_buffer_.block<3, 1>(3 * i, 0) = warp_[i].transpose() * in.segment<3>(3 * i);
    solver_.solve(rhs_buffer_, sol_buffer_);
    out.resize(in.size());
    for (int i = 0; i < n_free_; ++i) out.segment<3>(3 * i) = warp_[i] * sol_buffer_.block<3, 1>(3 * i, 0);
    return;
  }
  solver_.solve(rhs_buffer_, sol_buffer_);
  out = sol_buffer_.col(0);
}

// Rotations R_i = B_now B_at_factor^T of the free vertices' frames.
void SystemSolver::update_warp(const Solve& s) {
  warp_active_ = false;
  if (!options_.warp_preconditioner || steps_since_factor_ == 0 || frames_at_factor_.empty()) return;
  std::vector<Eigen::Matrix3d> now;
  vertex_frames(s.X, s.F, now);
  warp_.resize(n_free_);
  for (int v = 0; v < s.X.rows(); ++v) {
    const int fi = s.system.free_ids()(v);
    if (fi >= 0) warp_[fi] = now[v] * frames_at_factor_[v].transpose();
  }
  warp_active_ = true;
}

// Preconditioned conjugate gradients on A sol = b from the current sol.
// `precondition` applies M^-1. Returns iterations; sets counters.last_residual.
template <class Precondition>
int SystemSolver::pcg(const Solve& s, Precondition precondition, int max_iterations, bool& converged) {
  const auto Asym = s.A.selfadjointView<Eigen::Lower>();
  const double b_norm = std::max(s.b.norm(), 1e-300);
  // Filtered CG (Baraff & Witkin 1998, sec. 5.3): residuals and directions stay
  // in the unconstrained subspace, the constrained components keep their
  // prescribed values.
  s.contacts.impose(s.sol);
  r_ = s.b - Asym * s.sol;
  s.contacts.filter(r_);
  double res = r_.norm() / b_norm;
  int it = 0;
  converged = res <= options_.cg_tolerance;
  if (!converged) {
    precondition(r_, z_);
    s.contacts.filter(z_);
    p_ = z_;
    double rz = r_.dot(z_);
    while (it < max_iterations) {
      Ap_.noalias() = Asym * p_;
      s.contacts.filter(Ap_);
      const double pAp = p_.dot(Ap_);
      if (!(pAp > 0.0)) break;
      const double alpha = rz / pAp;
      s.sol += alpha * p_;
      r_ -= alpha * Ap_;
      ++it;
      res = r_.norm() / b_norm;
      if (res <= options_.cg_tolerance) {
        converged = true;
        break;
      }
      precondition(r_, z_);
      s.contacts.filter(z_);
      const double rz_new = r_.dot(z_);
      p_ = z_ + (rz_new / rz) * p_;
      rz = rz_new;
    }
  }
  s.counters.last_residual = res;
  return it;
}

double SystemSolver::relative_residual(const Solve& s) const {
  const double b_norm = std::max(s.b.norm(), 1e-300);
  Eigen::VectorXd res = s.b - s.A.selfadjointView<Eigen::Lower>() * s.sol;
  s.contacts.filter(res);
  return res.norm() / b_norm;
}

// A direct solve with the current factor; with constraints or a membrane-pattern
// factor, CG with that (fresh) factor as preconditioner.
void SystemSolver::direct_solve(const Solve& s, bool& converged) {
  if (s.contacts.empty() && !membrane_active_) {
    apply_factor(s.b, s.sol);
    s.counters.last_residual = relative_residual(s);
    converged = true;
    return;
  }
  auto by_factor = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { apply_factor(in, out); };
  const int it = pcg(s, by_factor, options_.fresh_factor_max_iterations, converged);
  s.counters.cg_iterations += it;
}

// Factorizes the current matrix and solves with it. A membrane-pattern factor
// that leaves CG short of the tolerance, or twice needs more than
// options.membrane_max_iterations (the bending stencils of near-degenerate
// rest triangles, whose couplings are far from small), is given up for the
// whole matrix, for the rest of the run.
void SystemSolver::solve_with_fresh_factor(const Solve& s, bool& converged) {
  factorize(s);
  warp_active_ = false;
  auto t0 = Clock::now();
  const long iterations_before = s.counters.cg_iterations;
  direct_solve(s, converged);
  s.times.solve += seconds_since(t0);
  if (!membrane_active_) return;
  if (converged) {
    if (s.counters.cg_iterations - iterations_before > options_.membrane_max_iterations) {
      ++s.counters.slow_membrane_solves;
    }
    // The solution stands; the next step factors the whole matrix.
    if (s.counters.slow_membrane_solves >= 2) {
      membrane_active_ = false;
      ++s.counters.membrane_fallbacks;
    }
    return;
  }
  membrane_active_ = false;
  ++s.counters.membrane_fallbacks;
  factorize(s);
  t0 = Clock::now();
  direct_solve(s, converged);
  s.times.solve += seconds_since(t0);
}

void SystemSolver::solve(const SystemAssembly& system, const ContactSet& contacts, const Eigen::MatrixXd& X,
                         const Eigen::MatrixXi& F, Eigen::VectorXd& sol, SolverCounters& counters,
                         PhaseTimes& times) {
  const Solve s{system.matrix(), system.rhs(), system, contacts, X, F, sol, counters, times};
  int iterations = 0;
  bool converged = false;
  switch (options_.strategy) {
    case SolverStrategy::refactor_every_step: {
      solve_with_fresh_factor(s, converged);
      if (!converged) throw NumericalError("constrained solve with a fresh factor did not converge");
      break;
    }
    case SolverStrategy::pcg_reused_factor: {
      auto by_factor = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { apply_factor(in, out); };
      // A factor for another step size (a halved substep, or back to the full
      // step after one) is far from this system: h scales its damping and
      // stiffness parts, which outweigh the mass by orders of magnitude at the
      // default material (cloth/README.md, "Solver strategies").
      if (!factor_valid_ || refresh_needed_ || factor_h_ != system.step_size()) factorize(s);
      auto t0 = Clock::now();
      update_warp(s);
      iterations = pcg(s, by_factor, options_.cg_max_iterations, converged);
      times.solve += seconds_since(t0);
      if (!converged) {
        // A stale preconditioner: refresh it and solve directly.
        solve_with_fresh_factor(s, converged);
        if (!converged) throw NumericalError("constrained solve with a fresh factor did not converge");
        break;
      }
      iterations_since_factor_ += iterations;
      ++steps_since_factor_;
      // Refresh when this step's iterations exceed the average cost per step
      // since the last factorization, counting the factorization as
      // `factorization_cost` iterations: the classic replacement rule that
      // minimizes the average cost. Counted in iterations, not seconds, so that
      // runs stay deterministic.
      if (static_cast<double>(iterations) * steps_since_factor_ >
          options_.factorization_cost + iterations_since_factor_) {
        refresh_needed_ = true;
      }
      break;
    }
    case SolverStrategy::pcg_jacobi: {
      const auto t0 = Clock::now();
      Eigen::VectorXd inv_diag(3 * n_free_);
      for (int i = 0; i < 3 * n_free_; ++i) inv_diag(i) = 1.0 / system.diagonal(i);
      iterations = pcg(s, [&inv_diag](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
                         out = inv_diag.cwiseProduct(in);
                       },
                       options_.cg_max_iterations, converged);
      times.solve += seconds_since(t0);
      if (!converged) throw NumericalError("Jacobi-preconditioned CG did not converge");
      break;
    }
  }
  counters.last_cg_iterations = iterations;
  counters.cg_iterations += iterations;
}

}  // namespace gp::cloth
