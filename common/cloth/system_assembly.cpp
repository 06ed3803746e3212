#include "cloth/system_assembly.h"

#include <algorithm>

#include "cloth/cloth_energy.h"

namespace gp::cloth {
namespace {

// The six 3x3 blocks of a triangle's 9x9 matrix kept in the lower-triangle storage:
// three diagonal blocks and the three above the diagonal (their transposes are
// the mirrored lower entries).
constexpr int kBlockPairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};

}  // namespace

int entry_index(const Eigen::SparseMatrix<double>& M, int row, int col) {
  const int* inner = M.innerIndexPtr();
  const int* begin = inner + M.outerIndexPtr()[col];
  const int* end = inner + M.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - inner) : -1;
}

void SystemAssembly::build(const Eigen::MatrixXi& F, const Eigen::SparseMatrix<double>& Q, int vertex_count,
                           const std::vector<int>& pinned_ids) {
  const int nv = vertex_count;
  free_id_ = Eigen::VectorXi::Constant(nv, -1);
  std::vector<char> is_pinned(nv, 0);
  for (int v : pinned_ids) is_pinned[v] = 1;
  n_free_ = 0;
  for (int v = 0; v < nv; ++v) {
    if (!is_pinned[v]) free_id_(v) = n_free_++;
  }
  const int n = 3 * n_free_;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(F.rows() * 45 + Q.nonZeros() * 3 + n);
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, 0.0);
  for (int f = 0; f < F.rows(); ++f) {
    for (int li = 0; li < 3; ++li) {
      for (int lj = 0; lj < 3; ++lj) {
        const int fi = free_id_(F(f, li)), fj = free_id_(F(f, lj));
        if (fi < 0 || fj < 0) continue;
        for (int a = 0; a < 3; ++a) {
          for (int c = 0; c < 3; ++c) {
            if (3 * fi + a >= 3 * fj + c) triplets.emplace_back(3 * fi + a, 3 * fj + c, 0.0);
          }
        }
      }
    }
  }
  for (int k = 0; k < Q.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, k); it; ++it) {
      const int fi = free_id_(static_cast<int>(it.row())), fj = free_id_(static_cast<int>(it.col()));
      if (fi >= 0 && fj >= 0 && fi >= fj) {
        for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * fi + c, 3 * fj + c, 0.0);
      }
    }
  }
  A_.resize(n, n);
  A_.setFromTriplets(triplets.begin(), triplets.end());
  A_.makeCompressed();

  triangle_positions_.assign(F.rows() * 54, -1);
  for (int f = 0; f < F.rows(); ++f) {
    for (int blk = 0; blk < 6; ++blk) {
      const int li = kBlockPairs[blk][0], lj = kBlockPairs[blk][1];
      const int fi = free_id_(F(f, li)), fj = free_id_(F(f, lj));
      if (fi < 0 || fj < 0) continue;
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) {
          int pos = -1;
          const int row = 3 * fi + a, col = 3 * fj + c;
          if (li == lj) {
            if (a >= c) pos = entry_index(A_, row, col);
          } else {
            pos = row >= col ? entry_index(A_, row, col) : entry_index(A_, col, row);
          }
          triangle_positions_[f * 54 + blk * 9 + a * 3 + c] = pos;
        }
      }
    }
  }
  mass_positions_.resize(n);
  for (int i = 0; i < n; ++i) mass_positions_[i] = entry_index(A_, i, i);
  vertex_block_positions_.resize(6 * static_cast<size_t>(n_free_));
  for (int fi = 0; fi < n_free_; ++fi) {
    int k = 0;
    for (int c = 0; c < 3; ++c) {
      for (int a = c; a < 3; ++a) vertex_block_positions_[6 * static_cast<size_t>(fi) + k++] = entry_index(A_, 3 * fi + a, 3 * fi + c);
    }
  }
  bend_entries_.clear();
  bend_couplings_.clear();
  for (int k = 0; k < Q.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, k); it; ++it) {
      const int vi = static_cast<int>(it.row()), vj = static_cast<int>(it.col());
      const int fi = free_id_(vi), fj = free_id_(vj);
      const int q_index = static_cast<int>(&it.value() - Q.valuePtr());
      if (fi >= 0 && fj >= 0 && fi >= fj) {
        BendEntry e{q_index, {0, 0, 0}};
        for (int c = 0; c < 3; ++c) e.pos[c] = entry_index(A_, 3 * fi + c, 3 * fj + c);
        bend_entries_.push_back(e);
      } else if (fi >= 0 && fj < 0) {
        bend_couplings_.push_back({vi, vj, q_index});
      }
    }
  }
  constant_h_ = -1.0;
}

double SystemAssembly::bend_coefficient(const ClothParameters& params, double damping_scale, double h) const {
  return h * h * params.k_bend + h * damping_scale * params.damping_bend;
}

