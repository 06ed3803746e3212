#include "pattern/dart_placement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "mesh/barycentric.h"
#include "mesh/laplacian.h"
#include "mesh/measures.h"
#include "mesh/point_triangle.h"
#include "mesh/topology.h"
#include "pattern/flatten.h"

namespace gp {
namespace {

// A smooth, compactly supported kernel: (1 - (d/r)^2)^2 for d < r.
double kernel(double d, double r) {
  const double s = d / r;
  return s < 1.0 ? (1.0 - s * s) * (1.0 - s * s) : 0.0;
}

// Angle defect 2 pi - sum of corner angles per vertex (mesh/measures.h), 0 on the boundary.
std::vector<double> inner_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const Eigen::VectorXd all = angle_defects(V, F);
  std::vector<double> defect(all.data(), all.data() + all.size());
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) defect[static_cast<size_t>(v)] = 0.0;
  return defect;
}

// Closest point of segment ab to q.
Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& q) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

double distance_to_outline(const PatternPiece& p, const Eigen::Vector3d& q) {
  double d = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < p.boundary.size(); ++k) {
    const Eigen::Vector3d a = p.V.row(p.boundary[k]), b = p.V.row(p.boundary[(k + 1) % p.boundary.size()]);
    d = std::min(d, (closest_on_segment(a, b, q) - q).norm());
  }
  return d;
}

// The point of the piece closest to x, as a piece-local curve point: a
// vertex or an edge point where it lies on one within `snap` (barycentric),
// else a face point. A point on an edge given as a face point would be
// inserted as a second vertex beside the edge's, leaving triangles of no
// area (a mirror image of a tip lands on a symmetric mesh's edges).
CurvePoint closest_point(const PatternPiece& p, const Eigen::Vector3d& x, Eigen::Vector3d& on, double snap = 1e-6) {
  double best = std::numeric_limits<double>::infinity();
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  for (int f = 0; f < p.F.rows(); ++f) {
    const TriangleClosestPoint q =
        closest_point_on_triangle(x, p.V.row(p.F(f, 0)), p.V.row(p.F(f, 1)), p.V.row(p.F(f, 2)));
    const double d = (q.point - x).squaredNorm();
    if (d < best) {
      best = d;
      face = f;
      bary = q.bary;
      on = q.point;
    }
  }
  if (face < 0) return CurvePoint{};
  int k = 0;
  if (bary.maxCoeff(&k) >= 1.0 - snap) return CurvePoint::at_vertex(p.F(face, k));
  if (bary.minCoeff(&k) <= snap) {
    const int a = p.F(face, (k + 1) % 3), b = p.F(face, (k + 2) % 3);
    const double t = bary[(k + 2) % 3] / (bary[(k + 1) % 3] + bary[(k + 2) % 3]);
    return CurvePoint::on_edge(a, b, t);
  }
  return CurvePoint::in_face(face, bary);
}

// Mode of sum_i w_i kernel(|x - X_i|) by mean shift from x.
Eigen::Vector3d mean_shift(const std::vector<Eigen::Vector3d>& X, const std::vector<double>& w, Eigen::Vector3d x,
                           double r) {
  for (int it = 0; it < 200; ++it) {
    Eigen::Vector3d num = Eigen::Vector3d::Zero();
    double den = 0.0;
    for (size_t i = 0; i < X.size(); ++i) {
      if (w[i] <= 0.0) continue;
      const double k = w[i] * kernel((X[i] - x).norm(), r);
      num += k * X[i];
      den += k;
    }
    if (!(den > 0.0)) break;
    const Eigen::Vector3d next = num / den;
    const double step = (next - x).norm();
    x = next;
    if (step < 1e-10 * r) break;
  }
  return x;
}

