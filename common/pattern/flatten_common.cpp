#include "pattern/flatten_common.h"

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

namespace gp::flatten_detail {

std::vector<LocalTriangle> local_triangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<LocalTriangle> T(static_cast<size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d x0 = V.row(F(f, 0)), x1 = V.row(F(f, 1)), x2 = V.row(F(f, 2));
    const Eigen::Vector3d e1 = x1 - x0, e2 = x2 - x0;
    const double l1 = e1.norm();
    const double cross = e1.cross(e2).norm();
    const double scale = std::max({e1.squaredNorm(), e2.squaredNorm(), (x2 - x1).squaredNorm()});
    LocalTriangle& t = T[static_cast<size_t>(f)];
    // A triangle whose area is below 1e-14 of its squared longest edge has no
    // usable plane (its angles are lost in rounding); it carries no energy and
    // is kept only in the flip checks.
    if (!(l1 > 0.0) || !(cross > 1e-14 * scale) || !std::isfinite(cross)) continue;
    Eigen::Matrix2d P;  // columns: corners 1 and 2 in the local frame
    P << l1, e2.dot(e1) / l1, 0.0, cross / l1;
    Eigen::Matrix<double, 2, 3> S;
    S << -1, 1, 0, -1, 0, 1;
    t.D = P.transpose().inverse() * S;
    t.area = 0.5 * cross;
    t.degenerate = false;
  }
  return T;
}

// local_triangles with every area raised to at least `fraction` of the
// mean: the weights of the flattening energies. The thin triangles a cut
// leaves where it passes close to a vertex would otherwise turn over at no
// cost (and make LSCM's system numerically singular); a stiff small triangle
// keeps its shape, so its share of the energy still vanishes with its size.
std::vector<LocalTriangle> weighted_triangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double fraction,
                                              const Eigen::VectorXd* face_weight) {
  std::vector<LocalTriangle> T = local_triangles(V, F);
  double mean = 0.0;
  int count = 0;
  for (const LocalTriangle& t : T)
    if (!t.degenerate) mean += t.area, ++count;
  mean /= std::max(1, count);
  for (LocalTriangle& t : T)
    if (!t.degenerate) t.area = std::max(t.area, fraction * mean);
  if (face_weight && face_weight->size() == F.rows())
    for (int f = 0; f < F.rows(); ++f) T[static_cast<size_t>(f)].area *= (*face_weight)[f];
  return T;
}

// The boundary edges of the non-degenerate triangles T (weighted_triangles),
// weighted relative to the edge's own triangle at its true area: a thin
// triangle's raised weight must not make its short edge a hard constraint.
std::vector<BoundaryEdge> boundary_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                         const std::vector<LocalTriangle>& T, double boundary_weight) {
  std::vector<BoundaryEdge> edges;
  if (!(boundary_weight > 0.0)) return edges;
  const std::vector<LocalTriangle> T0 = local_triangles(V, F);
  const Eigen::MatrixXi TT = triangle_adjacency(F);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (TT(f, k) < 0 && !T[static_cast<size_t>(f)].degenerate) {
        const int i = F(f, k), j = F(f, (k + 1) % 3);
        const double l = (V.row(i) - V.row(j)).norm();
        if (l > 0.0) edges.push_back({i, j, l, boundary_weight * T0[static_cast<size_t>(f)].area / (l * l)});
      }
  return edges;
}

Eigen::Matrix2d jacobian(const LocalTriangle& t, const Eigen::MatrixXd& UV, const Eigen::Vector3i& f) {
  Eigen::Matrix<double, 3, 2> U;
  for (int k = 0; k < 3; ++k) U.row(k) = UV.row(f[k]);
  return (t.D * U).transpose();
}

