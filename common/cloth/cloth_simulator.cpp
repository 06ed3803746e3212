#include "cloth/cloth_simulator.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/stopwatch.h"
#include "linalg/cholmod_solver.h"

namespace gp::cloth {
namespace {

// A vertex's second contact direction is dropped when it is within about 17
// degrees of the first (the two constraints would be nearly the same).
constexpr double kSmallestCreaseSine = 0.3;

// The six 3x3 blocks of a triangle's 9x9 matrix kept in the lower-triangle storage:
// three diagonal blocks and the three above the diagonal (their transposes are
// the mirrored lower entries).
constexpr int kBlockPairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};

// Index of entry (row, col) in the values of the compressed column-major M, or
// -1 when M does not store it.
int entry_index(const Eigen::SparseMatrix<double>& M, int row, int col) {
  const int* inner = M.innerIndexPtr();
  const int* begin = inner + M.outerIndexPtr()[col];
  const int* end = inner + M.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - inner) : -1;
}

// Why a (sub)step was rejected; none: it was accepted.
enum class Rejection { none, solve_failed, non_finite, too_fast, inverted, energy_growth };

struct StepOutcome {
  Rejection rejection = Rejection::none;
  std::string detail;  // what was wrong, for the error message when no halving helps
  bool accepted() const { return rejection == Rejection::none; }
};

// The counter of `r` in `counts` (r is a rejection, not none).
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

}  // namespace