// Log conformal factor u of the flattening keeping the boundary's length:
// L u = -K inside, u = 0 on the boundary (cotan Laplacian L).
std::vector<double> log_conformal_factor(const PatternPiece& p, const std::vector<double>& K) {
  const int n = static_cast<int>(p.V.rows());
  std::vector<char> boundary(static_cast<size_t>(n), 0);
  for (int v : p.boundary) boundary[static_cast<size_t>(v)] = 1;
  std::vector<int> index(static_cast<size_t>(n), -1);
  int m = 0;
  for (int v = 0; v < n; ++v)
    if (!boundary[static_cast<size_t>(v)]) index[static_cast<size_t>(v)] = m++;
  std::vector<double> u(static_cast<size_t>(n), 0.0);
  if (m == 0) return u;
  const Eigen::SparseMatrix<double> L = cotan_laplacian(p.V, p.F);
  std::vector<Eigen::Triplet<double>> trip;
  for (int c = 0; c < L.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it) {
      const int i = index[static_cast<size_t>(it.row())], j = index[static_cast<size_t>(c)];
      if (i >= 0 && j >= 0) trip.emplace_back(i, j, it.value());
    }
  Eigen::SparseMatrix<double> A(m, m);
  A.setFromTriplets(trip.begin(), trip.end());
  Eigen::VectorXd b(m);
  for (int v = 0; v < n; ++v)
    if (index[static_cast<size_t>(v)] >= 0) b[index[static_cast<size_t>(v)]] = -K[static_cast<size_t>(v)];
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) return u;
  const Eigen::VectorXd x = solver.solve(b);
  for (int v = 0; v < n; ++v)
    if (index[static_cast<size_t>(v)] >= 0) u[static_cast<size_t>(v)] = x[index[static_cast<size_t>(v)]];
  return u;
}

Eigen::Vector2d chart_position(const PatternPiece& p, const Eigen::MatrixXd& chart, const CurvePoint& q) {
  return curve_point_position(chart, p.F, q);
}

// Area of the polygon loop[i0..i1] (cyclic, inclusive) in the chart.
double sub_polygon_area(const Eigen::MatrixXd& UV, const std::vector<int>& loop, size_t i0, size_t i1) {
  const size_t n = loop.size();
  std::vector<int> ids;
  for (size_t i = i0;; i = (i + 1) % n) {
    ids.push_back(loop[i]);
    if (i == i1) break;
  }
  double a = 0.0;
  for (size_t k = 0; k < ids.size(); ++k) {
    const Eigen::Vector2d p = UV.row(ids[k]), q = UV.row(ids[(k + 1) % ids.size()]);
    a += 0.5 * (p.x() * q.y() - p.y() * q.x());
  }
  return std::abs(a);
}

// The point at t along outline edge k (boundary[k] -> boundary[k+1]) of the
// piece, kept min_edge_fraction away from its ends (or snapped to an end
// within snap_fraction), as a curve point.
CurvePoint outline_point(const PatternPiece& p, size_t k, double t, const PatternOptions& options) {
  const int a = p.boundary[k], b = p.boundary[(k + 1) % p.boundary.size()];
  const double f = options.seams.smoothing.trace.min_edge_fraction;
  return snap_to_vertices({CurvePoint::on_edge(a, b, std::clamp(t, f, 1.0 - f))}, options.seams.smoothing.trace.snap_fraction)
      .front();
}

// The samples whose kernel density places dart tips in piece c: inner
// vertices with their angle defects (or, conformal placement, their
// compression -u per unit of a mean kernel's area).
void curvature_samples(const Pattern& pattern, size_t c, const PatternOptions& options,
                       std::vector<Eigen::Vector3d>& X, std::vector<double>& value) {
  const PatternPiece& p = pattern.pieces[c];
  const int n = static_cast<int>(p.V.rows());
  const double r = options.darts.kernel_radius;
  std::vector<char> boundary(static_cast<size_t>(n), 0);
  for (int v : p.boundary) boundary[static_cast<size_t>(v)] = 1;
  // The piece's angle defects: the rest shape's at its own vertices, zero at
  // points a cut added on an edge or in a face (their angles sum to 2 pi).
  const std::vector<double> K = inner_defects(p.V, p.F);
  if (options.darts.dart_placement == PatternOptions::DartPlacement::conformal) {
    const std::vector<double> u = log_conformal_factor(p, K);
    const Eigen::VectorXd mass = lumped_mass(p.V, p.F);
    for (int v = 0; v < n; ++v)
      if (!boundary[static_cast<size_t>(v)]) {
        X.push_back(p.V.row(v).transpose());
        // -u (compression of the conformal flattening) integrated over the
        // vertex's area, per unit of a mean kernel's area: radians-like.
        value.push_back(-u[static_cast<size_t>(v)] * mass[v] / (M_PI * r * r / 3.0));
      }
  } else {
    for (int v = 0; v < n; ++v)
      if (!boundary[static_cast<size_t>(v)] && p.mesh_vertex_ids[v] < pattern.mesh.rest_vertex_count) {
        X.push_back(p.V.row(v).transpose());
        value.push_back(K[static_cast<size_t>(v)]);
      }
  }
}

}  // namespace

