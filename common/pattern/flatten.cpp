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

namespace gp {
namespace {

using Triplet = Eigen::Triplet<double>;

// Simplicial: it calls no BLAS, so a flattening is bitwise the same whichever
// kernels OpenBLAS picks for the CPU, and for these 2D Laplacians of single
// pieces it is also the faster method (see common/pattern/README.md).
const CholmodOptions kFlattenSolver{CholmodOptions::Method::simplicial};

// A triangle in an orthonormal frame of its own plane: corner 0 at the origin,
// corner 1 on the x axis. D maps corner values (3) to the gradient (2), so the
// Jacobian of the flat map with corner positions U (3 by 2) is J = (D U)^T.
struct LocalTriangle {
  Eigen::Matrix<double, 2, 3> D = Eigen::Matrix<double, 2, 3>::Zero();
  double area = 0.0;
  bool degenerate = true;
};

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
std::vector<LocalTriangle> weighted_triangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double fraction) {
  std::vector<LocalTriangle> T = local_triangles(V, F);
  double mean = 0.0;
  int count = 0;
  for (const LocalTriangle& t : T)
    if (!t.degenerate) mean += t.area, ++count;
  mean /= std::max(1, count);
  for (LocalTriangle& t : T)
    if (!t.degenerate) t.area = std::max(t.area, fraction * mean);
  return T;
}

// A boundary edge i -> j of 3D length `length` and the weight of keeping it
// (the boundary-length term of flattening_energy).
struct BoundaryEdge {
  int i, j;
  double length, weight;
};

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

}  // namespace

Eigen::MatrixXd flattening_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const Eigen::MatrixXd& UV) {
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  Eigen::MatrixXd S(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    S.row(f) = t.degenerate ? Eigen::RowVector2d(1.0, 1.0)
                            : singular_values_2x2(jacobian(t, UV, F.row(f))).transpose();
  }
  return S;
}

DistortionStats distortion_stats(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const Eigen::MatrixXd& UV) {
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  Eigen::VectorXd area(F.rows()), area_2d(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    area[f] = T[static_cast<size_t>(f)].area;
    area_2d[f] = signed_area_2d(UV, F.row(f));
  }
  return distortion_stats(flattening_stretches(V, F, UV), area, area_2d);
}

DistortionStats distortion_stats(const Eigen::MatrixXd& S, const Eigen::VectorXd& area_3d,
                                 const Eigen::VectorXd& area_2d) {
  DistortionStats st;
  const int m = static_cast<int>(S.rows());
  if (m == 0) return st;
  std::vector<double> err(static_cast<size_t>(m)), str(static_cast<size_t>(m)), com(static_cast<size_t>(m));
  st.max_error = st.max_stretch = st.max_compression = -std::numeric_limits<double>::infinity();
  double weighted = 0.0;
  for (int f = 0; f < m; ++f) {
    const size_t i = static_cast<size_t>(f);
    st.area_3d += area_3d[f];
    st.area_2d += area_2d[f];
    if (!(area_2d[f] > 0.0)) ++st.flipped_triangles;
    str[i] = S(f, 0) - 1.0;
    com[i] = 1.0 - S(f, 1);
    err[i] = std::max(std::abs(S(f, 0) - 1.0), std::abs(S(f, 1) - 1.0));
    st.max_error = std::max(st.max_error, err[i]);
    st.max_stretch = std::max(st.max_stretch, str[i]);
    st.max_compression = std::max(st.max_compression, com[i]);
    weighted += area_3d[f] * err[i];
  }
  st.mean_error = st.area_3d > 0.0 ? weighted / st.area_3d : 0.0;
  auto percentile = [&](const std::vector<double>& value, double fraction) {
    return area_weighted_percentile(Eigen::Map<const Eigen::VectorXd>(value.data(), m), area_3d, fraction);
  };
  // Mean of the values over the worst `fraction` of the area.
  auto worst_mean = [&](const std::vector<double>& value, double fraction) {
    std::vector<int> order(static_cast<size_t>(m));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return value[static_cast<size_t>(a)] > value[static_cast<size_t>(b)] ||
             (value[static_cast<size_t>(a)] == value[static_cast<size_t>(b)] && a < b);
    });
    const double want = fraction * st.area_3d;
    double acc = 0.0, sum = 0.0;
    for (int f : order) {
      const double take = std::min(area_3d[f], want - acc);
      if (take <= 0.0) break;
      sum += take * value[static_cast<size_t>(f)];
      acc += take;
    }
    return acc > 0.0 ? sum / acc : 0.0;
  };
  st.worst1_compression = worst_mean(com, 0.01);
  st.worst5_ease = worst_mean(str, 0.05);
  st.p95_error = percentile(err, 0.95);
  st.p95_stretch = percentile(str, 0.95);
  st.p95_compression = percentile(com, 0.95);
  st.p99_compression = percentile(com, 0.99);
  return st;
}

