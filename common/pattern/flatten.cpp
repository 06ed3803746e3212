#include "pattern/flatten.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/math.h"
#include "linalg/cholmod_solver.h"
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

// Closest rotation to a 2x2 matrix (polar decomposition), in closed form: for
// J = [a b; c d] the rotation maximizing tr(R^T J) has angle atan2(c - b, a + d).
Eigen::Matrix2d closest_rotation(const Eigen::Matrix2d& J) {
  const double angle = gp::math::atan2(J(1, 0) - J(0, 1), J(0, 0) + J(1, 1));
  Eigen::Matrix2d R;
  R << gp::math::cos(angle), -gp::math::sin(angle), gp::math::sin(angle), gp::math::cos(angle);
  return R;
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

Eigen::MatrixXd lscm(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const std::vector<LocalTriangle>& T, const std::vector<int>& loop) {
  const int n = static_cast<int>(V.rows());
  const Eigen::SparseMatrix<double> L = dirichlet_matrix(T, F, n);
  std::vector<Triplet> trip;
  for (int c = 0; c < L.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it) {
      trip.emplace_back(static_cast<int>(it.row()), c, it.value());
      trip.emplace_back(static_cast<int>(it.row()) + n, c + n, it.value());
    }
  // Minus the signed flat area 1/2 sum_(i->j) (u_i v_j - u_j v_i) over the
  // boundary (Levy et al. 2002; Mullen et al. 2008, eq. 4): E_C = E_D - A.
  for (size_t k = 0; k < loop.size(); ++k) {
    const int i = loop[k], j = loop[(k + 1) % loop.size()];
    trip.emplace_back(i, j + n, -0.5);
    trip.emplace_back(j + n, i, -0.5);
    trip.emplace_back(j, i + n, 0.5);
    trip.emplace_back(i + n, j, 0.5);
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
  return UV;
}

// Tutte's embedding (uniform weights) with the boundary on a circle spaced by
// 3D arc length: flip-free for any disk (Floater 2003), used when LSCM flips.
Eigen::MatrixXd tutte(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop) {
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

}  // namespace

Eigen::MatrixXd principal_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& UV) {
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  Eigen::MatrixXd S(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    if (t.degenerate) {
      S.row(f) << 1.0, 1.0;
      continue;
    }
    const Eigen::Matrix2d J = jacobian(t, UV, F.row(f));
    // Closed-form singular values of a 2x2 matrix.
    const double e = 0.5 * (J(0, 0) + J(1, 1)), ff = 0.5 * (J(0, 0) - J(1, 1));
    const double g = 0.5 * (J(1, 0) + J(0, 1)), h = 0.5 * (J(1, 0) - J(0, 1));
    const double q = std::hypot(e, h), r = std::hypot(ff, g);
    S.row(f) << q + r, std::abs(q - r);
  }
  return S;
}

DistortionStats distortion_stats(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const Eigen::MatrixXd& UV) {
  DistortionStats st;
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  const Eigen::MatrixXd S = principal_stretches(V, F, UV);
  const int m = static_cast<int>(F.rows());
  std::vector<double> err(static_cast<size_t>(m)), str(static_cast<size_t>(m)), com(static_cast<size_t>(m)),
      area(static_cast<size_t>(m));
  st.max_error = st.max_stretch = st.max_compression = -std::numeric_limits<double>::infinity();
  double weighted = 0.0;
  for (int f = 0; f < m; ++f) {
    const size_t i = static_cast<size_t>(f);
    area[i] = T[i].area;
    st.area_3d += area[i];
    const double a2 = signed_area_2d(UV, F.row(f));
    st.area_2d += a2;
    if (!(a2 > 0.0)) ++st.flipped_triangles;
    str[i] = S(f, 0) - 1.0;
    com[i] = 1.0 - S(f, 1);
    err[i] = std::max(std::abs(S(f, 0) - 1.0), std::abs(S(f, 1) - 1.0));
    st.max_error = std::max(st.max_error, err[i]);
    st.max_stretch = std::max(st.max_stretch, str[i]);
    st.max_compression = std::max(st.max_compression, com[i]);
    weighted += area[i] * err[i];
  }
  if (m == 0) return DistortionStats{};
  st.mean_error = st.area_3d > 0.0 ? weighted / st.area_3d : 0.0;
  auto percentile = [&](const std::vector<double>& value) {
    std::vector<int> order(static_cast<size_t>(m));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return value[static_cast<size_t>(a)] < value[static_cast<size_t>(b)] ||
             (value[static_cast<size_t>(a)] == value[static_cast<size_t>(b)] && a < b);
    });
    double acc = 0.0;
    for (int f : order) {
      acc += area[static_cast<size_t>(f)];
      if (acc >= 0.95 * st.area_3d) return value[static_cast<size_t>(f)];
    }
    return value[static_cast<size_t>(order.back())];
  };
  st.p95_error = percentile(err);
  st.p95_stretch = percentile(str);
  st.p95_compression = percentile(com);
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