Eigen::MatrixXd conformal_chart(const PatternPiece& piece) {
  return lscm_flatten(piece.V, piece.F, piece.boundary, FlattenOptions{}.min_weight_fraction);
}

std::vector<DartTip> dart_tips(const Pattern& pattern, size_t c, const PatternOptions& options, int count) {
  const PatternPiece& p = pattern.pieces[c];
  const double r = options.darts.kernel_radius;
  std::vector<Eigen::Vector3d> X;
  std::vector<double> value;
  curvature_samples(pattern, c, options, X, value);
  const size_t m = X.size();
  // Kernel density of the signed values at every sample, and its positive
  // part as the weights of the mean shift.
  std::vector<double> density(m, 0.0);
  for (size_t i = 0; i < m; ++i)
    for (size_t j = 0; j < m; ++j) density[i] += value[j] * kernel((X[j] - X[i]).norm(), r);
  std::vector<double> weight(m);
  for (size_t i = 0; i < m; ++i) weight[i] = std::max(0.0, density[i]);
  std::vector<DartTip> tips;
  std::vector<Eigen::Vector3d> taken;
  for (const int d : p.dart_seams) {
    const auto& ids = pattern.seams[static_cast<size_t>(d)].vertex_ids;
    if (!ids.empty()) taken.push_back(pattern.mesh.V.row(ids.back()).transpose());
  }
  for (int attempt = 0; attempt < 4 && static_cast<int>(tips.size()) < count; ++attempt) {
    size_t best = m;
    for (size_t i = 0; i < m; ++i) {
      bool near = false;
      for (const auto& t : taken) near = near || (X[i] - t).norm() < 2.0 * r;
      if (near) continue;
      if (best == m || density[i] > density[best]) best = i;
    }
    if (best == m || !(density[best] > 0.0)) break;
    const Eigen::Vector3d mode = mean_shift(X, weight, X[best], r);
    // A start two radii from every taken mode can still climb back to one of
    // them (a broad hill of curvature): that mode is taken, and a second
    // dart to it would coincide with the first, leaving a slit of zero area
    // between them. Its start is kept out of the next attempts instead.
    bool repeated = false;
    for (const auto& t : taken) repeated = repeated || (mode - t).norm() < 2.0 * r;
    if (repeated) {
      taken.push_back(X[best]);
      continue;
    }
    taken.push_back(mode);
    DartTip tip;
    tip.at = closest_point(p, mode, tip.point);
    for (size_t i = 0; i < m; ++i)
      tip.curvature += value[i] * kernel((X[i] - tip.point).norm(), r);
    if (tip.curvature < options.darts.min_dart_angle) break;  // weaker modes follow
    if (distance_to_outline(p, tip.point) < options.darts.tip_margin) {
      // A cone at the outline (a shoulder point, where the shoulder seam
      // meets the armhole) has no room for a tip; a tailor points the dart
      // at it from as near as a tip fits: the inner vertex tip_margin inside
      // nearest to the mode, if the curvature around it still calls for a
      // dart.
      if (!options.darts.tip_inward) continue;
      int inner = -1;
      double nearest = std::numeric_limits<double>::infinity();
      for (int v = 0; v < p.V.rows(); ++v) {
        const Eigen::Vector3d x = p.V.row(v).transpose();
        const double d = (x - mode).norm();
        if (d < nearest && distance_to_outline(p, x) >= options.darts.tip_margin) nearest = d, inner = v;
      }
      if (inner < 0 || nearest > 2.0 * r) continue;
      DartTip moved;
      moved.point = p.V.row(inner).transpose();
      moved.at = CurvePoint::at_vertex(inner);
      for (size_t i = 0; i < m; ++i) moved.curvature += value[i] * kernel((X[i] - moved.point).norm(), r);
      if (moved.curvature < options.darts.min_dart_angle) continue;
      tip = moved;
    }
    tips.push_back(tip);
  }
  // Named in a fixed order (left to right, then top down) rather than by
  // strength, which may swap between two about equal tips.
  std::sort(tips.begin(), tips.end(), [](const DartTip& a, const DartTip& b) {
    return a.point.x() > b.point.x() || (a.point.x() == b.point.x() && a.point.y() > b.point.y());
  });
  return tips;
}