double signed_area_2d(const Eigen::MatrixXd& UV, const Eigen::Vector3i& f) {
  const Eigen::Vector2d a = UV.row(f[1]) - UV.row(f[0]);
  const Eigen::Vector2d b = UV.row(f[2]) - UV.row(f[0]);
  return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

// The local step of the energy sum_i f(s_i) over the singular values s_i of
// J, f(s) = (1 - s)^2 below 1 and ease_weight (s - 1)^2 above: the target
// T = J - grad / 2 = U diag(t(s)) V^T with t(s) = 1 below 1 and
// 1 + (1 - ease_weight)(s - 1) above (J = U diag(s) V^T in closed form,
// s_y < 0 when J flips). With ease_weight <= 1 the quadratic |J - T|^2 about
// the current J majorizes the energy, so the global step never raises it
// (local/global as majorization-minimization). A flipped J goes to its
// closest rotation, as in ARAP. Returns T; `energy` gets sum_i f(s_i).
Eigen::Matrix2d local_target(const Eigen::Matrix2d& J, double ease_weight, double& energy) {
  // J = Q+ + Q-, Q+ = [e -h; h e] = q R(a) (its similarity part), Q- = [f g;
  // g -f] = r S(b) (a reflection times r); J's singular values are q + r and
  // q - r, and a matrix with the same singular vectors and singular values
  // (tx, ty) is (tx + ty)/2 R(a) + (tx - ty)/2 S(b): no angle is needed.
  const double e = 0.5 * (J(0, 0) + J(1, 1)), f = 0.5 * (J(0, 0) - J(1, 1));
  const double g = 0.5 * (J(1, 0) + J(0, 1)), h = 0.5 * (J(1, 0) - J(0, 1));
  const double q = std::sqrt(e * e + h * h), r = std::sqrt(f * f + g * g);
  const double sx = q + r, sy = q - r;
  Eigen::Matrix2d plus, minus;
  plus << e, -h, h, e;
  minus << f, g, g, -f;
  if (!(q > 0.0)) {
    // No similarity part: J is a reflection times r; its closest rotation is any, take I.
    energy = (sx - 1.0) * (sx - 1.0) + (sy - 1.0) * (sy - 1.0);
    return Eigen::Matrix2d::Identity();
  }
  if (!(sy > 0.0)) {
    // Flipped (or degenerate): the closest rotation, as in ARAP.
    energy = (sx - 1.0) * (sx - 1.0) + (sy - 1.0) * (sy - 1.0);
    return plus / q;
  }
  auto target = [&](double s) { return s < 1.0 ? 1.0 : 1.0 + (1.0 - ease_weight) * (s - 1.0); };
  auto cost = [&](double s) { return s < 1.0 ? (1.0 - s) * (1.0 - s) : ease_weight * (s - 1.0) * (s - 1.0); };
  const double tx = target(sx), ty = target(sy);
  energy = cost(sx) + cost(sy);
  Eigen::Matrix2d T = (0.5 * (tx + ty) / q) * plus;
  if (r > 0.0) T += (0.5 * (tx - ty) / r) * minus;
  return T;
}

// Dirichlet matrix L = sum_t A_t D_t^T D_t (the cotangent Laplacian, PSD by construction).
Eigen::SparseMatrix<double> dirichlet_matrix(const std::vector<LocalTriangle>& T,
                                             const Eigen::MatrixXi& F, int n) {
  std::vector<Triplet> trip;
  trip.reserve(static_cast<size_t>(F.rows()) * 9);
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    if (t.degenerate) continue;
    const Eigen::Matrix3d K = t.area * t.D.transpose() * t.D;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) trip.emplace_back(F(f, i), F(f, j), K(i, j));
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(trip.begin(), trip.end());
  return L;
}

// Solves the quadratic problem min 1/2 x^T H x with the variables in `fixed`
// (value per variable, NaN when free) held: H_ff x_f = -H_fp x_p.
Eigen::VectorXd solve_with_fixed(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& fixed) {
  const int n = static_cast<int>(H.rows());
  std::vector<int> free_index(static_cast<size_t>(n), -1);
  int m = 0;
  for (int i = 0; i < n; ++i)
    if (std::isnan(fixed[i])) free_index[static_cast<size_t>(i)] = m++;
  Eigen::VectorXd x = fixed;
  if (m == 0) return x;
  std::vector<Triplet> trip;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
  for (int c = 0; c < H.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, c); it; ++it) {
      const int r = static_cast<int>(it.row());
      const int fr = free_index[static_cast<size_t>(r)], fc = free_index[static_cast<size_t>(c)];
      if (fr < 0) continue;
      if (fc >= 0)
        trip.emplace_back(fr, fc, it.value());
      else
        b[fr] -= it.value() * fixed[c];
    }
  Eigen::SparseMatrix<double> A(m, m);
  A.setFromTriplets(trip.begin(), trip.end());
  CholmodSolver solver{kFlattenSolver};
  solver.compute(A);
  const Eigen::VectorXd y = solver.solve(b);
  for (int i = 0; i < n; ++i)
    if (free_index[static_cast<size_t>(i)] >= 0) x[i] = y[free_index[static_cast<size_t>(i)]];
  return x;
}

// Two boundary vertices far apart (the first one farthest from the loop's
// first vertex, the second farthest from it), to pin LSCM's similarity freedom.
std::pair<int, int> far_pair(const Eigen::MatrixXd& V, const std::vector<int>& loop) {
  auto farthest = [&](int from) {
    int best = loop.front();
    double best_d = -1.0;
    for (int v : loop) {
      const double d = (V.row(v) - V.row(from)).squaredNorm();
      if (d > best_d) best_d = d, best = v;
    }
    return best;
  };
  const int a = farthest(loop.front());
  return {a, farthest(a)};
}

