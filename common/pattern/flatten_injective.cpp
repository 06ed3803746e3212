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

double symmetric_dirichlet_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& UV,
                                  const FlattenOptions& options) {
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, options.min_weight_fraction);
  double energy = 0.0;
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    if (t.degenerate) continue;
    const Eigen::Matrix2d J = jacobian(t, UV, F.row(f));
    const double det = J.determinant();
    if (!(det > 0.0)) return std::numeric_limits<double>::infinity();
    // |J|^2 + |J^-1|^2 - 4, and |J^-1|^2 = |J|^2 / det^2 for a 2x2 matrix.
    const double n2 = J.squaredNorm();
    energy += t.area * (n2 + n2 / (det * det) - 4.0);
  }
  return energy;
}

ArapRun injective_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                          const FlattenOptions& options) {
  const int n = static_cast<int>(V.rows());
  if (UV.rows() != n || UV.cols() != 2) throw GeometryError("injective_flatten: the start has the wrong size");
  if (count_flips(UV, F) > 0) throw GeometryError("injective_flatten: the start has flipped triangles");
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, options.min_weight_fraction);
  // Boundary edges keep their 3D length as in arap_flatten: w (|u_i - u_j| - l)^2,
  // majorized by w |u_i - u_j - l d|^2 with d the edge's current direction.
  const std::vector<BoundaryEdge> edges = boundary_edges(V, F, T, options.boundary_weight);
  auto energy_of = [&](const Eigen::MatrixXd& X) {
    double e = symmetric_dirichlet_energy(V, F, X, options);
    for (const auto& b : edges) {
      const double len = (X.row(b.i) - X.row(b.j)).norm();
      e += b.weight * (len - b.length) * (len - b.length);
    }
    return e;
  };
  // Unknowns: u of every vertex, then v; the first outline vertex is pinned.
  const auto loops = boundary_loops(F);
  const int pin = loops.empty() ? 0 : loops.front().front();
  auto index = [&](int vertex, int coordinate) {
    if (vertex == pin) return -1;
    const int k = vertex < pin ? vertex : vertex - 1;
    return coordinate * (n - 1) + k;
  };
  const int m = 2 * (n - 1);
  ArapRun run;
  run.energy = energy_of(UV);
  if (m <= 0 || !std::isfinite(run.energy)) return run;
  CholmodSolver solver{kFlattenSolver};
  bool analyzed = false;
  std::vector<Triplet> trip;
  const double area_scale = std::max(1e-300, std::accumulate(T.begin(), T.end(), 0.0,
                                                             [](double s, const LocalTriangle& t) { return s + t.area; }));
  for (int it = 0; it < options.max_iterations; ++it) {
    // Local step (Rabinovich et al. 2017, SLIM): per triangle the closest
    // rotation R = U V^T of J = U S V^T and the weight W = U diag(w) U^T,
    // w_i^2 = f'(s_i) / (2 (s_i - 1)) = (s^3 + s^2 + s + 1) / s^3 for
    // f(s) = s^2 + s^-2; the global step minimizes sum_t A_t |W (J - R)|^2.
    trip.clear();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
    for (int f = 0; f < F.rows(); ++f) {
      const LocalTriangle& t = T[static_cast<size_t>(f)];
      if (t.degenerate) continue;
      const Eigen::Matrix2d J = jacobian(t, UV, F.row(f));
      const Eigen::JacobiSVD<Eigen::Matrix2d> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Eigen::Matrix2d R = svd.matrixU() * svd.matrixV().transpose();
      Eigen::Vector2d w;
      for (int k = 0; k < 2; ++k) {
        const double s = std::max(svd.singularValues()[k], 1e-12);
        w[k] = std::sqrt((s * s * s + s * s + s + 1.0) / (s * s * s));
      }
      const Eigen::Matrix2d W = svd.matrixU() * w.asDiagonal() * svd.matrixU().transpose();
      const Eigen::Matrix2d WR = W * R;
      // Row i of W (J - R): sum_c W(i, c) D x_c - (W R)(i, :)^T, x_c the
      // corner values of coordinate c; 6 unknowns per triangle.
      for (int i = 0; i < 2; ++i) {
        Eigen::Matrix<double, 2, 6> A;
        A.leftCols<3>() = W(i, 0) * t.D;
        A.rightCols<3>() = W(i, 1) * t.D;
        const Eigen::Vector2d b = WR.row(i).transpose();
        const Eigen::Matrix<double, 6, 6> K = t.area * A.transpose() * A;
        const Eigen::Matrix<double, 6, 1> g = t.area * A.transpose() * b;
        int idx[6];
        Eigen::Matrix<double, 6, 1> known;
        for (int k = 0; k < 3; ++k) {
          idx[k] = index(F(f, k), 0);
          idx[k + 3] = index(F(f, k), 1);
          known[k] = UV(F(f, k), 0);
          known[k + 3] = UV(F(f, k), 1);
        }
        for (int a = 0; a < 6; ++a) {
          if (idx[a] < 0) continue;
          rhs[idx[a]] += g[a];
          for (int c = 0; c < 6; ++c) {
            if (idx[c] >= 0)
              trip.emplace_back(idx[a], idx[c], K(a, c));
            else
              rhs[idx[a]] -= K(a, c) * known[c];
          }
        }
      }
    }
    for (const auto& e : edges) {
      const Eigen::RowVector2d x = UV.row(e.i) - UV.row(e.j);
      const double len = x.norm();
      const Eigen::RowVector2d target = len > 0.0 ? Eigen::RowVector2d(e.length * x / len) : Eigen::RowVector2d(e.length, 0.0);
      for (int c = 0; c < 2; ++c) {
        const int a = index(e.i, c), b = index(e.j, c);
        if (a >= 0) trip.emplace_back(a, a, e.weight), rhs[a] += e.weight * target[c];
        if (b >= 0) trip.emplace_back(b, b, e.weight), rhs[b] -= e.weight * target[c];
        if (a >= 0 && b >= 0) trip.emplace_back(a, b, -e.weight), trip.emplace_back(b, a, -e.weight);
        if (a >= 0 && b < 0) rhs[a] += e.weight * UV(e.j, c);
        if (b >= 0 && a < 0) rhs[b] += e.weight * UV(e.i, c);
      }
    }
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(trip.begin(), trip.end());
    // A vertex whose triangles are all degenerate carries no energy: a tiny
    // proximal term keeps the system definite without moving the fixed point.
    const double proximal = 1e-10 * A.diagonal().sum() / m;
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c)
        if (index(i, c) >= 0) rhs[index(i, c)] += proximal * UV(i, c);
    Eigen::SparseMatrix<double> I(m, m);
    I.setIdentity();
    A += proximal * I;
    if (!analyzed) solver.analyze(A), analyzed = true;
    solver.factorize(A);
    const Eigen::VectorXd x = solver.solve(rhs);
    if (!x.allFinite()) break;
    Eigen::MatrixXd dUV = Eigen::MatrixXd::Zero(n, 2);
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 2; ++c)
        if (index(i, c) >= 0) dUV(i, c) = x[index(i, c)] - UV(i, c);
    // The step: at most 90 % of the largest flip-free one, halved until the
    // energy (infinite at a degenerate triangle) decreases.
    double step = std::min(1.0, options.line_search_margin * max_flip_free_step(UV, dUV, F, 1.0 / options.line_search_margin));
    double next = std::numeric_limits<double>::infinity();
    Eigen::MatrixXd candidate;
    for (int halving = 0; halving < 30; ++halving, step *= 0.5) {
      candidate = UV + step * dUV;
      next = count_flips(candidate, F) == 0 ? energy_of(candidate) : std::numeric_limits<double>::infinity();
      if (next < run.energy) break;
    }
    if (!(next < run.energy)) break;
    UV = candidate;
    const double decrease = run.energy - next;
    run.energy = next;
    run.iterations = it + 1;
    if (run.energy <= 1e-24 * area_scale) break;
    if (decrease <= options.injective_tolerance * run.energy) break;
  }
  return run;
}

}  // namespace gp