bool polylines_cross(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  for (int i = 0; i + 1 < A.rows(); ++i)
    for (int j = 0; j + 1 < B.rows(); ++j) {
      const Eigen::Vector2d a0 = A.row(i), a1 = A.row(i + 1), b0 = B.row(j), b1 = B.row(j + 1);
      if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) continue;
      if (std::max(a0.x(), a1.x()) < std::min(b0.x(), b1.x()) || std::max(b0.x(), b1.x()) < std::min(a0.x(), a1.x()) ||
          std::max(a0.y(), a1.y()) < std::min(b0.y(), b1.y()) || std::max(b0.y(), b1.y()) < std::min(a0.y(), a1.y()))
        continue;
      const double d0 = orient_2d(a0, a1, b0), d1 = orient_2d(a0, a1, b1);
      const double d2 = orient_2d(b0, b1, a0), d3 = orient_2d(b0, b1, a1);
      if (((d0 <= 0.0 && d1 >= 0.0) || (d0 >= 0.0 && d1 <= 0.0)) &&
          ((d2 <= 0.0 && d3 >= 0.0) || (d2 >= 0.0 && d3 <= 0.0)))
        return true;
    }
  return false;
}

std::optional<SurfaceCurve> dart_curve(const PatternPiece& p, const Eigen::MatrixXd& chart, const DartTip& tip,
                                       const PatternOptions& options, const std::vector<Eigen::MatrixXd>& avoid) {
  // The mouth: the outline's point nearest to the tip (continuous in the
  // shape, unlike the nearest outline vertex); the next nearest outline
  // segment's where the straight wedge would cross a line to avoid.
  const size_t nb = p.boundary.size();
  std::vector<std::tuple<double, size_t, double>> candidates;  // (distance, segment, t)
  for (size_t k = 0; k < nb; ++k) {
    const Eigen::Vector3d a = p.V.row(p.boundary[k]), b = p.V.row(p.boundary[(k + 1) % nb]);
    const Eigen::Vector3d q = closest_on_segment(a, b, tip.point);
    const double t = (b - a).squaredNorm() > 0.0 ? (q - a).dot(b - a) / (b - a).squaredNorm() : 0.0;
    candidates.emplace_back((q - tip.point).norm(), k, t);
  }
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [d, k, t] : candidates) {
    if (d < options.darts.min_dart_length) return std::nullopt;
    const CurvePoint mouth = outline_point(p, k, t, options);
    Eigen::MatrixXd P(2, 2);
    P.row(0) = curve_point_position(chart, p.F, mouth).transpose();
    P.row(1) = chart_position(p, chart, tip.at).transpose();
    if (std::any_of(avoid.begin(), avoid.end(), [&](const Eigen::MatrixXd& line) { return polylines_cross(P, line); }))
      continue;
    const SurfaceCurve c = trace_polyline(chart, p.F, mouth, tip.at, P, {}, options.seams.smoothing.trace);
    if (c.size() < 2) return std::nullopt;
    return c;
  }
  return std::nullopt;
}

std::optional<Eigen::Vector3d> panel_centre(const PatternPiece& p, const PatternOptions& options) {
  // The centroid of the one-sided energy of the piece's conformal
  // flattening that keeps its boundary's length (log conformal factor u:
  // L u = -K, u = 0 on the boundary; energy u^2 where u < 0, ease_weight u^2
  // where u > 0, per unit area). A linear solve, so that the seam moves
  // continuously with the shape; and a centroid, not the highest mode, which
  // would jump between two about equal blobs (a left and a right one).
  const std::vector<double> K = inner_defects(p.V, p.F);
  const std::vector<double> u = log_conformal_factor(p, K);
  const Eigen::VectorXd mass = lumped_mass(p.V, p.F);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (int v = 0; v < static_cast<int>(p.V.rows()); ++v) {
    const double x = u[static_cast<size_t>(v)];
    const double e = mass[v] * (x < 0.0 || options.limit.symmetric ? x * x : options.flatten.ease_weight * x * x);
    centroid += e * p.V.row(v).transpose();
    total += e;
  }
  if (!(total > 0.0)) return std::nullopt;
  return Eigen::Vector3d(centroid / total);
}