FlattenResult flatten_piece(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            const FlattenOptions& options, const Eigen::VectorXi* material_ids) {
  const int n = static_cast<int>(V.rows());
  const auto loops = boundary_loops(F);
  if (loops.size() != 1 || euler_characteristic(F) != 1)
    throw GeometryError("a piece to flatten must be a disk (one boundary loop, Euler characteristic 1); it has " +
                        std::to_string(loops.size()) + " boundary loops and Euler characteristic " +
                        std::to_string(euler_characteristic(F)));
  if (!V.allFinite()) throw GeometryError("the piece has non-finite vertex coordinates");
  const std::vector<int>& loop = loops.front();
  const std::vector<LocalTriangle> T = local_triangles(V, F);

  FlattenResult result;
  Eigen::MatrixXd UV_lscm;
  bool lscm_solved = false;
  try {
    UV_lscm = lscm(V, F, T, loop);
    double total = 0.0;
    for (int f = 0; f < F.rows(); ++f) total += signed_area_2d(UV_lscm, F.row(f));
    if (total < 0.0) UV_lscm.col(0) *= -1.0;
    lscm_solved = UV_lscm.allFinite();
  } catch (const NumericalError&) {
    lscm_solved = false;
  }

  // Boundary edges (i -> j, 3D length l, weight w): the term
  // w |u_i - u_j - l d|^2 with d the current unit direction of the flat edge
  // joins ARAP's local step (d) and global step (a constant matrix), like the
  // edge springs of a local/global solver (Liu et al. 2008; Bouaziz et al.
  // 2014, projective dynamics).
  struct BoundaryEdge {
    int i, j;
    double length, weight;
  };
  std::vector<BoundaryEdge> edges;
  if (options.boundary_weight > 0.0) {
    const Eigen::MatrixXi TT = triangle_adjacency(F);
    for (int f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (TT(f, k) < 0 && !T[static_cast<size_t>(f)].degenerate) {
          const int i = F(f, k), j = F(f, (k + 1) % 3);
          const double l = (V.row(i) - V.row(j)).norm();
          if (l > 0.0) edges.push_back({i, j, l, options.boundary_weight * T[static_cast<size_t>(f)].area / (l * l)});
        }
  }
  // ARAP: one pinned vertex removes the translation; L is factorized once.
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
  const int pin = loop.front();
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
  CholmodSolver solver{kFlattenSolver};
  if (m > 0) {
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(trip.begin(), trip.end());
    solver.compute(A);
  }

  auto energy_and_rhs = [&](const Eigen::MatrixXd& UV, Eigen::MatrixXd* rhs) {
    double energy = 0.0;
    if (rhs) rhs->setZero(n, 2);
    for (int f = 0; f < F.rows(); ++f) {
      const LocalTriangle& t = T[static_cast<size_t>(f)];
      if (t.degenerate) continue;
      const Eigen::Matrix2d J = jacobian(t, UV, F.row(f));
      const Eigen::Matrix2d R = closest_rotation(J);
      energy += t.area * (J - R).squaredNorm();
      if (rhs) {
        const Eigen::Matrix<double, 3, 2> b = t.area * t.D.transpose() * R.transpose();
        for (int k = 0; k < 3; ++k) rhs->row(F(f, k)) += b.row(k);
      }
    }
    for (const auto& e : edges) {
      const Eigen::RowVector2d x = UV.row(e.i) - UV.row(e.j);
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

  // Local/global iterations from UV. With `injective`, every global step is
  // shortened to keep all triangles positive (UV must start flip-free) and
  // the iteration only stops on a small decrease after a full step.
  auto arap = [&](Eigen::MatrixXd& UV, bool injective, int& iterations) {
    Eigen::MatrixXd rhs;
    double energy = energy_and_rhs(UV, &rhs);
    Eigen::MatrixXd B(m, 2), X;
    iterations = 0;
    for (int it = 0; it < options.max_iterations && m > 0; ++it) {
      // Global step (Liu et al. 2008, eq. 7) with the rotations of the local step.
      for (int i = 0; i < n; ++i) {
        const int fi = free_index[static_cast<size_t>(i)];
        if (fi >= 0) B.row(fi) = rhs.row(i);
      }
      for (int c = 0; c < L.outerSize(); ++c)
        for (Eigen::SparseMatrix<double>::InnerIterator e(L, c); e; ++e) {
          const int fr = free_index[static_cast<size_t>(e.row())];
          if (fr >= 0 && c == pin) B.row(fr) -= e.value() * UV.row(pin);
        }
      solver.solve(B, X);
      Eigen::MatrixXd target = UV;
      for (int i = 0; i < n; ++i) {
        const int fi = free_index[static_cast<size_t>(i)];
        if (fi >= 0) target.row(i) = X.row(fi);
      }
      const Eigen::MatrixXd dUV = target - UV;
      double step = 1.0;
      if (injective) {
        const double t_root = max_flip_free_step(UV, dUV, F, 1.0 / options.line_search_margin);
        step = std::min(1.0, options.line_search_margin * t_root);
      }
      UV += step * dUV;
      const double next_energy = energy_and_rhs(UV, &rhs);
      iterations = it + 1;
      const double decrease = energy - next_energy;
      energy = next_energy;
      if (energy <= 1e-24 * area_scale) break;
      if (decrease <= options.tolerance * energy && step == 1.0) break;
    }
    return energy;
  };

  // Unconstrained ARAP from LSCM first (fastest to converge); if it leaves
  // flipped triangles, injective ARAP from a flip-free start (LSCM when it has
  // no flips, else Tutte's embedding) guarantees a flip-free result.
  bool done = false;
  if (lscm_solved) {
    result.UV = UV_lscm;
    result.initialization = "lscm";
    result.energy = arap(result.UV, false, result.iterations);
    done = result.UV.allFinite() && (count_flips(result.UV, F) == 0 || !options.injective_fallback);
  }
  if (!done) {
    if (lscm_solved && count_flips(UV_lscm, F) == 0) {
      result.UV = UV_lscm;
      result.initialization = "lscm, injective";
    } else {
      result.UV = tutte(V, F, loop);
      result.initialization = "tutte, injective";
      if (count_flips(result.UV, F) != 0)
        throw NumericalError("Tutte's embedding of the piece has flipped triangles (the piece is not 3-connected)");
    }
    int more = 0;
    result.energy = arap(result.UV, true, more);
    result.iterations += more;
  }
  if (!result.UV.allFinite()) throw NumericalError("the flattening produced non-finite coordinates");
  result.stats = distortion_stats(V, F, result.UV);
  Eigen::MatrixXd P(static_cast<int>(loop.size()), 2);
  for (size_t k = 0; k < loop.size(); ++k) P.row(static_cast<int>(k)) = result.UV.row(loop[k]);
  std::vector<int> at, material;
  if (material_ids)
    for (int v : loop) material.push_back((*material_ids)[v]);
  result.boundary_overlaps = polygon_self_intersects(P, &at, material_ids ? &material : nullptr);
  for (int k : at) result.overlap_vertex_ids.push_back(loop[static_cast<size_t>(k)]);
  return result;
}

}  // namespace gp
