#include "pattern/flatten.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/math.h"
#include "linalg/cholmod_solver.h"
#include "mesh/measures.h"
#include "mesh/principal_stretches.h"
#include "mesh/topology.h"
#include "pattern/flatten_common.h"

namespace gp {

using namespace flatten_detail;

double flattening_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& UV,
                         const FlattenOptions& options, Eigen::MatrixXd* gradient, const Eigen::VectorXd* face_weight) {
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, options.min_weight_fraction, face_weight);
  const double ease_weight = std::clamp(options.ease_weight, 0.0, 1.0);
  if (gradient) gradient->setZero(UV.rows(), 2);
  double energy = 0.0;
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    if (t.degenerate) continue;
    const Eigen::Matrix2d J = jacobian(t, UV, F.row(f));
    double e = 0.0;
    const Eigen::Matrix2d target = local_target(J, ease_weight, e);
    energy += t.area * e;
    if (gradient) {
      // dE/dJ = 2 w (J - T); J = (D U)^T, so dE/dU = D^T (dE/dJ)^T.
      const Eigen::Matrix<double, 3, 2> g = 2.0 * t.area * t.D.transpose() * (J - target).transpose();
      for (int k = 0; k < 3; ++k) gradient->row(F(f, k)) += g.row(k);
    }
  }
  for (const BoundaryEdge& e : boundary_edges(V, F, T, options.boundary_weight)) {
    const Eigen::RowVector2d x = UV.row(e.i) - UV.row(e.j);
    const double len = x.norm();
    energy += e.weight * (len - e.length) * (len - e.length);
    if (gradient && len > 0.0) {
      const Eigen::RowVector2d g = 2.0 * e.weight * (len - e.length) * x / len;
      gradient->row(e.i) += g;
      gradient->row(e.j) -= g;
    }
  }
  return energy;
}

namespace {

// The global step's system: the cotangent (Dirichlet) matrix L of the triangles T plus the boundary
// edges' springs, reduced to the free vertices (one pinned vertex removes the translation), with a
// tiny proximal diagonal: A is what is factorized once.
struct FlatSystem {
  Eigen::SparseMatrix<double> L;  // #V by #V, the pinned vertex included
  Eigen::SparseMatrix<double> A;  // m by m, the free vertices
  int pin = 0;
  std::vector<int> free_index;  // per vertex, its row in A, -1 for the pin
  int m = 0;
  double proximal = 0.0;
};

FlatSystem flat_system(const std::vector<LocalTriangle>& T, const Eigen::MatrixXi& F, int n,
                       const std::vector<BoundaryEdge>& edges) {
  FlatSystem s;
  Eigen::SparseMatrix<double>& L = s.L;
  L = dirichlet_matrix(T, F, n);
  if (!edges.empty()) {
    std::vector<Triplet> extra;
    for (const auto& e : edges) {
      extra.emplace_back(e.i, e.i, e.weight);
      extra.emplace_back(e.j, e.j, e.weight);
      extra.emplace_back(e.i, e.j, -e.weight);
      extra.emplace_back(e.j, e.i, -e.weight);
    }
    Eigen::SparseMatrix<double> E(n, n);
    E.setFromTriplets(extra.begin(), extra.end());
    L += E;
  }
  const auto loops = boundary_loops(F);
  const int pin = s.pin = loops.empty() ? 0 : loops.front().front();
  std::vector<int>& free_index = s.free_index;
  free_index.assign(static_cast<size_t>(n), -1);
  int& m = s.m;
  for (int i = 0; i < n; ++i)
    if (i != pin) free_index[static_cast<size_t>(i)] = m++;
  std::vector<Triplet> trip;
  for (int c = 0; c < L.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it) {
      const int fr = free_index[static_cast<size_t>(it.row())], fc = free_index[static_cast<size_t>(c)];
      if (fr >= 0 && fc >= 0) trip.emplace_back(fr, fc, it.value());
    }
  // A vertex whose triangles are all degenerate carries no energy: a tiny
  // proximal term eps |u - u_current|^2 keeps the system definite without
  // moving the fixed point (its right-hand side is added in the global step).
  double diagonal = 0.0;
  for (const auto& t : trip)
    if (t.row() == t.col()) diagonal += t.value();
  const double proximal = s.proximal = 1e-10 * diagonal / std::max(1, m);
  for (int i = 0; i < m; ++i) trip.emplace_back(i, i, proximal);
  if (m > 0) {
    s.A.resize(m, m);
    s.A.setFromTriplets(trip.begin(), trip.end());
  }
  return s;
}

}  // namespace