std::optional<DartTip> dart_tip_near(const Pattern& pattern, size_t c, const Eigen::Vector3d& x,
                                     double min_curvature, const PatternOptions& options) {
  const PatternPiece& p = pattern.pieces[c];
  DartTip tip;
  tip.at = closest_point(p, x, tip.point);
  if (distance_to_outline(p, tip.point) < options.darts.tip_margin) return std::nullopt;
  std::vector<Eigen::Vector3d> X;
  std::vector<double> value;
  curvature_samples(pattern, c, options, X, value);
  for (size_t i = 0; i < X.size(); ++i) tip.curvature += value[i] * kernel((X[i] - tip.point).norm(), options.darts.kernel_radius);
  if (!(tip.curvature >= min_curvature)) return std::nullopt;
  return tip;
}

Eigen::Vector3d centre_seam_point(const PatternPiece& p, double plane_x, const Eigen::Vector3d& from) {
  // From the piece's point nearest to `from`: the centroid of a back lies
  // inside the body, and the plane point nearest to it could be on either side.
  Eigen::Vector3d near;
  closest_point(p, from, near);
  Eigen::Vector3d on = from;
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < p.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = p.V.row(p.F(f, k)), b = p.V.row(p.F(f, (k + 1) % 3));
      const double da = a.x() - plane_x, db = b.x() - plane_x;
      if ((da < 0.0) == (db < 0.0) || da == db) continue;
      const Eigen::Vector3d x = a + (da / (da - db)) * (b - a);
      if ((x - near).squaredNorm() < best) best = (x - near).squaredNorm(), on = x;
    }
  return on;
}