bool polygon_self_intersects(const Eigen::MatrixXd& P, std::vector<int>* vertex_ids,
                             const std::vector<int>* material_ids) {
  const int n = static_cast<int>(P.rows());
  if (n < 4) return false;
  auto orient = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    const double v = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    return (v > 0.0) - (v < 0.0);
  };
  auto on_segment = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) &&
           std::min(a.y(), b.y()) <= c.y() && c.y() <= std::max(a.y(), b.y());
  };
  // Sweep over segments sorted by their left end: only segments whose x
  // ranges overlap are tested.
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  auto xmin = [&](int i) { return std::min(P(i, 0), P((i + 1) % n, 0)); };
  auto xmax = [&](int i) { return std::max(P(i, 0), P((i + 1) % n, 0)); };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return xmin(a) < xmin(b) || (xmin(a) == xmin(b) && a < b); });
  bool found = false;
  for (size_t ia = 0; ia < order.size(); ++ia) {
    const int i = order[ia];
    const Eigen::Vector2d a = P.row(i), b = P.row((i + 1) % n);
    for (size_t ib = ia + 1; ib < order.size() && xmin(order[ib]) <= xmax(i); ++ib) {
      const int j = order[ib];
      if (j == (i + 1) % n || i == (j + 1) % n) continue;
      if (material_ids) {
        const auto& m = *material_ids;
        const int mi0 = m[static_cast<size_t>(i)], mi1 = m[static_cast<size_t>((i + 1) % n)];
        const int mj0 = m[static_cast<size_t>(j)], mj1 = m[static_cast<size_t>((j + 1) % n)];
        if (mi0 == mj0 || mi0 == mj1 || mi1 == mj0 || mi1 == mj1) continue;
      }
      const Eigen::Vector2d c = P.row(j), d = P.row((j + 1) % n);
      const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
      bool hit = (o1 != o2 && o3 != o4);
      if (!hit)
        hit = (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
              (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
      if (hit) {
        found = true;
        if (!vertex_ids) return true;
        vertex_ids->push_back(std::min(i, j));
        vertex_ids->push_back(std::max(i, j));
      }
    }
  }
  if (vertex_ids) {
    std::sort(vertex_ids->begin(), vertex_ids->end());
    vertex_ids->erase(std::unique(vertex_ids->begin(), vertex_ids->end()), vertex_ids->end());
  }
  return found;
}

Eigen::MatrixXd lscm_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop,
                             double min_weight_fraction) {
  const int n = static_cast<int>(V.rows());
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, min_weight_fraction);
  // Per triangle, w/2 |D u - R D v|^2 with R the quarter turn (u_x = v_y,
  // u_y = -v_x): the Cauchy-Riemann residual, whose area-weighted sum is the
  // conformal energy of Levy et al. 2002 (Mullen et al. 2008, eq. 4: the
  // Dirichlet energy minus the flat area). Assembled per triangle so that a
  // thin triangle can weigh more than its area.
  std::vector<Triplet> trip;
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    if (t.degenerate) continue;
    Eigen::Matrix<double, 2, 6> M;
    M.leftCols<3>() = t.D;
    M.rightCols<3>().row(0) = -t.D.row(1);
    M.rightCols<3>().row(1) = t.D.row(0);
    const Eigen::Matrix<double, 6, 6> K = t.area * M.transpose() * M;
    int idx[6];
    for (int k = 0; k < 3; ++k) idx[k] = F(f, k), idx[k + 3] = F(f, k) + n;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) trip.emplace_back(idx[i], idx[j], K(i, j));
  }
  Eigen::SparseMatrix<double> H(2 * n, 2 * n);
  H.setFromTriplets(trip.begin(), trip.end());
  const auto [p, q] = far_pair(V, loop);
  Eigen::VectorXd fixed = Eigen::VectorXd::Constant(2 * n, std::numeric_limits<double>::quiet_NaN());
  fixed[p] = 0.0;
  fixed[p + n] = 0.0;
  fixed[q] = (V.row(p) - V.row(q)).norm();
  fixed[q + n] = 0.0;
  const Eigen::VectorXd x = solve_with_fixed(H, fixed);
  Eigen::MatrixXd UV(n, 2);
  UV.col(0) = x.head(n);
  UV.col(1) = x.tail(n);
  double total = 0.0;
  for (int f = 0; f < F.rows(); ++f) total += signed_area_2d(UV, F.row(f));
  if (total < 0.0) UV.col(0) *= -1.0;
  return UV;
}