int count_flips(const Eigen::MatrixXd& UV, const Eigen::MatrixXi& F) {
  int flips = 0;
  for (int f = 0; f < F.rows(); ++f)
    if (!(signed_area_2d(UV, F.row(f)) > 0.0)) ++flips;
  return flips;
}

// Largest t in (0, t_cap] such that every triangle keeps a positive area on
// UV + t dUV: the smallest positive root of each triangle's area, a quadratic
// in t (Smith and Schaefer 2015, section 4.2).
double max_flip_free_step(const Eigen::MatrixXd& UV, const Eigen::MatrixXd& dUV,
                          const Eigen::MatrixXi& F, double t_cap) {
  double t_max = t_cap;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector2d e1 = UV.row(F(f, 1)) - UV.row(F(f, 0)), e2 = UV.row(F(f, 2)) - UV.row(F(f, 0));
    const Eigen::Vector2d d1 = dUV.row(F(f, 1)) - dUV.row(F(f, 0)), d2 = dUV.row(F(f, 2)) - dUV.row(F(f, 0));
    auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
    const double c = cross(e1, e2);
    const double b = cross(e1, d2) + cross(d1, e2);
    const double a = cross(d1, d2);
    // Smallest positive root of a t^2 + b t + c (c > 0).
    double root = std::numeric_limits<double>::infinity();
    if (std::abs(a) <= 1e-300 * std::max(1.0, std::abs(b))) {
      if (b < 0.0) root = -c / b;
    } else {
      const double disc = b * b - 4.0 * a * c;
      if (disc >= 0.0) {
        const double sq = std::sqrt(disc);
        // Numerically stable pair of roots.
        const double qq = -0.5 * (b + (b >= 0.0 ? sq : -sq));
        const double r1 = qq / a, r2 = qq != 0.0 ? c / qq : std::numeric_limits<double>::infinity();
        for (double r : {r1, r2})
          if (r > 0.0 && r < root) root = r;
      }
    }
    t_max = std::min(t_max, root);
  }
  return t_max;
}

// Untangles the few flipped triangles a plain flattening can leave (at a
// sharp concave corner of the outline, or thin triangles along a cut): the
// vertices within `rings` rings of a flipped triangle are smoothed towards
// the mean of their neighbours (Jacobi, a few passes; outline vertices
// towards the mean of their two outline neighbours), the region growing by
// a ring when that does not suffice. Whether no flip is left.
bool repair_flips(const Eigen::MatrixXi& F, const std::vector<std::vector<int>>& neighbors,
                  const std::vector<int>& loop, Eigen::MatrixXd& UV) {
  const int n = static_cast<int>(UV.rows());
  std::vector<std::array<int, 2>> outline(static_cast<size_t>(n), {-1, -1});
  for (size_t k = 0; k < loop.size(); ++k)
    outline[static_cast<size_t>(loop[k])] = {loop[(k + loop.size() - 1) % loop.size()], loop[(k + 1) % loop.size()]};
  const Eigen::MatrixXd start = UV;
  for (int rings = 0; rings <= 6; ++rings) {
    UV = start;
    for (int round = 0; round < 4; ++round) {
      std::vector<char> move(static_cast<size_t>(n), 0);
      std::vector<int> frontier;
      for (int f = 0; f < F.rows(); ++f)
        if (!(signed_area_2d(UV, F.row(f)) > 0.0))
          for (int k = 0; k < 3; ++k)
            if (!move[static_cast<size_t>(F(f, k))]) {
              move[static_cast<size_t>(F(f, k))] = 1;
              frontier.push_back(F(f, k));
            }
      if (frontier.empty()) return true;
      for (int r = 0; r < rings; ++r) {
        std::vector<int> next;
        for (int v : frontier)
          for (int w : neighbors[static_cast<size_t>(v)])
            if (!move[static_cast<size_t>(w)]) {
              move[static_cast<size_t>(w)] = 1;
              next.push_back(w);
            }
        frontier = next;
      }
      for (int pass = 0; pass < 10 * (rings + 1); ++pass) {
        const Eigen::MatrixXd before = UV;
        for (int v = 0; v < n; ++v) {
          if (!move[static_cast<size_t>(v)]) continue;
          const auto& o = outline[static_cast<size_t>(v)];
          if (o[0] >= 0) {
            UV.row(v) = 0.5 * (before.row(o[0]) + before.row(o[1]));
          } else if (!neighbors[static_cast<size_t>(v)].empty()) {
            Eigen::RowVector2d mean = Eigen::RowVector2d::Zero();
            for (int w : neighbors[static_cast<size_t>(v)]) mean += before.row(w);
            UV.row(v) = mean / static_cast<double>(neighbors[static_cast<size_t>(v)].size());
          }
        }
      }
    }
    if (count_flips(UV, F) == 0) return true;
  }
  UV = start;
  return false;
}

}  // namespace gp::flatten_detail
