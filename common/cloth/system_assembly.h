#pragma once
// The linear system of one linearized implicit Euler step (Baraff & Witkin 1998, sec. 5, eq. 16-18)
// over the free vertices' degrees of freedom:
//   A = M + h D + h^2 (H + k_bend Q),   b = M v + h f(x) - A_fp v_p
// A in lower-triangle compressed storage (3 #free square, free vertices numbered in vertex order,
// dof 3 i + c), H the PSD-projected membrane Hessian, D the damping matrices, f the conservative
// forces (membrane, bending, gravity); the coupling A_fp to the pinned vertices' prescribed
// velocities v_p moves to the right-hand side. The sparsity pattern is built once per pin set; the
// mass and bending part once per step size, damping scale and rest state.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth/cloth_model.h"

namespace gp::cloth {

// Index of entry (row, col) in the values of the compressed column-major M, or -1 when M does not
// store it.
int entry_index(const Eigen::SparseMatrix<double>& M, int row, int col);

class SystemAssembly {
 public:
  // The pattern for faces F (#F by 3) and bending matrix Q (#V by #V) with the pinned vertices
  // `pinned_ids` (distinct, in [0, vertex_count)) eliminated.
  void build(const Eigen::MatrixXi& F, const Eigen::SparseMatrix<double>& Q, int vertex_count,
             const std::vector<int>& pinned_ids);
  // Forgets the mass and bending part (a new rest state or damping scale).
  void invalidate_constant_part() { constant_h_ = -1.0; }

  // Fills A's values and b for step size h [s] at positions X and velocities Vel (#V by 3), with
  // V_prescribed (#V by 3) the pinned vertices' velocities over the step; damping_scale multiplies
  // every damping coefficient. Returns the elastic energy (membrane plus bending) at X [J].
  double assemble(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Vel, const Eigen::MatrixXd& V_prescribed,
                  const Eigen::MatrixXi& F, const ClothRestState& rest, const ClothParameters& params,
                  double damping_scale, double h);

  // After assemble(): adds K (3x3, symmetric) to the diagonal block of vertex v (free) in A and r to
  // its rows of b, for terms of one vertex alone (the static solve's contact barrier).
  void add_vertex_terms(int v, const Eigen::Matrix3d& K, const Eigen::Vector3d& r);

  const Eigen::SparseMatrix<double>& matrix() const { return A_; }  // A (lower triangle)
  const Eigen::VectorXd& rhs() const { return b_; }                 // b (3 #free)
  const Eigen::VectorXi& free_ids() const { return free_id_; }      // #V: free index, -1 if pinned
  int free_count() const { return n_free_; }
  double diagonal(int i) const { return A_.valuePtr()[mass_positions_[i]]; }  // A(i, i)
  // The step size the mass and bending part was assembled for [s] (-1 when none is).
  double step_size() const { return constant_h_; }

 private:
  // Coefficient of Q in the system matrix: bending stiffness and damping.
  double bend_coefficient(const ClothParameters& params, double damping_scale, double h) const;
  void build_constant_values(const ClothRestState& rest, const ClothParameters& params, double damping_scale,
                             double h);

  Eigen::VectorXi free_id_;
  int n_free_ = 0;
  Eigen::SparseMatrix<double> A_;
  Eigen::VectorXd b_;
  Eigen::MatrixXd G_;                    // gradient of the elastic energy (#V by 3), work buffer
  std::vector<int> triangle_positions_;  // 54 per face: value index or -1
  std::vector<int> mass_positions_;      // one per free dof
  std::vector<int> vertex_block_positions_;  // 6 per free vertex: (0,0) (1,0) (2,0) (1,1) (2,1) (2,2), or -1
  struct BendEntry {
    int q_index;  // index into Q's values
    int pos[3];
  };
  std::vector<BendEntry> bend_entries_;
  struct BendCoupling {
    int free_vertex;
    int pinned_vertex;
    int q_index;
  };
  std::vector<BendCoupling> bend_couplings_;
  Eigen::VectorXd constant_values_;
  double constant_h_ = -1.0;
};

// The energies the step checks compare [J]: membrane (stretch plus shear) of the configuration X
// (#V by 3), quadratic bending 0.5 k_bend tr(X^T Q X), kinetic 0.5 sum_i m_i |v_i|^2.
double membrane_energy(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, const ClothRestState& rest,
                       const ClothParameters& params);
double quadratic_bending_energy(const Eigen::MatrixXd& X, const ClothRestState& rest, const ClothParameters& params);
double kinetic_energy(const Eigen::MatrixXd& Vel, const Eigen::VectorXd& masses);

}  // namespace gp::cloth