Eigen::MatrixXd tutte_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop) {
  const int n = static_cast<int>(V.rows());
  double perimeter = 0.0;
  std::vector<double> s(loop.size(), 0.0);
  for (size_t k = 0; k < loop.size(); ++k) {
    s[k] = perimeter;
    perimeter += (V.row(loop[(k + 1) % loop.size()]) - V.row(loop[k])).norm();
  }
  const double radius = perimeter / (2.0 * M_PI);
  Eigen::VectorXd fixed = Eigen::VectorXd::Constant(2 * n, std::numeric_limits<double>::quiet_NaN());
  for (size_t k = 0; k < loop.size(); ++k) {
    const double angle = 2.0 * M_PI * s[k] / perimeter;
    fixed[loop[k]] = radius * gp::math::cos(angle);
    fixed[loop[k] + n] = radius * gp::math::sin(angle);
  }
  const auto neighbors = vertex_neighbors(F, n);
  std::vector<Triplet> trip;
  for (int i = 0; i < n; ++i)
    for (int j : neighbors[static_cast<size_t>(i)]) {
      trip.emplace_back(i, i, 1.0);
      trip.emplace_back(i, j, -1.0);
      trip.emplace_back(i + n, i + n, 1.0);
      trip.emplace_back(i + n, j + n, -1.0);
    }
  Eigen::SparseMatrix<double> H(2 * n, 2 * n);
  H.setFromTriplets(trip.begin(), trip.end());
  const Eigen::VectorXd x = solve_with_fixed(H, fixed);
  Eigen::MatrixXd UV(n, 2);
  UV.col(0) = x.head(n);
  UV.col(1) = x.tail(n);
  return UV;
}

double flattening_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& UV,
                         const FlattenOptions& options, Eigen::MatrixXd* gradient) {
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, options.min_weight_fraction);
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