ArapRun arap_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                     const FlattenOptions& options, bool injective, const Eigen::VectorXd* face_weight) {
  const int n = static_cast<int>(V.rows());
  if (UV.rows() != n || UV.cols() != 2) throw GeometryError("arap_flatten: the start has the wrong size");
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, options.min_weight_fraction, face_weight);
  const double ease_weight = std::clamp(options.ease_weight, 0.0, 1.0);
  // Boundary edges (i -> j, 3D length l, weight w): the term
  // w |u_i - u_j - l d|^2 with d the current unit direction of the flat edge
  // joins the local step (d) and the global step (a constant matrix), like the
  // edge springs of a local/global solver (Liu et al. 2008; Bouaziz et al.
  // 2014, projective dynamics).
  const std::vector<BoundaryEdge> edges = boundary_edges(V, F, T, options.boundary_weight);
  // One pinned vertex removes the translation; L is factorized once.
  const FlatSystem system = flat_system(T, F, n, edges);
  const Eigen::SparseMatrix<double>& L = system.L;
  const int pin = system.pin, m = system.m;
  const std::vector<int>& free_index = system.free_index;
  const double proximal = system.proximal;
  CholmodSolver solver{kFlattenSolver};
  if (m > 0) solver.compute(system.A);

  auto energy_and_rhs = [&](const Eigen::MatrixXd& X, Eigen::MatrixXd* rhs) {
    double energy = 0.0;
    if (rhs) rhs->setZero(n, 2);
    for (int f = 0; f < F.rows(); ++f) {
      const LocalTriangle& t = T[static_cast<size_t>(f)];
      if (t.degenerate) continue;
      const Eigen::Matrix2d J = jacobian(t, X, F.row(f));
      double e = 0.0;
      const Eigen::Matrix2d R = local_target(J, ease_weight, e);
      energy += t.area * e;
      if (rhs) {
        const Eigen::Matrix<double, 3, 2> b = t.area * t.D.transpose() * R.transpose();
        for (int k = 0; k < 3; ++k) rhs->row(F(f, k)) += b.row(k);
      }
    }
    for (const auto& e : edges) {
      const Eigen::RowVector2d x = X.row(e.i) - X.row(e.j);
      const double len = x.norm();
      const Eigen::RowVector2d target = len > 0.0 ? Eigen::RowVector2d(e.length * x / len) : Eigen::RowVector2d(e.length, 0.0);
      energy += e.weight * (x - target).squaredNorm();
      if (rhs) {
        rhs->row(e.i) += e.weight * target;
        rhs->row(e.j) -= e.weight * target;
      }
    }
    return energy;
  };
  const double area_scale = std::max(1e-300, std::accumulate(T.begin(), T.end(), 0.0,
                                                             [](double s, const LocalTriangle& t) { return s + t.area; }));

  ArapRun run;
  Eigen::MatrixXd rhs;
  run.energy = energy_and_rhs(UV, &rhs);
  Eigen::MatrixXd B(m, 2), X;
  // The global step G(UV): the minimizer for the local step's targets.
  auto global_step = [&](const Eigen::MatrixXd& from, const Eigen::MatrixXd& targets_rhs) {
    for (int i = 0; i < n; ++i) {
      const int fi = free_index[static_cast<size_t>(i)];
      if (fi >= 0) B.row(fi) = targets_rhs.row(i) + proximal * from.row(i);
    }
    for (Eigen::SparseMatrix<double>::InnerIterator e(L, pin); e; ++e) {
      const int fr = free_index[static_cast<size_t>(e.row())];
      if (fr >= 0) B.row(fr) -= e.value() * from.row(pin);
    }
    solver.solve(B, X);
    Eigen::MatrixXd target = from;
    for (int i = 0; i < n; ++i) {
      const int fi = free_index[static_cast<size_t>(i)];
      if (fi >= 0) target.row(i) = X.row(fi);
    }
    return target;
  };
  // Anderson acceleration of the fixed-point map UV -> G(UV) (Peng et al.
  // 2018, "Anderson acceleration for geometry optimization and physics
  // simulation"): the next iterate mixes the last `window` global steps; it
  // is kept only where it lowers the energy, else the plain step is taken
  // and the history restarts. Local/global alone needs hundreds of
  // iterations on a whole shirt panel.
  const int window = std::max(0, options.anderson_window);
  std::vector<Eigen::VectorXd> dG, dF;
  Eigen::VectorXd g_prev, f_prev;
  bool have_prev = false;
  auto flat = [](const Eigen::MatrixXd& M) { return Eigen::Map<const Eigen::VectorXd>(M.data(), M.size()); };
  for (int it = 0; it < options.max_iterations && m > 0; ++it) {
    const Eigen::MatrixXd target = global_step(UV, rhs);
    const Eigen::VectorXd g = flat(target), f = g - flat(UV);
    if (have_prev) {
      dG.push_back(g - g_prev);
      dF.push_back(f - f_prev);
      if (static_cast<int>(dG.size()) > window) {
        dG.erase(dG.begin());
        dF.erase(dF.begin());
      }
    }
    g_prev = g;
    f_prev = f;
    have_prev = true;
    Eigen::MatrixXd next = target;
    bool accelerated = false;
    if (!dF.empty() && window > 0) {
      const int k = static_cast<int>(dF.size());
      Eigen::MatrixXd A(f.size(), k);
      for (int j = 0; j < k; ++j) A.col(j) = dF[static_cast<size_t>(j)];
      Eigen::MatrixXd AtA = A.transpose() * A;
      AtA.diagonal().array() += 1e-10 * (AtA.diagonal().maxCoeff() + 1e-300);
      const Eigen::VectorXd theta = AtA.ldlt().solve(A.transpose() * f);
      if (theta.allFinite()) {
        Eigen::VectorXd x = g;
        for (int j = 0; j < k; ++j) x -= theta[j] * dG[static_cast<size_t>(j)];
        next = Eigen::Map<const Eigen::MatrixXd>(x.data(), n, 2);
        accelerated = true;
      }
    }
    double step = 1.0;
    auto advance = [&](const Eigen::MatrixXd& to) {
      const Eigen::MatrixXd dUV = to - UV;
      step = 1.0;
      if (injective) {
        const double t_root = max_flip_free_step(UV, dUV, F, 1.0 / options.line_search_margin);
        step = std::min(1.0, options.line_search_margin * t_root);
      }
      return Eigen::MatrixXd(UV + step * dUV);
    };
    Eigen::MatrixXd candidate = advance(next);
    Eigen::MatrixXd candidate_rhs;
    double next_energy = energy_and_rhs(candidate, &candidate_rhs);
    // Where a flat triangle is almost degenerate the flip-free step can be
    // so short that rounding still flips it: such a step is refused.
    const bool flips = injective && count_flips(candidate, F) > 0;
    if (accelerated && (flips || !(next_energy < run.energy))) {
      // The mixed iterate does not descend: the plain step, history cleared.
      dG.clear();
      dF.clear();
      candidate = advance(target);
      next_energy = energy_and_rhs(candidate, &candidate_rhs);
    }
    if (injective && count_flips(candidate, F) > 0) break;
    UV = candidate;
    rhs = candidate_rhs;
    run.iterations = it + 1;
    const double decrease = run.energy - next_energy;
    run.energy = next_energy;
    if (run.energy <= 1e-24 * area_scale) break;
    if (decrease <= options.tolerance * run.energy && step == 1.0) break;
  }
  return run;
}

}  // namespace gp