const char* solver_strategy_name(SolverStrategy s) {
  switch (s) {
    case SolverStrategy::pcg_reused_factor: return "pcg_reused_factor";
    case SolverStrategy::refactor_every_step: return "refactor_every_step";
    case SolverStrategy::pcg_jacobi: return "pcg_jacobi";
  }
  return "unknown";
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

struct ClothSimulator::Impl {
  Eigen::MatrixXd V_rest, X, Vel;
  Eigen::MatrixXi F;
  ClothParameters params;
  SimulatorOptions options;
  ClothRestState rest;

  std::vector<int> pinned_ids;
  Eigen::VectorXi free_id;        // #V, -1 for pinned vertices
  Eigen::MatrixXd pin_targets;    // #pinned by 3
  int n_free = 0;

  Eigen::SparseMatrix<double> A;  // lower triangle over the free dofs
  Eigen::SparseMatrix<double> A_factored;  // A with the constraint stiffening, when P is not used (see factorize)
  // Membrane-pattern preconditioner (options.membrane_pattern_preconditioner):
  // for every entry of A its position in P, or -1 when dropped; for dropped
  // entries the positions of their row's and column's diagonals in P.
  Eigen::SparseMatrix<double> P;
  std::vector<int> p_position, p_diagonal_row, p_diagonal_col;
  // Whether the factor is of P (cleared for good when a fresh P factor fails
  // to bring CG to the tolerance: the dropped couplings were not small).
  bool membrane_active = true;
  std::vector<int> triangle_positions;  // 54 per face: value index or -1
  std::vector<int> mass_positions;      // 3 per free vertex
  struct BendEntry {
    int q_index;   // index into rest.Q's values
    int pos[3];
  };
  std::vector<BendEntry> bend_entries;
  struct BendCoupling {
    int free_vertex;
    int pinned_vertex;
    int q_index;
  };
  std::vector<BendCoupling> bend_couplings;
  Eigen::VectorXd constant_values;
  double constant_h = -1.0;
  double damping_scale = 1.0;

  CholmodSolver solver;
  bool factor_valid = false;
  bool refresh_needed = true;
  long iterations_since_factor = 0;  // CG iterations since the last factorization
  std::vector<Eigen::Matrix3d> frames_at_factor, warp;  // per vertex / per free vertex
  bool warp_active = false;
  Eigen::VectorXi neighbour_ids;  // a fixed neighbour per vertex (-1 if isolated)
  int neighbour(int v) const { return neighbour_ids(v); }
  long steps_since_factor = 0;
  double factor_h = -1.0;  // step size the factor was computed for

  CollisionHandler collision_handler;
  ContactHandler contact_handler;
  StepEndHandler step_end_handler;
  // Active velocity constraints of the current (sub)step over free dofs.
  std::vector<VelocityConstraint> constraints;
  std::vector<int> constraint_free;     // free vertex index per constraint
  std::vector<char> released;           // #V: the body pulled this vertex in the last (sub)step
  std::vector<char> in_contact;         // #V: constrained in the last (sub)step and not released
  PhaseTimes times;
  SolverCounters counters;

  // Work buffers.
  Eigen::MatrixXd G, V_prescribed;
  Eigen::VectorXd b, sol, r, z, p, Ap;
  Eigen::MatrixXd rhs_buffer, sol_buffer;
  std::vector<int> flipped_faces;  // the faces the last (sub)step turned over
  std::string last_failure;  // the detail of the last rejection, for the error message

  int value_position(int row, int col) const { return entry_index(A, row, col); }

  void build_pattern() {
    const int nv = static_cast<int>(X.rows());
    free_id = Eigen::VectorXi::Constant(nv, -1);
    std::vector<char> is_pinned(nv, 0);
    for (int v : pinned_ids) is_pinned[v] = 1;
    n_free = 0;
    for (int v = 0; v < nv; ++v) {
      if (!is_pinned[v]) free_id(v) = n_free++;
    }
    const int n = 3 * n_free;
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(F.rows() * 45 + rest.Q.nonZeros() * 3 + n);
    for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, 0.0);
    for (int f = 0; f < F.rows(); ++f) {
      for (int li = 0; li < 3; ++li) {
        for (int lj = 0; lj < 3; ++lj) {
          const int fi = free_id(F(f, li)), fj = free_id(F(f, lj));
          if (fi < 0 || fj < 0) continue;
          for (int a = 0; a < 3; ++a) {
            for (int c = 0; c < 3; ++c) {
              if (3 * fi + a >= 3 * fj + c) triplets.emplace_back(3 * fi + a, 3 * fj + c, 0.0);
            }
          }
        }
      }
    }
    for (int k = 0; k < rest.Q.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(rest.Q, k); it; ++it) {
        const int fi = free_id(static_cast<int>(it.row())), fj = free_id(static_cast<int>(it.col()));
        if (fi >= 0 && fj >= 0 && fi >= fj) {
          for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * fi + c, 3 * fj + c, 0.0);
        }
      }
    }
    A.resize(n, n);
    A.setFromTriplets(triplets.begin(), triplets.end());
    A.makeCompressed();
    build_membrane_pattern(n);

    triangle_positions.assign(F.rows() * 54, -1);
    for (int f = 0; f < F.rows(); ++f) {
      for (int blk = 0; blk < 6; ++blk) {
        const int li = kBlockPairs[blk][0], lj = kBlockPairs[blk][1];
        const int fi = free_id(F(f, li)), fj = free_id(F(f, lj));
        if (fi < 0 || fj < 0) continue;
        for (int a = 0; a < 3; ++a) {
          for (int c = 0; c < 3; ++c) {
            int pos = -1;
            const int row = 3 * fi + a, col = 3 * fj + c;
            if (li == lj) {
              if (a >= c) pos = value_position(row, col);
            } else {
              pos = row >= col ? value_position(row, col) : value_position(col, row);
            }
            triangle_positions[f * 54 + blk * 9 + a * 3 + c] = pos;
          }
        }
      }
    }
    neighbour_ids = Eigen::VectorXi::Constant(X.rows(), -1);
    for (int f = F.rows() - 1; f >= 0; --f) {
      for (int k = 0; k < 3; ++k) neighbour_ids(F(f, k)) = F(f, (k + 1) % 3);
    }
    mass_positions.resize(n);
    for (int i = 0; i < n; ++i) mass_positions[i] = value_position(i, i);
    bend_entries.clear();
    bend_couplings.clear();
    for (int k = 0; k < rest.Q.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(rest.Q, k); it; ++it) {
        const int vi = static_cast<int>(it.row()), vj = static_cast<int>(it.col());
        const int fi = free_id(vi), fj = free_id(vj);
        const int q_index = static_cast<int>(&it.value() - rest.Q.valuePtr());
        if (fi >= 0 && fj >= 0 && fi >= fj) {
          BendEntry e{q_index, {0, 0, 0}};
          for (int c = 0; c < 3; ++c) e.pos[c] = value_position(3 * fi + c, 3 * fj + c);
          bend_entries.push_back(e);
        } else if (fi >= 0 && fj < 0) {
          bend_couplings.push_back({vi, vj, q_index});
        }
      }
    }
    constant_h = -1.0;
    factor_valid = false;
    refresh_needed = true;
  }

  // P: A's pattern restricted to vertex pairs that share a face (the membrane's
  // one-ring), and the maps from A's entries into it.
  void build_membrane_pattern(int n) {
    std::vector<std::vector<int>> ring(n_free);
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
    P.resize(n, n);
    P.setFromTriplets(triplets.begin(), triplets.end());
    P.makeCompressed();
    p_position.assign(A.nonZeros(), -1);
    p_diagonal_row.assign(A.nonZeros(), -1);
    p_diagonal_col.assign(A.nonZeros(), -1);
    for (int col = 0; col < n; ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it) {
        const int q = static_cast<int>(&it.value() - A.valuePtr());
        const int row = static_cast<int>(it.row());
        p_position[q] = entry_index(P, row, col);
        if (p_position[q] < 0) {
          p_diagonal_row[q] = entry_index(P, row, row);
          p_diagonal_col[q] = entry_index(P, col, col);
        }
      }
    }
  }

  // Coefficient of Q in the system matrix: bending stiffness and damping.
  double bend_coefficient(double h) const {
    return h * h * params.k_bend + h * damping_scale * params.damping_bend;
  }

  // Mass and bending part of the system matrix for step size h (constant while
  // the rest shape and h are unchanged).
  void build_constant_values(double h) {
    constant_values = Eigen::VectorXd::Zero(A.nonZeros());
    for (int v = 0; v < X.rows(); ++v) {
      const int fi = free_id(v);
      if (fi < 0) continue;
      for (int c = 0; c < 3; ++c) constant_values(mass_positions[3 * fi + c]) += rest.masses(v);
    }
    const double cb = bend_coefficient(h);
    const double* q = rest.Q.valuePtr();
    for (const BendEntry& e : bend_entries) {
      for (int c = 0; c < 3; ++c) constant_values(e.pos[c]) += cb * q[e.q_index];
    }
    constant_h = h;
  }

  double bending_energy_total(const Eigen::MatrixXd& Xc) const {
    return 0.5 * params.k_bend * (Xc.transpose() * (rest.Q * Xc)).trace();
  }

  double membrane_energy(const Eigen::MatrixXd& Xc) const {
    double e = 0.0;
    for (int f = 0; f < F.rows(); ++f) {
      Eigen::Matrix3d T;
      for (int k = 0; k < 3; ++k) T.col(k) = Xc.row(F(f, k)).transpose();
      e += stretch_energy(T, rest.triangles[f], params.k_stretch) +
           shear_energy(T, rest.triangles[f], params.k_shear);
    }
    return e;
  }

  double kinetic(const Eigen::MatrixXd& Vc) const {
    return 0.5 * (rest.masses.array() * Vc.rowwise().squaredNorm().array()).sum();
  }

  // Assembles A (values) and b for step size h; returns the elastic energy at X.
  double assemble(double h) {
    if (constant_h != h) build_constant_values(h);
    std::copy(constant_values.data(), constant_values.data() + constant_values.size(), A.valuePtr());
    double* vals = A.valuePtr();
    G.noalias() = params.k_bend * (rest.Q * X);
    double energy = bending_energy_total(X);
    b.setZero(3 * n_free);
    const MembraneCoefficients coeffs{params.k_stretch, params.k_shear, damping_scale * params.damping_stretch,
                                      damping_scale * params.damping_shear};
    Vector9d g9;
    Matrix9d K9;
    for (int f = 0; f < F.rows(); ++f) {
      Eigen::Matrix3d T;
      for (int k = 0; k < 3; ++k) T.col(k) = X.row(F(f, k)).transpose();
      energy += membrane_system_block(T, rest.triangles[f], coeffs, h, g9, K9);
      for (int k = 0; k < 3; ++k) G.row(F(f, k)) += g9.segment<3>(3 * k).transpose();
      const int* pos = &triangle_positions[f * 54];
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
        const int fi = free_id(F(f, li));
        if (fi < 0) continue;
        for (int lj = 0; lj < 3; ++lj) {
          const int vj = F(f, lj);
          if (free_id(vj) >= 0) continue;
          b.segment<3>(3 * fi) -=
              K9.block<3, 3>(3 * li, 3 * lj) * V_prescribed.row(vj).transpose();
        }
      }
    }
    const double cb = bend_coefficient(h);
    const double* q = rest.Q.valuePtr();
    for (const BendCoupling& c : bend_couplings) {
      b.segment<3>(3 * free_id(c.free_vertex)) -=
          cb * q[c.q_index] * V_prescribed.row(c.pinned_vertex).transpose();
    }
    for (int v = 0; v < X.rows(); ++v) {
      const int fi = free_id(v);
      if (fi < 0) continue;
      const double m = rest.masses(v);
      b.segment<3>(3 * fi) += m * Vel.row(v).transpose() +
                              h * (m * params.gravity - G.row(v).transpose());
    }
    return energy;
  }

  // Per-vertex orthonormal frames [t, n x t, n] of positions Xc: n the (area
  // weighted) vertex normal, t the direction to a fixed neighbour projected into
  // the tangent plane. Used to rotate a stale factor along with the cloth.
  void vertex_frames(const Eigen::MatrixXd& Xc, std::vector<Eigen::Matrix3d>& frames) const {
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(Xc.rows(), 3);
    for (int f = 0; f < F.rows(); ++f) {
      const Eigen::RowVector3d x0 = Xc.row(F(f, 0)), x1 = Xc.row(F(f, 1)), x2 = Xc.row(F(f, 2));
      const Eigen::RowVector3d n = (x1 - x0).cross(x2 - x0);
      for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n;
    }
    frames.resize(Xc.rows());
    for (int v = 0; v < Xc.rows(); ++v) {
      Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
      const double ln = N.row(v).norm();
      if (ln > 0.0 && neighbour(v) >= 0) {
        const Eigen::Vector3d n = N.row(v).transpose() / ln;
        Eigen::Vector3d t = (Xc.row(neighbour(v)) - Xc.row(v)).transpose();
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
  void factorize() {
    const auto t0 = Clock::now();
    if (constraints.empty() && !membrane_active) {
      solver.factorize(A);
    } else {
      // The matrix to factor: P, refilled from A at every factorization and so
      // stiffened in place, or a copy of A.
      Eigen::SparseMatrix<double>* factored = &P;
      if (membrane_active) {
        // Dropped entries go to both diagonals by magnitude: P - A is then
        // diagonally dominant, so P >= A > 0.
        P.coeffs().setZero();
        double* pv = P.valuePtr();
        const double* av = A.valuePtr();
        for (Eigen::Index q = 0; q < A.nonZeros(); ++q) {
          if (p_position[q] >= 0) {
            pv[p_position[q]] += av[q];
          } else {
            pv[p_diagonal_row[q]] += std::abs(av[q]);
            pv[p_diagonal_col[q]] += std::abs(av[q]);
          }
        }
      } else {
        A_factored = A;
        factored = &A_factored;
      }
      double* vals = factored->valuePtr();
      for (size_t k = 0; k < constraints.size(); ++k) {
        const int fi = constraint_free[k];
        const Eigen::Vector3d& n = constraints[k].normal;
        double diagonal = 0.0;
        for (int a = 0; a < 3; ++a) diagonal += vals[entry_index(*factored, 3 * fi + a, 3 * fi + a)];
        const double kappa = options.constraint_preconditioner_stiffness * diagonal / 3.0;
        for (int a = 0; a < 3; ++a) {
          for (int c = 0; c <= a; ++c) vals[entry_index(*factored, 3 * fi + a, 3 * fi + c)] += kappa * n(a) * n(c);
        }
      }
      solver.factorize(*factored);
    }
    // The frames rotate a factor reused over later steps (update_warp); a
    // factor made for one step only needs none.
    if (options.warp_preconditioner && options.strategy == SolverStrategy::pcg_reused_factor) {
      vertex_frames(X, frames_at_factor);
    }
    times.factorization += seconds_since(t0);
    ++counters.factorizations;
    factor_valid = true;
    factor_h = constant_h;
    refresh_needed = false;
    iterations_since_factor = 0;
    steps_since_factor = 0;
  }

  void apply_factor(const Eigen::VectorXd& in, Eigen::VectorXd& out) {
    rhs_buffer = in;
    if (warp_active) {
      // P^-1 = Q A_old^-1 Q^T with Q = blockdiag(R_i): under a rigid rotation of
      // the cloth the system matrix transforms exactly like this (every term is
      // rotation invariant and the mass isotropic), so the stale factor follows
      // the cloth's local rotations instead of going stale with them.
      for (int i = 0; i < n_free; ++i) rhs_buffer.block<3, 1>(3 * i, 0) = warp[i].transpose() * in.segment<3>(3 * i);
      solver.solve(rhs_buffer, sol_buffer);
      out.resize(in.size());
      for (int i = 0; i < n_free; ++i) out.segment<3>(3 * i) = warp[i] * sol_buffer.block<3, 1>(3 * i, 0);
      return;
    }
    solver.solve(rhs_buffer, sol_buffer);
    out = sol_buffer.col(0);
  }

  // Rotations R_i = B_now B_at_factor^T of the free vertices' frames.
  void update_warp() {
    warp_active = false;
    if (!options.warp_preconditioner || steps_since_factor == 0 || frames_at_factor.empty()) return;
    std::vector<Eigen::Matrix3d> now;
    vertex_frames(X, now);
    warp.resize(n_free);
    for (int v = 0; v < X.rows(); ++v) {
      if (free_id(v) >= 0) warp[free_id(v)] = now[v] * frames_at_factor[v].transpose();
    }
    warp_active = true;
  }

  // S v: removes the constrained normal components (Baraff & Witkin 1998, eq. 17).
  void filter(Eigen::VectorXd& v) const {
    for (size_t k = 0; k < constraints.size(); ++k) {
      const Eigen::Vector3d& n = constraints[k].normal;
      auto seg = v.segment<3>(3 * constraint_free[k]);
      seg -= n * n.dot(seg);
    }
  }

  // Sets the constrained normal components of sol to their prescribed values.
  void impose_constraints() {
    for (size_t k = 0; k < constraints.size(); ++k) {
      const Eigen::Vector3d& n = constraints[k].normal;
      auto seg = sol.segment<3>(3 * constraint_free[k]);
      seg += n * (constraints[k].normal_velocity - n.dot(seg));
    }
  }

  // Collects the contact constraints of this (sub)step (free vertices only,
  // one per vertex, released ones skipped), in ascending vertex order.
  void gather_constraints(double h) {
    constraints.clear();
    constraint_free.clear();
    if (!contact_handler) return;
    std::vector<VelocityConstraint> all;
    contact_handler(X, h, all);
    std::stable_sort(all.begin(), all.end(),
                     [](const VelocityConstraint& a, const VelocityConstraint& c) { return a.vertex < c.vertex; });
    if (released.size() != static_cast<size_t>(X.rows())) released.assign(X.rows(), 0);
    if (in_contact.size() != static_cast<size_t>(X.rows())) in_contact.assign(X.rows(), 0);
    for (const VelocityConstraint& c : all) {
      if (c.vertex < 0 || c.vertex >= X.rows()) continue;
      const int fi = free_id(c.vertex);
      const double len = c.normal.norm();
      if (fi < 0 || !(len > 0.0) || !std::isfinite(c.normal_velocity)) continue;
      if (released[c.vertex] || !(c.touching || in_contact[c.vertex])) continue;
      VelocityConstraint k = c;
      k.normal /= len;
      const bool second = !constraints.empty() && constraints.back().vertex == c.vertex;
      if (second) {
        // Two directions of one vertex (a crease, Baraff & Witkin 1998, sec.
        // 5.3): the second normal is made orthogonal to the first, and its
        // prescribed speed follows from both, so that n1.v' = a1 and n2.v' = a2
        // hold together: n2' = (n2 - d n1) / s, a2' = (a2 - d a1) / s with
        // d = n1.n2, s = |n2 - d n1|. Nearly parallel ones add nothing.
        if (constraints.size() >= 2 && constraints[constraints.size() - 2].vertex == c.vertex) continue;
        const VelocityConstraint& first = constraints.back();
        const double d = first.normal.dot(k.normal);
        const Eigen::Vector3d perpendicular = k.normal - d * first.normal;
        const double sine = perpendicular.norm();
        if (!(sine > kSmallestCreaseSine)) continue;
        k.normal = perpendicular / sine;
        k.normal_velocity = (c.normal_velocity - d * first.normal_velocity) / sine;
      }
      constraints.push_back(k);
      constraint_free.push_back(fi);
    }
    counters.constraints += static_cast<long>(constraints.size());
  }

  // After a solve: the constraint force is h f_c = A v' - b on the constrained
  // normal; where it points into the body, the body would have to pull, so the
  // constraint is released for the next (sub)step (Baraff & Witkin 1998, sec. 5.3).
  void update_released(double h) {
    if (released.size() != static_cast<size_t>(X.rows())) released.assign(X.rows(), 0);
    std::fill(released.begin(), released.end(), 0);
    in_contact.assign(X.rows(), 0);
    for (const VelocityConstraint& c : constraints) in_contact[c.vertex] = 1;
    if (constraints.empty()) return;
    const Eigen::VectorXd residual = A.selfadjointView<Eigen::Lower>() * sol - b;
    const double g = params.gravity.norm();
    for (size_t k = 0; k < constraints.size(); ++k) {
      const double threshold = options.contact_release_fraction * h * rest.masses(constraints[k].vertex) * g;
      if (constraints[k].normal.dot(residual.segment<3>(3 * constraint_free[k])) < -threshold) {
        released[constraints[k].vertex] = 1;
        in_contact[constraints[k].vertex] = 0;
        ++counters.released;
      }
    }
  }

  // Preconditioned conjugate gradients on A sol = b from the current sol.
  // `precondition` applies M^-1. Returns iterations; sets counters.last_residual.
  template <class Precondition>
  int pcg(Precondition precondition, int max_iterations, bool& converged) {
    const auto Asym = A.selfadjointView<Eigen::Lower>();
    const double b_norm = std::max(b.norm(), 1e-300);
    // Filtered CG (Baraff & Witkin 1998, sec. 5.3): residuals and directions stay
    // in the unconstrained subspace, the constrained components keep their
    // prescribed values.
    impose_constraints();
    r = b - Asym * sol;
    filter(r);
    double res = r.norm() / b_norm;
    int it = 0;
    converged = res <= options.cg_tolerance;
    if (!converged) {
      precondition(r, z);
      filter(z);
      p = z;
      double rz = r.dot(z);
      while (it < max_iterations) {
        Ap.noalias() = Asym * p;
        filter(Ap);
        const double pAp = p.dot(Ap);
        if (!(pAp > 0.0)) break;
        const double alpha = rz / pAp;
        sol += alpha * p;
        r -= alpha * Ap;
        ++it;
        res = r.norm() / b_norm;
        if (res <= options.cg_tolerance) {
          converged = true;
          break;
        }
        precondition(r, z);
        filter(z);
        const double rz_new = r.dot(z);
        p = z + (rz_new / rz) * p;
        rz = rz_new;
      }
    }
    counters.last_residual = res;
    return it;
  }

  double relative_residual() const {
    const double b_norm = std::max(b.norm(), 1e-300);
    Eigen::VectorXd res = b - A.selfadjointView<Eigen::Lower>() * sol;
    filter(res);
    return res.norm() / b_norm;
  }

  // A direct solve with the current factor; with constraints or a membrane-pattern
  // factor, CG with that (fresh) factor as preconditioner.
  void direct_solve(bool& converged) {
    if (constraints.empty() && !membrane_active) {
      apply_factor(b, sol);
      counters.last_residual = relative_residual();
      converged = true;
      return;
    }
    auto by_factor = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { apply_factor(in, out); };
    const int it = pcg(by_factor, options.fresh_factor_max_iterations, converged);
    counters.cg_iterations += it;
  }

  // Factorizes the current matrix and solves with it. A membrane-pattern factor
  // that leaves CG short of the tolerance, or twice needs more than
  // options.membrane_max_iterations (the bending stencils of near-degenerate
  // rest triangles, whose couplings are far from small), is given up for the
  // whole matrix, for the rest of the run.
  void solve_with_fresh_factor(bool& converged) {
    factorize();
    warp_active = false;
    auto t0 = Clock::now();
    const long iterations_before = counters.cg_iterations;
    direct_solve(converged);
    times.solve += seconds_since(t0);
    if (!membrane_active) return;
    if (converged) {
      if (counters.cg_iterations - iterations_before > options.membrane_max_iterations) ++counters.slow_membrane_solves;
      // The solution stands; the next step factors the whole matrix.
      if (counters.slow_membrane_solves >= 2) {
        membrane_active = false;
        ++counters.membrane_fallbacks;
      }
      return;
    }
    membrane_active = false;
    ++counters.membrane_fallbacks;
    factorize();
    t0 = Clock::now();
    direct_solve(converged);
    times.solve += seconds_since(t0);
  }

  void solve_system() {
    sol.resize(3 * n_free);
    for (int v = 0; v < X.rows(); ++v) {
      if (free_id(v) >= 0) sol.segment<3>(3 * free_id(v)) = Vel.row(v).transpose();
    }
    int iterations = 0;
    bool converged = false;
    switch (options.strategy) {
      case SolverStrategy::refactor_every_step: {
        solve_with_fresh_factor(converged);
        if (!converged) throw NumericalError("constrained solve with a fresh factor did not converge");
        break;
      }
      case SolverStrategy::pcg_reused_factor: {
        auto by_factor = [this](const Eigen::VectorXd& in, Eigen::VectorXd& out) { apply_factor(in, out); };
        // A factor for another step size (a halved substep, or back to the full
        // step after one) is far from this system: h scales its damping and
        // stiffness parts, which outweigh the mass by orders of magnitude at the
        // default material; measured, such a stale factor took 100-200
        // CG iterations against 3-10 for a fresh one.
        if (!factor_valid || refresh_needed || factor_h != constant_h) factorize();
        auto t0 = Clock::now();
        update_warp();
        iterations = pcg(by_factor, options.cg_max_iterations, converged);
        times.solve += seconds_since(t0);
        if (!converged) {
          // A stale preconditioner: refresh it and solve directly.
          solve_with_fresh_factor(converged);
          if (!converged) throw NumericalError("constrained solve with a fresh factor did not converge");
          break;
        }
        iterations_since_factor += iterations;
        ++steps_since_factor;
        // Refresh when this step's iterations exceed the average cost per step
        // since the last factorization, counting the factorization as
        // `factorization_cost` iterations: the classic replacement rule that
        // minimizes the average cost. Counted in iterations, not seconds, so that
        // runs stay deterministic.
        if (static_cast<double>(iterations) * steps_since_factor >
            options.factorization_cost + iterations_since_factor) {
          refresh_needed = true;
        }
        break;
      }
      case SolverStrategy::pcg_jacobi: {
        const auto t0 = Clock::now();
        Eigen::VectorXd inv_diag(3 * n_free);
        for (int i = 0; i < 3 * n_free; ++i) inv_diag(i) = 1.0 / A.valuePtr()[mass_positions[i]];
        iterations = pcg([&inv_diag](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
                           out = inv_diag.cwiseProduct(in);
                         },
                         options.cg_max_iterations, converged);
        times.solve += seconds_since(t0);
        if (!converged) throw NumericalError("Jacobi-preconditioned CG did not converge");
        break;
      }
    }
    counters.last_cg_iterations = iterations;
    counters.cg_iterations += iterations;
  }

  // One linearized implicit Euler step of size h, kept only if accepted.
  // [s_start, s_end]: the part of the step this (sub)step covers.
  StepOutcome single_step(double h, const Eigen::MatrixXd& pin_end, bool accept_flips, double s_start, double s_end) {
    auto t0 = Clock::now();
    V_prescribed.setZero(X.rows(), 3);
    for (size_t k = 0; k < pinned_ids.size(); ++k) {
      const int v = pinned_ids[k];
      V_prescribed.row(v) = (pin_end.row(k) - X.row(v)) / h;
    }
    const double energy_before = assemble(h) + kinetic(Vel);
    times.forces_assembly += seconds_since(t0);
    t0 = Clock::now();
    gather_constraints(h);
    times.collisions += seconds_since(t0);
    try {
      solve_system();
    } catch (const NumericalError& e) {
      factor_valid = false;
      return {Rejection::solve_failed, std::string("linear solve failed: ") + e.what()};
    }
    const std::vector<char> released_before = released, in_contact_before = in_contact;
    update_released(h);

    t0 = Clock::now();
    Eigen::MatrixXd X_new = X, V_new = V_prescribed;
    for (int v = 0; v < X.rows(); ++v) {
      const int fi = free_id(v);
      if (fi >= 0) V_new.row(v) = sol.segment<3>(3 * fi).transpose();
    }
    X_new += h * V_new;
    for (size_t k = 0; k < pinned_ids.size(); ++k) X_new.row(pinned_ids[k]) = pin_end.row(k);
    times.checks += seconds_since(t0);

    if (collision_handler || step_end_handler) {
      t0 = Clock::now();
      const Eigen::MatrixXd X_solved = X_new;
      if (collision_handler) collision_handler(X_new, V_new);
      if (step_end_handler) step_end_handler(X, X_new, s_start, s_end);
      // A vertex the handler moved gets the velocity of its actual displacement
      // over the step (the velocity update of position-based dynamics, Mueller
      // et al. 2007, "Position based dynamics", sec. 3.1). Keeping the solved
      // velocity instead left vertices pressed into a concave part of the body
      // (an armpit crease, where the contact constraint blocks one normal and
      // the projection another) with a velocity they never moved at, pushed
      // back every step. Measured on the shared-body shirt (1,085 vertices)
      // moving T -> A -> arms up -> arms bent -> T: without this update the
      // A-pose was still moving after its 1,000-step settling cap (1,824 steps,
      // 49 s); with it every key pose settled (1,248 steps, 34 s).
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
    StepOutcome outcome;
    flipped_faces.clear();
    if (!X_new.allFinite() || !V_new.allFinite()) {
      outcome = {Rejection::non_finite, "non-finite positions or velocities"};
    } else if (V_new.rowwise().norm().maxCoeff() > options.max_speed) {
      outcome = {Rejection::too_fast, "vertex speed above " + std::to_string(options.max_speed) + " m/s"};
    } else {
      for (int f = 0; f < F.rows(); ++f) {
        const Eigen::Vector3d x0 = X.row(F(f, 0)), x1 = X.row(F(f, 1)), x2 = X.row(F(f, 2));
        const Eigen::Vector3d y0 = X_new.row(F(f, 0)), y1 = X_new.row(F(f, 1)), y2 = X_new.row(F(f, 2));
        const Eigen::Vector3d n_old = (x1 - x0).cross(x2 - x0);
        const Eigen::Vector3d n_new = (y1 - y0).cross(y2 - y0);
        if (n_old.dot(n_new) < 0.0) flipped_faces.push_back(f);
      }
      // A triangle turned over within one step is a symptom of a too large step
      // and is retried; if it survives the smallest step, it is a fold forced by
      // the body (cloth squeezed between two body parts), which cloth may do: it
      // is accepted and counted rather than ending the run.
      const long flipped = static_cast<long>(flipped_faces.size());
      if (flipped > 0 && !accept_flips) {
        outcome = {Rejection::inverted,
                   std::to_string(flipped) + " triangle(s) inverted, first " + std::to_string(flipped_faces.front())};
      } else if (flipped > 0) {
        counters.accepted_flips += flipped;
      }
      if (outcome.accepted()) {
        const double energy_after = membrane_energy(X_new) + bending_energy_total(X_new) + kinetic(V_new);
        const double floor = 10.0 * rest.masses.sum();
        if (energy_after > options.energy_growth_limit * energy_before + floor) {
          outcome = {Rejection::energy_growth, "energy exploded (" + std::to_string(energy_before) + " J -> " +
                                                   std::to_string(energy_after) + " J)"};
        }
      }
    }
    times.checks += seconds_since(t0);
    if (!outcome.accepted()) {
      released = released_before;
      in_contact = in_contact_before;
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
      for (int f : flipped_faces) ++counters.inverted_faces[f];
    }
    X = X_saved;
    Vel = V_saved;
    last_failure = outcome.detail;
    if (depth >= options.max_step_halvings) return false;
    const Eigen::MatrixXd pin_mid = 0.5 * (pin_start + pin_end);
    const double s_mid = 0.5 * (s_start + s_end);
    return advance(0.5 * h, pin_start, pin_mid, depth + 1, s_start, s_mid) &&
           advance(0.5 * h, pin_mid, pin_end, depth + 1, s_mid, s_end);
  }
};

ClothSimulator::ClothSimulator(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                               const ClothParameters& params, const SimulatorOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!(options.dt > 0.0)) throw UsageError("time step must be positive");
  impl_->V_rest = V_rest;
  impl_->F = F;
  impl_->params = params;
  impl_->options = options;
  impl_->rest = build_rest_state(V_rest, F, params);
  impl_->X = V_rest;
  impl_->Vel = Eigen::MatrixXd::Zero(V_rest.rows(), 3);
  impl_->pin_targets.resize(0, 3);
  impl_->membrane_active = options.membrane_pattern_preconditioner;
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
  impl_->constant_h = -1.0;
}

void ClothSimulator::set_rest_triangles(const std::vector<TriangleRest>& triangles) {
  ClothRestState rest = impl_->rest;
  cloth::set_rest_triangles(triangles, impl_->F, impl_->params, rest);
  impl_->rest = std::move(rest);
  impl_->constant_h = -1.0;
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
}

void ClothSimulator::set_velocities(const Eigen::MatrixXd& Vel) {
  if (Vel.rows() != impl_->X.rows() || Vel.cols() != 3) throw UsageError("velocities must be #V by 3");
  impl_->Vel = Vel;
}

void ClothSimulator::set_collision_handler(CollisionHandler handler) {
  impl_->collision_handler = std::move(handler);
}

void ClothSimulator::set_contact_handler(ContactHandler handler) {
  impl_->contact_handler = std::move(handler);
  impl_->released.clear();
  impl_->in_contact.clear();
}

void ClothSimulator::set_step_end_handler(StepEndHandler handler) {
  impl_->step_end_handler = std::move(handler);
}

void ClothSimulator::set_damping_scale(double scale) {
  if (!(scale >= 0.0) || !std::isfinite(scale)) throw UsageError("damping scale must be finite and non-negative");
  if (scale == impl_->damping_scale) return;
  impl_->damping_scale = scale;
  impl_->constant_h = -1.0;
}

void ClothSimulator::step() {
  Impl& s = *impl_;
  const Eigen::MatrixXd X0 = s.X, V0 = s.Vel;
  Eigen::MatrixXd pin_start(s.pinned_ids.size(), 3);
  for (size_t k = 0; k < s.pinned_ids.size(); ++k) pin_start.row(k) = s.X.row(s.pinned_ids[k]);
  if (!s.advance(s.options.dt, pin_start, s.pin_targets, 0, 0.0, 1.0)) {
    s.X = X0;
    s.Vel = V0;
    throw NumericalError("cloth step failed after " + std::to_string(s.options.max_step_halvings) +
                             " halvings of the time step: " + s.last_failure,
                         "step " + std::to_string(s.counters.steps));
  }
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