ArapRun arap_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                     const FlattenOptions& options, bool injective) {
  const int n = static_cast<int>(V.rows());
  if (UV.rows() != n || UV.cols() != 2) throw GeometryError("arap_flatten: the start has the wrong size");
  const std::vector<LocalTriangle> T = weighted_triangles(V, F, options.min_weight_fraction);
  const double ease_weight = std::clamp(options.ease_weight, 0.0, 1.0);
  // Boundary edges (i -> j, 3D length l, weight w): the term
  // w |u_i - u_j - l d|^2 with d the current unit direction of the flat edge
  // joins the local step (d) and the global step (a constant matrix), like the
  // edge springs of a local/global solver (Liu et al. 2008; Bouaziz et al.
  // 2014, projective dynamics).
  const std::vector<BoundaryEdge> edges = boundary_edges(V, F, T, options.boundary_weight);
  // One pinned vertex removes the translation; L is factorized once.
  Eigen::SparseMatrix<double> L = dirichlet_matrix(T, F, n);
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
  const int pin = loops.empty() ? 0 : loops.front().front();
  std::vector<int> free_index(static_cast<size_t>(n), -1);
  int m = 0;
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
  const double proximal = 1e-10 * diagonal / std::max(1, m);
  for (int i = 0; i < m; ++i) trip.emplace_back(i, i, proximal);
  CholmodSolver solver{kFlattenSolver};
  if (m > 0) {
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(trip.begin(), trip.end());
    solver.compute(A);
  }

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

namespace {

// The result's distortion figures and the overlaps of its outline.
void measure_result(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop,
                    const Eigen::VectorXi* material_ids, FlattenResult& result) {
  result.stats = distortion_stats(V, F, result.UV);
  Eigen::MatrixXd P(static_cast<int>(loop.size()), 2);
  for (size_t k = 0; k < loop.size(); ++k) P.row(static_cast<int>(k)) = result.UV.row(loop[k]);
  std::vector<int> at, material;
  if (material_ids)
    for (int v : loop) material.push_back((*material_ids)[v]);
  result.overlap_vertex_ids.clear();
  result.boundary_overlaps = polygon_self_intersects(P, &at, material_ids ? &material : nullptr);
  for (int k : at) result.overlap_vertex_ids.push_back(loop[static_cast<size_t>(k)]);
}

}  // namespace

FlattenResult flatten_piece(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            const FlattenOptions& options, const Eigen::VectorXi* material_ids) {
  const auto loops = boundary_loops(F);
  if (loops.size() != 1 || euler_characteristic(F) != 1)
    throw GeometryError("a piece to flatten must be a disk (one boundary loop, Euler characteristic 1); it has " +
                        std::to_string(loops.size()) + " boundary loops and Euler characteristic " +
                        std::to_string(euler_characteristic(F)));
  if (!V.allFinite()) throw GeometryError("the piece has non-finite vertex coordinates");
  const std::vector<int>& loop = loops.front();

  FlattenResult result;
  Eigen::MatrixXd UV_lscm;
  bool lscm_solved = false;
  try {
    UV_lscm = lscm_flatten(V, F, loop, options.min_weight_fraction);
    lscm_solved = UV_lscm.allFinite();
  } catch (const NumericalError&) {
    lscm_solved = false;
  }
  // Plain iterations from LSCM first (fastest to converge). Flipped
  // triangles they leave are untangled locally and the iterations resumed
  // injectively from there; if that fails, injective iterations from a
  // flip-free start (LSCM when it has no flips, else Tutte's embedding)
  // guarantee a flip-free result.
  bool done = false;
  if (lscm_solved) {
    result.UV = UV_lscm;
    result.initialization = "lscm";
    const ArapRun run = arap_flatten(V, F, result.UV, options, false);
    result.iterations = run.iterations;
    result.energy = run.energy;
    done = result.UV.allFinite() && (count_flips(result.UV, F) == 0 || !options.injective_fallback);
    if (!done && result.UV.allFinite()) {
      Eigen::MatrixXd repaired = result.UV;
      if (repair_flips(F, vertex_neighbors(F, static_cast<int>(V.rows())), loop, repaired)) {
        // Plain iterations again from the untangled map (they often settle
        // without the flips now); injective ones where they do not.
        Eigen::MatrixXd again = repaired;
        const ArapRun plain = arap_flatten(V, F, again, options, false);
        result.iterations += plain.iterations;
        if (again.allFinite() && count_flips(again, F) == 0) {
          result.UV = again;
          result.initialization = "lscm, untangled";
          result.energy = plain.energy;
          done = true;
        } else {
          result.UV = repaired;
          result.initialization = "lscm, untangled, injective";
          FlattenOptions longer = options;
          longer.max_iterations = 4 * options.max_iterations;
          const ArapRun more = injective_flatten(V, F, result.UV, longer);
          result.iterations += more.iterations;
          result.energy = more.energy;
          done = count_flips(result.UV, F) == 0;
        }
      }
    }
  }
  if (!done) {
    const FlattenResult plain = result;
    bool start = true;
    if (lscm_solved && count_flips(UV_lscm, F) == 0) {
      result.UV = UV_lscm;
      result.initialization = "lscm, injective";
    } else {
      result.UV = tutte_flatten(V, F, loop);
      result.initialization = "tutte, injective";
      // A piece that is not 3-connected (a vertex whose neighbours all lie
      // on the outline) can fold even in Tutte's embedding.
      start = count_flips(result.UV, F) == 0;
    }
    if (start) {
      const ArapRun run = injective_flatten(V, F, result.UV, options);
      result.iterations += run.iterations;
      result.energy = run.energy;
    } else if (plain.UV.size() > 0 && plain.UV.allFinite()) {
      // No flip-free start: the plain flattening with its flips (reported).
      result = plain;
      result.initialization += ", flips kept";
    } else {
      // Nor a plain one (LSCM failed): plain iterations from Tutte's folded embedding.
      const ArapRun run = arap_flatten(V, F, result.UV, options, false);
      result.initialization = "tutte, flips kept";
      result.iterations = run.iterations;
      result.energy = run.energy;
    }
  }
  if (!result.UV.allFinite()) throw NumericalError("the flattening produced non-finite coordinates");
  measure_result(V, F, loop, material_ids, result);
  return result;
}

void polish_flattening(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FlattenResult& result,
                       const FlattenOptions& options, const Eigen::VectorXi* material_ids) {
  // Injective results minimise another energy, and a piece that kept its
  // flips has no flip-free start.
  if (result.initialization.find("injective") != std::string::npos || count_flips(result.UV, F) > 0) return;
  FlattenOptions tight = options;
  tight.tolerance = options.final_tolerance;
  tight.max_iterations = 20 * options.max_iterations;
  Eigen::MatrixXd UV = result.UV;
  // Plain steps (the line search would only shorten them); a polish that
  // folds the piece is not taken.
  const ArapRun run = arap_flatten(V, F, UV, tight, false);
  if (!UV.allFinite() || count_flips(UV, F) > 0 || !(run.energy <= result.energy)) return;
  result.UV = UV;
  result.iterations += run.iterations;
  result.energy = run.energy;
  measure_result(V, F, boundary_loops(F).front(), material_ids, result);
}

}  // namespace gp