namespace {

// The areas of the parts that a chain of faces leaves of piece p: faces joined across edges, not
// through the chain's faces (each of which the seam splits between the two parts).
std::vector<double> part_areas_apart_from(const PatternPiece& p, const std::vector<int>& chain_faces) {
  std::vector<char> blocked(static_cast<size_t>(p.F.rows()), 0);
  for (int f : chain_faces) blocked[static_cast<size_t>(f)] = 1;
  std::map<std::pair<int, int>, std::vector<int>> faces_of_edge;
  for (int f = 0; f < p.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = p.F(f, k), b = p.F(f, (k + 1) % 3);
      faces_of_edge[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  auto face_area = [&](int f) {
    const Eigen::Vector3d q0 = p.V.row(p.F(f, 0)), q1 = p.V.row(p.F(f, 1)), q2 = p.V.row(p.F(f, 2));
    return 0.5 * (q1 - q0).cross(q2 - q0).norm();
  };
  std::vector<int> component(static_cast<size_t>(p.F.rows()), -1);
  std::vector<double> part;
  for (int f0 = 0; f0 < p.F.rows(); ++f0) {
    if (blocked[static_cast<size_t>(f0)] || component[static_cast<size_t>(f0)] >= 0) continue;
    const int id = static_cast<int>(part.size());
    part.push_back(0.0);
    std::vector<int> stack{f0};
    component[static_cast<size_t>(f0)] = id;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      part.back() += face_area(f);
      for (int k = 0; k < 3; ++k) {
        const int a = p.F(f, k), b = p.F(f, (k + 1) % 3);
        for (int g : faces_of_edge[{std::min(a, b), std::max(a, b)}])
          if (!blocked[static_cast<size_t>(g)] && component[static_cast<size_t>(g)] < 0) {
            component[static_cast<size_t>(g)] = id;
            stack.push_back(g);
          }
      }
    }
  }
  return part;
}

// A snapped chain can come back to a vertex it passed (around a vertex on the plane) or touch the
// outline at a vertex between its ends (a symmetric mesh has vertices on the plane): a cut that
// touches itself or the outline is no seam. Loops are erased, and of the parts between outline
// vertices the longest is returned (fewer than two points: none).
SurfaceCurve simple_cut(const PatternPiece& p, const SurfaceCurve& cut) {
  const int n = static_cast<int>(p.V.rows());
  SurfaceCurve simple;
  for (const CurvePoint& q : cut) {
    if (q.is_vertex()) {
      const auto seen = std::find_if(simple.begin(), simple.end(), [&](const CurvePoint& r) {
        return r.is_vertex() && r.vertex == q.vertex;
      });
      if (seen != simple.end()) {
        simple.erase(seen + 1, simple.end());
        continue;
      }
    }
    simple.push_back(q);
  }
  std::vector<char> outline(static_cast<size_t>(n), 0);
  for (int v : p.boundary) outline[static_cast<size_t>(v)] = 1;
  SurfaceCurve longest, run;
  auto close_run = [&]() {
    if (run.size() >= 2 && curve_length(p.V, p.F, run) > curve_length(p.V, p.F, longest)) longest = run;
  };
  for (size_t i = 0; i < simple.size(); ++i) {
    run.push_back(simple[i]);
    if (i > 0 && i + 1 < simple.size() && simple[i].is_vertex() && outline[static_cast<size_t>(simple[i].vertex)]) {
      close_run();
      run = {simple[i]};
    }
  }
  close_run();
  return longest;
}

}  // namespace

std::optional<SurfaceCurve> centre_seam_curve(const Pattern& pattern, size_t c, double plane_x,
                                              const Eigen::Vector3d& near, const PatternOptions& options) {
  const PatternPiece& p = pattern.pieces[c];
  const int n = static_cast<int>(p.V.rows());
  // A symmetric mesh has vertices and whole edges on the plane: the section
  // would run along edges and zigzag through vertices, and touch itself once
  // snapped. The plane is moved off every vertex by at least a twentieth of
  // the mean edge length (by the least of 0, +-0.1, +-0.2, ... edge lengths
  // that does it; a few millimetres, nothing a tailor sees).
  double h = 0.0;
  for (int f = 0; f < p.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) h += (p.V.row(p.F(f, k)) - p.V.row(p.F(f, (k + 1) % 3))).norm();
  h /= std::max<Eigen::Index>(1, 3 * p.F.rows());
  double x0 = plane_x;
  for (int i = 0; i <= 20; ++i) {
    const double shift = (i % 2 ? 1.0 : -1.0) * 0.1 * h * ((i + 1) / 2);
    double nearest = std::numeric_limits<double>::infinity();
    for (int v = 0; v < n; ++v) nearest = std::min(nearest, std::abs(p.V(v, 0) - (plane_x + shift)));
    if (nearest >= 0.05 * h) {
      x0 = plane_x + shift;
      break;
    }
  }
  plane_x = x0;
  // The level set {x = plane_x} of the piecewise-linear x: a vertex on the
  // plane counts as beyond it, so every face has none or two crossed edges.
  auto above = [&](int v) { return p.V(v, 0) >= plane_x; };
  std::map<std::pair<int, int>, std::vector<int>> faces_of;  // crossed edge -> its faces
  for (int f = 0; f < p.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = p.F(f, k), b = p.F(f, (k + 1) % 3);
      if (above(a) != above(b)) faces_of[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  std::map<int, std::vector<std::pair<int, int>>> edges_of;  // face -> its crossed edges
  for (const auto& [e, fs] : faces_of)
    for (int f : fs) edges_of[f].push_back(e);
  std::vector<char> on_dart(static_cast<size_t>(n), 0);
  {
    std::vector<char> dart_vertex(static_cast<size_t>(pattern.mesh.V.rows()), 0);
    for (int d : p.dart_seams)
      for (int v : pattern.seams[static_cast<size_t>(d)].vertex_ids) dart_vertex[static_cast<size_t>(v)] = 1;
    for (int v = 0; v < n; ++v) on_dart[static_cast<size_t>(v)] = dart_vertex[static_cast<size_t>(p.mesh_vertex_ids[v])];
  }
  // Crossings near an edge's end are that vertex (snap_to_vertices below):
  // where the plane runs through a vertex, the chain fans around it through
  // edges crossed next to it, and points kept a fraction off the vertex
  // would leave slivers there.
  auto point_on = [&](const std::pair<int, int>& e) {
    const double da = p.V(e.first, 0) - plane_x, db = p.V(e.second, 0) - plane_x;
    return CurvePoint::on_edge(e.first, e.second, std::clamp(da / (da - db), 0.0, 1.0));
  };
  // Open chains, each walked from a crossed outline edge to another.
  std::set<std::pair<int, int>> used;
  struct Chain {
    std::vector<std::pair<int, int>> edges;
    std::vector<int> faces;
    double distance = std::numeric_limits<double>::infinity();  // to `near`
  };
  std::optional<Chain> best;
  for (const auto& [start, fs] : faces_of) {
    if (fs.size() != 1 || used.count(start)) continue;
    Chain chain;
    std::pair<int, int> e = start;
    int face = fs[0];
    bool open = false;
    for (int guard = 0; guard <= p.F.rows(); ++guard) {
      used.insert(e);
      chain.edges.push_back(e);
      chain.faces.push_back(face);
      const auto& es = edges_of[face];
      if (es.size() != 2) break;
      const std::pair<int, int> next = es[0] == e ? es[1] : es[0];
      if (used.count(next)) break;
      const auto& nf = faces_of[next];
      if (nf.size() == 1) {
        used.insert(next);
        chain.edges.push_back(next);
        open = true;
        break;
      }
      face = nf[0] == face ? nf[1] : nf[0];
      e = next;
    }
    if (!open) continue;
    // A seam ending on a dart's leg would part the dart's sides.
    const auto& e0 = chain.edges.front();
    const auto& e1 = chain.edges.back();
    if ((on_dart[static_cast<size_t>(e0.first)] && on_dart[static_cast<size_t>(e0.second)]) ||
        (on_dart[static_cast<size_t>(e1.first)] && on_dart[static_cast<size_t>(e1.second)]))
      continue;
    for (const auto& ce : chain.edges)
      chain.distance = std::min(chain.distance, (curve_point_position(p.V, p.F, point_on(ce)) - near).norm());
    if (!best || chain.distance < best->distance) best = chain;
  }
  if (!best) return std::nullopt;
  const std::vector<double> part = part_areas_apart_from(p, best->faces);
  if (part.size() < 2 || *std::min_element(part.begin(), part.end()) < options.panels.min_piece_area) return std::nullopt;
  SurfaceCurve cut;
  for (const auto& ce : best->edges) cut.push_back(point_on(ce));
  cut = snap_to_vertices(cut, std::max(options.seams.smoothing.trace.min_edge_fraction, options.seams.smoothing.trace.snap_fraction));
  const SurfaceCurve longest = simple_cut(p, cut);
  if (longest.size() < 2) return std::nullopt;
  return longest;
}

std::optional<SurfaceCurve> panel_curve(const Pattern& pattern, size_t c, const Eigen::MatrixXd& chart,
                                        const Eigen::Vector3d& centre, const PatternOptions& options,
                                        std::string* where) {
  const PatternPiece& p = pattern.pieces[c];
  Eigen::Vector3d on;
  const CurvePoint mode = closest_point(p, centre, on);
  const Eigen::Vector2d x = chart_position(p, chart, mode);
  // The grain in the chart: the area-weighted gradient of the rest height.
  Eigen::Vector2d up = Eigen::Vector2d::Zero();
  for (int f = 0; f < p.F.rows(); ++f) {
    Eigen::Matrix2d E;
    E.col(0) = (chart.row(p.F(f, 1)) - chart.row(p.F(f, 0))).transpose();
    E.col(1) = (chart.row(p.F(f, 2)) - chart.row(p.F(f, 0))).transpose();
    const double det = E.determinant();
    if (!(det > 0.0)) continue;
    const Eigen::Vector2d dh(p.V(p.F(f, 1), 1) - p.V(p.F(f, 0), 1), p.V(p.F(f, 2), 1) - p.V(p.F(f, 0), 1));
    up += 0.5 * det * E.transpose().inverse() * dh;
  }
  if (!(up.norm() > 0.0)) up = Eigen::Vector2d(0.0, 1.0);
  up.normalize();
  // Along the grain: the princess line of a tailor's fitted panels. (Cuts
  // across the grain were tried: chosen by the principal axis of the energy's
  // spread, they sliced garments whose sleeves stayed on into horizontal strips.)
  const Eigen::Vector2d dir = up;
  const size_t nb = p.boundary.size();
  std::vector<char> on_dart(static_cast<size_t>(p.V.rows()), 0);
  {
    std::vector<char> dart_vertex(static_cast<size_t>(pattern.mesh.V.rows()), 0);
    for (int d : p.dart_seams)
      for (int v : pattern.seams[static_cast<size_t>(d)].vertex_ids) dart_vertex[static_cast<size_t>(v)] = 1;
    for (int v = 0; v < p.V.rows(); ++v) on_dart[static_cast<size_t>(v)] = dart_vertex[static_cast<size_t>(p.mesh_vertex_ids[v])];
  }
  // Nearest outline crossings of the line x + s dir on either side.
  // The chord ends where it meets the outline, not at the nearest outline
  // vertex (which would jump from one vertex to the next).
  double s_plus = std::numeric_limits<double>::infinity(), s_minus = -s_plus;
  size_t k_plus = 0, k_minus = 0;
  double t_plus = 0.0, t_minus = 0.0;
  for (size_t k = 0; k < nb; ++k) {
    // A dart's legs are outline too, but a seam ending on one would part
    // the dart's sides.
    if (on_dart[static_cast<size_t>(p.boundary[k])] && on_dart[static_cast<size_t>(p.boundary[(k + 1) % nb])]) continue;
    const Eigen::Vector2d q0 = chart.row(p.boundary[k]), q1 = chart.row(p.boundary[(k + 1) % nb]);
    const Eigen::Vector2d e = q1 - q0;
    const double det = -dir.x() * e.y() + dir.y() * e.x();
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector2d rhs = q0 - x;
    const double s = (-rhs.x() * e.y() + rhs.y() * e.x()) / det;
    const double t = (dir.x() * rhs.y() - dir.y() * rhs.x()) / det;
    if (t < 0.0 || t > 1.0) continue;
    if (s > 0.0 && s < s_plus) s_plus = s, k_plus = k, t_plus = t;
    if (s < 0.0 && s > s_minus) s_minus = s, k_minus = k, t_minus = t;
  }
  if (!std::isfinite(s_plus) || !std::isfinite(s_minus) || k_plus == k_minus) return std::nullopt;
  // Chart areas are conformal, not true: the parts are compared with the
  // piece's own chart area scaled to its 3D area.
  double chart_area = 0.0, area = 0.0;
  for (int f = 0; f < p.F.rows(); ++f) {
    const Eigen::Vector3d q0 = p.V.row(p.F(f, 0)), q1 = p.V.row(p.F(f, 1)), q2 = p.V.row(p.F(f, 2));
    area += 0.5 * (q1 - q0).cross(q2 - q0).norm();
    chart_area += 0.5 * orient_2d(chart.row(p.F(f, 0)).transpose(), chart.row(p.F(f, 1)).transpose(),
                               chart.row(p.F(f, 2)).transpose());
  }
  const double scale = chart_area > 0.0 ? area / chart_area : 1.0;
  const double part = scale * std::min(sub_polygon_area(chart, p.boundary, (k_minus + 1) % nb, k_plus),
                                       sub_polygon_area(chart, p.boundary, (k_plus + 1) % nb, k_minus));
  if (part < options.panels.min_piece_area) return std::nullopt;
  const CurvePoint from = outline_point(p, k_minus, t_minus, options), to = outline_point(p, k_plus, t_plus, options);
  Eigen::MatrixXd P(2, 2);
  P.row(0) = curve_point_position(chart, p.F, from).transpose();
  P.row(1) = curve_point_position(chart, p.F, to).transpose();
  const SurfaceCurve cut = trace_polyline(chart, p.F, from, to, P, {}, options.seams.smoothing.trace);
  if (cut.size() < 2) return std::nullopt;
  if (where) *where = "panel seam along the grain through the centroid of its conformal distortion energy";
  return cut;
}

}  // namespace gp