void SystemAssembly::build_constant_values(const ClothRestState& rest, const ClothParameters& params,
                                           double damping_scale, double h) {
  constant_values_ = Eigen::VectorXd::Zero(A_.nonZeros());
  for (int v = 0; v < free_id_.size(); ++v) {
    const int fi = free_id_(v);
    if (fi < 0) continue;
    for (int c = 0; c < 3; ++c) constant_values_(mass_positions_[3 * fi + c]) += rest.masses(v);
  }
  const double cb = bend_coefficient(params, damping_scale, h);
  const double* q = rest.Q.valuePtr();
  for (const BendEntry& e : bend_entries_) {
    for (int c = 0; c < 3; ++c) constant_values_(e.pos[c]) += cb * q[e.q_index];
  }
  constant_h_ = h;
}

double SystemAssembly::assemble(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Vel,
                                const Eigen::MatrixXd& V_prescribed, const Eigen::MatrixXi& F,
                                const ClothRestState& rest, const ClothParameters& params, double damping_scale,
                                double h) {
  if (constant_h_ != h) build_constant_values(rest, params, damping_scale, h);
  std::copy(constant_values_.data(), constant_values_.data() + constant_values_.size(), A_.valuePtr());
  double* vals = A_.valuePtr();
  G_.noalias() = params.k_bend * (rest.Q * X);
  double energy = quadratic_bending_energy(X, rest, params);
  b_.setZero(3 * n_free_);
  const MembraneCoefficients coeffs{params.k_stretch, params.k_shear, damping_scale * params.damping_stretch,
                                    damping_scale * params.damping_shear, params.compression_ratio};
  Vector9d g9;
  Matrix9d K9;
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix3d T;
    for (int k = 0; k < 3; ++k) T.col(k) = X.row(F(f, k)).transpose();
    energy += membrane_system_block(T, rest.triangles[f], coeffs, h, g9, K9);
    for (int k = 0; k < 3; ++k) G_.row(F(f, k)) += g9.segment<3>(3 * k).transpose();
    const int* pos = &triangle_positions_[f * 54];
    for (int blk = 0; blk < 6; ++blk) {
      const int li = kBlockPairs[blk][0], lj = kBlockPairs[blk][1];
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) {
          const int q = pos[blk * 9 + a * 3 + c];
          if (q >= 0) vals[q] += K9(3 * li + a, 3 * lj + c);
        }
      }
    }
    // Coupling to pinned vertices goes to the right-hand side: b_f -= A_fp v_p.
    for (int li = 0; li < 3; ++li) {
      const int fi = free_id_(F(f, li));
      if (fi < 0) continue;
      for (int lj = 0; lj < 3; ++lj) {
        const int vj = F(f, lj);
        if (free_id_(vj) >= 0) continue;
        b_.segment<3>(3 * fi) -= K9.block<3, 3>(3 * li, 3 * lj) * V_prescribed.row(vj).transpose();
      }
    }
  }
  const double cb = bend_coefficient(params, damping_scale, h);
  const double* q = rest.Q.valuePtr();
  for (const BendCoupling& c : bend_couplings_) {
    b_.segment<3>(3 * free_id_(c.free_vertex)) -= cb * q[c.q_index] * V_prescribed.row(c.pinned_vertex).transpose();
  }
  for (int v = 0; v < X.rows(); ++v) {
    const int fi = free_id_(v);
    if (fi < 0) continue;
    const double m = rest.masses(v);
    b_.segment<3>(3 * fi) += m * Vel.row(v).transpose() + h * (m * params.gravity - G_.row(v).transpose());
  }
  return energy;
}

void SystemAssembly::add_vertex_terms(int v, const Eigen::Matrix3d& K, const Eigen::Vector3d& r) {
  const int fi = free_id_(v);
  if (fi < 0) return;
  double* vals = A_.valuePtr();
  int k = 0;
  for (int c = 0; c < 3; ++c) {
    for (int a = c; a < 3; ++a) {
      const int q = vertex_block_positions_[6 * static_cast<size_t>(fi) + k++];
      if (q >= 0) vals[q] += K(a, c);
    }
  }
  b_.segment<3>(3 * fi) += r;
}

double membrane_energy(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F, const ClothRestState& rest,
                       const ClothParameters& params) {
  double e = 0.0;
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix3d T;
    for (int k = 0; k < 3; ++k) T.col(k) = X.row(F(f, k)).transpose();
    e += stretch_energy(T, rest.triangles[f], params.k_stretch, params.compression_ratio) +
         shear_energy(T, rest.triangles[f], params.k_shear);
  }
  return e;
}

double quadratic_bending_energy(const Eigen::MatrixXd& X, const ClothRestState& rest, const ClothParameters& params) {
  return 0.5 * params.k_bend * (X.transpose() * (rest.Q * X)).trace();
}

double kinetic_energy(const Eigen::MatrixXd& Vel, const Eigen::VectorXd& masses) {
  return 0.5 * (masses.array() * Vel.rowwise().squaredNorm().array()).sum();
}

}  // namespace gp::cloth
