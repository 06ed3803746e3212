#pragma once
// Solves the step's system A v' = b (system_assembly.h) under the contact constraints
// (contact_set.h) by the strategy of SimulatorOptions::strategy (cloth_simulator.h): conjugate
// gradients filtered to the unconstrained subspace (Baraff & Witkin 1998, sec. 5.3), preconditioned
// by a CHOLMOD factor (fresh every step, or reused and rotated with the cloth) or by the diagonal.
// Owns the factor, the membrane-pattern matrix it may be computed from, and the refresh state.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth/cloth_simulator.h"
#include "cloth/contact_set.h"
#include "cloth/system_assembly.h"
#include "linalg/cholmod_solver.h"

namespace gp::cloth {

class SystemSolver {
 public:
  explicit SystemSolver(const SimulatorOptions& options);

  // After system.build(): the membrane pattern of A restricted to vertex pairs that share a face of F,
  // a fixed neighbour per vertex for the factor's rotation, and no valid factor.
  void reset(const SystemAssembly& system, const Eigen::MatrixXi& F);
  // The factor is not to be reused (its step was rejected).
  void invalidate() { factor_valid_ = false; }

  // Solves A sol = b of `system` with the constrained normal components of `contacts` prescribed,
  // from the initial guess sol (3 #free). X (#V by 3) are the positions the system was assembled
  // at (the factor's rotation). Adds to counters (factorizations, CG iterations, residual,
  // membrane fallbacks) and times (factorization, solve). Throws NumericalError when CG does not
  // reach options.cg_tolerance with a fresh factor (or, for pcg_jacobi, within its iteration cap).
  void solve(const SystemAssembly& system, const ContactSet& contacts, const Eigen::MatrixXd& X,
             const Eigen::MatrixXi& F, Eigen::VectorXd& sol, SolverCounters& counters, PhaseTimes& times);

 private:
  struct Solve;  // the arguments of one solve()
  void factorize(const Solve& s);
  void apply_factor(const Eigen::VectorXd& in, Eigen::VectorXd& out);
  void update_warp(const Solve& s);
  void vertex_frames(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, std::vector<Eigen::Matrix3d>& frames) const;
  template <class Precondition>
  int pcg(const Solve& s, Precondition precondition, int max_iterations, bool& converged);
  double relative_residual(const Solve& s) const;
  void direct_solve(const Solve& s, bool& converged);
  void solve_with_fresh_factor(const Solve& s, bool& converged);

  SimulatorOptions options_;
  int n_free_ = 0;
  Eigen::SparseMatrix<double> A_factored_;  // A with the constraint stiffening, when P is not used
  // Membrane-pattern preconditioner (options.membrane_pattern_preconditioner): for every entry of A
  // its position in P, or -1 when dropped; for dropped entries the positions of their row's and
  // column's diagonals in P.
  Eigen::SparseMatrix<double> P_;
  std::vector<int> p_position_, p_diagonal_row_, p_diagonal_col_;
  // Whether the factor is of P (cleared for good when a fresh P factor fails to bring CG to the
  // tolerance: the dropped couplings were not small).
  bool membrane_active_ = true;

  CholmodSolver solver_;
  bool factor_valid_ = false;
  bool refresh_needed_ = true;
  long iterations_since_factor_ = 0;  // CG iterations since the last factorization
  long steps_since_factor_ = 0;
  double factor_h_ = -1.0;            // step size the factor was computed for
  std::vector<Eigen::Matrix3d> frames_at_factor_, warp_;  // per vertex / per free vertex
  bool warp_active_ = false;
  Eigen::VectorXi neighbour_ids_;  // a fixed neighbour per vertex (-1 if isolated)

  // Work buffers.
  Eigen::VectorXd r_, z_, p_, Ap_;
  Eigen::MatrixXd rhs_buffer_, sol_buffer_;
};

}  // namespace gp::cloth
