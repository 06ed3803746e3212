#include "pattern/surface_curve.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "mesh/barycentric.h"
#include "mesh/topology.h"
#include "pattern/flatten.h"

namespace gp {

CurvePoint CurvePoint::at_vertex(int v) {
  CurvePoint p;
  p.vertex = v;
  return p;
}

CurvePoint CurvePoint::on_edge(int a, int b, double t) {
  CurvePoint p;
  if (a > b) {
    std::swap(a, b);
    t = 1.0 - t;
  }
  p.a = a;
  p.b = b;
  p.t = t;
  return p;
}

CurvePoint CurvePoint::in_face(int face, const Eigen::Vector3d& bary) {
  CurvePoint p;
  p.face = face;
  p.bary = bary;
  return p;
}

Eigen::VectorXd curve_point_position(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const CurvePoint& p) {
  if (p.is_vertex()) return V.row(p.vertex).transpose();
  if (p.is_edge()) return ((1.0 - p.t) * V.row(p.a) + p.t * V.row(p.b)).transpose();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(V.cols());
  for (int k = 0; k < 3; ++k) x += p.bary[k] * V.row(F(p.face, k)).transpose();
  return x;
}

Eigen::MatrixXd curve_positions(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const SurfaceCurve& curve) {
  Eigen::MatrixXd P(static_cast<int>(curve.size()), V.cols());
  for (size_t i = 0; i < curve.size(); ++i) P.row(static_cast<int>(i)) = curve_point_position(V, F, curve[i]).transpose();
  return P;
}

double curve_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const SurfaceCurve& curve) {
  const Eigen::MatrixXd P = curve_positions(V, F, curve);
  double s = 0.0;
  for (int i = 0; i + 1 < P.rows(); ++i) s += (P.row(i + 1) - P.row(i)).norm();
  return s;
}

namespace {

// Distance from q to the 2D polyline P (#P by 2).
double distance_to_polyline(const Eigen::MatrixXd& P, const Eigen::Vector2d& q) {
  double d = std::numeric_limits<double>::infinity();
  for (int i = 0; i + 1 < P.rows(); ++i) {
    const Eigen::Vector2d a = P.row(i), ab = P.row(i + 1) - P.row(i);
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0.0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    d = std::min(d, (a + t * ab - q).norm());
  }
  if (P.rows() == 1) d = (P.row(0).transpose() - q).norm();
  return d;
}

// The face holding a (boundary) edge point q, and the edge's local index in it; -1 when none.
int face_of_edge(const Eigen::MatrixXi& F, const CurvePoint& q, int& local) {
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (std::min(a, b) == q.a && std::max(a, b) == q.b) {
        local = k;
        return f;
      }
    }
  return -1;
}

// The edge (local index) through which the segment pos -> q leaves `face`, not the one it came in
// through (`entry`): q beyond it, and the segment separates its ends; in rounding trouble, the edge
// q lies farthest beyond. -1 when q lies beyond none.
int exit_edge(const Eigen::MatrixXd& UV, const Eigen::MatrixXi& F, int face, int entry, const Eigen::Vector2d& pos,
              const Eigen::Vector2d& q) {
  auto uv = [&](int v) { return Eigen::Vector2d(UV(v, 0), UV(v, 1)); };
  int exit = -1;
  for (int k = 0; k < 3 && exit < 0; ++k) {
    if (k == entry) continue;
    const Eigen::Vector2d u = uv(F(face, k)), w = uv(F(face, (k + 1) % 3));
    const double ou = orient_2d(pos, q, u), ow = orient_2d(pos, q, w);
    if (((ou >= 0.0) != (ow >= 0.0)) && orient_2d(u, w, q) < 0.0) exit = k;
  }
  double best = 0.0;
  for (int k = 0; k < 3 && exit < 0; ++k) {
    if (k == entry) continue;
    const Eigen::Vector2d u = uv(F(face, k)), w = uv(F(face, (k + 1) % 3));
    const double len = (w - u).norm();
    const double depth = len > 0.0 ? -orient_2d(u, w, q) / len : 0.0;
    if (depth > best) best = depth, exit = k;
  }
  return exit;
}

// Two consecutive crossings of one edge (the walk touched an edge and turned back) add nothing:
// both dropped.
SurfaceCurve without_turnbacks(const SurfaceCurve& curve) {
  SurfaceCurve clean;
  for (const CurvePoint& p : curve) {
    if (!clean.empty() && p.is_edge() && clean.back().is_edge() && clean.back().a == p.a && clean.back().b == p.b) {
      clean.pop_back();
      continue;
    }
    clean.push_back(p);
  }
  return clean;
}

}  // namespace

SurfaceCurve trace_polyline(const Eigen::MatrixXd& UV, const Eigen::MatrixXi& F, const CurvePoint& start,
                            const CurvePoint& end, const Eigen::MatrixXd& P, const std::vector<int>& row_vertex,
                            const TraceOptions& options) {
  const int nv = static_cast<int>(UV.rows());
  const Eigen::MatrixXi TT = triangle_adjacency(F);
  const auto vf = vertex_faces(F, nv);
  auto uv = [&](int v) { return Eigen::Vector2d(UV(v, 0), UV(v, 1)); };
  const double lo = options.min_edge_fraction, hi = 1.0 - options.min_edge_fraction;
  SurfaceCurve curve{start};
  if (P.rows() < 2) return {};
  enum class State { vertex, face };
  State state = start.is_vertex() ? State::vertex : State::face;
  int vertex = start.is_vertex() ? start.vertex : -1;
  int face = start.is_face() ? start.face : -1;
  int entry = -1;  // local edge index (k: F(face,k) -> F(face,k+1)) the walk came in through, or -1
  if (start.is_edge()) {
    face = face_of_edge(F, start, entry);
    if (face < 0) return {};
  }
  Eigen::Vector2d pos = P.row(0).transpose();
  int steps = 0;

  for (int row = 1; row < P.rows(); ++row) {
    const Eigen::Vector2d q = P.row(row).transpose();
    const bool last = row + 1 == P.rows();
    const int target_vertex = last ? (end.is_vertex() ? end.vertex : -1)
                                   : (static_cast<size_t>(row) < row_vertex.size() ? row_vertex[static_cast<size_t>(row)] : -1);
    for (;;) {
      if (++steps > options.max_steps) return {};
      if (state == State::vertex) {
        if (target_vertex == vertex) break;  // already there
        // The face of the fan whose corner at `vertex` holds the direction to q.
        const Eigen::Vector2d d = q - pos;
        int next = -1, k0 = -1;
        for (int f : vf[static_cast<size_t>(vertex)]) {
          int k = 0;
          while (F(f, k) != vertex) ++k;
          const Eigen::Vector2d a = uv(F(f, (k + 1) % 3)) - pos, b = uv(F(f, (k + 2) % 3)) - pos;
          const double ca = a.x() * d.y() - a.y() * d.x();  // cross(a, d)
          const double cb = d.x() * b.y() - d.y() * b.x();  // cross(d, b)
          if (ca >= 0.0 && cb > 0.0) {
            next = f;
            k0 = k;
            break;
          }
        }
        if (next < 0) return {};
        face = next;
        const int a = F(face, (k0 + 1) % 3), b = F(face, (k0 + 2) % 3);
        if (target_vertex == a || target_vertex == b) {
          // Straight along the face to a corner: the chord runs inside the face.
          curve.push_back(CurvePoint::at_vertex(target_vertex));
          vertex = target_vertex;
          pos = uv(vertex);
          break;
        }
        if (orient_2d(uv(a), uv(b), q) >= 0.0) {
          // q inside this face.
          state = State::face;
          entry = -1;
          pos = q;
          break;
        }
        const double oa = orient_2d(pos, q, uv(a)), ob = orient_2d(pos, q, uv(b));
        double t = (oa - ob) != 0.0 ? oa / (oa - ob) : 0.5;
        t = std::clamp(t, lo, hi);
        curve.push_back(CurvePoint::on_edge(a, b, t));
        const int g = TT(face, (k0 + 1) % 3);
        if (g < 0) return {};
        pos = (1.0 - t) * uv(a) + t * uv(b);
        int e = 0;
        while (!(F(g, e) == b && F(g, (e + 1) % 3) == a)) ++e;
        face = g;
        entry = e;
        state = State::face;
        vertex = -1;
        continue;
      }
      // In `face`, at pos.
      if (last && end.is_edge()) {
        bool has = false;
        for (int k = 0; k < 3; ++k) {
          const int a = F(face, k), b = F(face, (k + 1) % 3);
          has = has || (std::min(a, b) == end.a && std::max(a, b) == end.b);
        }
        if (has) {
          curve.push_back(end);
          state = State::face;
          break;
        }
      }
      if (target_vertex >= 0 && (F(face, 0) == target_vertex || F(face, 1) == target_vertex || F(face, 2) == target_vertex)) {
        curve.push_back(CurvePoint::at_vertex(target_vertex));
        state = State::vertex;
        vertex = target_vertex;
        pos = uv(vertex);
        break;
      }
      bool inside = true;
      for (int k = 0; k < 3; ++k)
        if (orient_2d(uv(F(face, k)), uv(F(face, (k + 1) % 3)), q) < 0.0) inside = false;
      if (inside && target_vertex < 0) {
        pos = q;
        entry = -1;
        break;
      }
      const int exit = exit_edge(UV, F, face, entry, pos, q);
      if (exit < 0) {
        if (target_vertex >= 0) return {};  // the vertex target is not ahead: give up
        pos = q;
        entry = -1;
        break;
      }
      const int a = F(face, exit), b = F(face, (exit + 1) % 3);
      const double oa = orient_2d(pos, q, uv(a)), ob = orient_2d(pos, q, uv(b));
      double t = (oa - ob) != 0.0 ? oa / (oa - ob) : 0.5;
      t = std::clamp(t, lo, hi);
      curve.push_back(CurvePoint::on_edge(a, b, t));
      const int g = TT(face, exit);
      if (g < 0) return {};  // the polyline leaves the chart
      pos = (1.0 - t) * uv(a) + t * uv(b);
      int e = 0;
      while (!(F(g, e) == b && F(g, (e + 1) % 3) == a)) ++e;
      face = g;
      entry = e;
    }
  }
  if (end.is_vertex()) {
    if (!curve.back().is_vertex() || curve.back().vertex != end.vertex) return {};
  } else if (end.is_edge()) {
    if (!curve.back().is_edge() || curve.back().a != end.a || curve.back().b != end.b) return {};
  } else {
    if (state != State::face) return {};
    curve.push_back(CurvePoint::in_face(face, clamped_barycentric_2d(uv(F(face, 0)), uv(F(face, 1)), uv(F(face, 2)),
                                                          P.row(P.rows() - 1).transpose())));
  }
  return snap_to_vertices(without_turnbacks(curve), options.snap_fraction);
}

SurfaceCurve snap_to_vertices(const SurfaceCurve& curve, double fraction) {
  SurfaceCurve out;
  for (CurvePoint p : curve) {
    if (p.is_edge() && p.t < fraction) p = CurvePoint::at_vertex(p.a);
    else if (p.is_edge() && p.t > 1.0 - fraction) p = CurvePoint::at_vertex(p.b);
    if (!out.empty() && p.is_vertex() && out.back().is_vertex() && out.back().vertex == p.vertex) continue;
    out.push_back(p);
  }
  return out;
}

Eigen::MatrixXd smooth_polyline_2d(const Eigen::MatrixXd& P, const std::vector<int>& fixed_rows, double spacing,
                                   double wavelength, std::vector<int>* fixed_out, double tolerance,
                                   const std::vector<int>& kept_rows, double kept_tolerance) {
  const int n = static_cast<int>(P.rows());
  std::vector<int> fixed = fixed_rows;
  fixed.push_back(0);
  fixed.push_back(n - 1);
  // Without a tolerance, kept rows are fixed.
  if (!(tolerance > 0.0)) fixed.insert(fixed.end(), kept_rows.begin(), kept_rows.end());
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  std::vector<char> kept(static_cast<size_t>(n), 0);
  if (tolerance > 0.0)
    for (int i : kept_rows)
      if (!std::binary_search(fixed.begin(), fixed.end(), i)) kept[static_cast<size_t>(i)] = 1;
  std::vector<int> breaks = fixed;
  for (int i = 0; i < n; ++i)
    if (kept[static_cast<size_t>(i)]) breaks.push_back(i);
  std::sort(breaks.begin(), breaks.end());
  // Resample every section between fixed (and kept) rows at (about) `spacing`.
  std::vector<Eigen::Vector2d> pts;
  std::vector<int> fixed_new, kept_new;
  for (size_t s = 0; s + 1 < breaks.size(); ++s) {
    const int i0 = breaks[s], i1 = breaks[s + 1];
    std::vector<double> arc{0.0};
    for (int i = i0; i < i1; ++i) arc.push_back(arc.back() + (P.row(i + 1) - P.row(i)).norm());
    const double length = arc.back();
    const int segments = std::max(1, static_cast<int>(std::ceil(length / spacing - 1e-9)));
    (kept[static_cast<size_t>(i0)] ? kept_new : fixed_new).push_back(static_cast<int>(pts.size()));
    pts.push_back(P.row(i0).transpose());
    int j = 0;
    for (int k = 1; k < segments; ++k) {
      const double target = length * k / segments;
      while (j + 1 < static_cast<int>(arc.size()) - 1 && arc[static_cast<size_t>(j + 1)] < target) ++j;
      const double span = arc[static_cast<size_t>(j + 1)] - arc[static_cast<size_t>(j)];
      const double u = span > 0.0 ? (target - arc[static_cast<size_t>(j)]) / span : 0.0;
      pts.push_back(((1.0 - u) * P.row(i0 + j) + u * P.row(i0 + j + 1)).transpose());
    }
  }
  fixed_new.push_back(static_cast<int>(pts.size()));
  pts.push_back(P.row(n - 1).transpose());
  const int m = static_cast<int>(pts.size());
  Eigen::MatrixXd X(m, 2);
  for (int i = 0; i < m; ++i) X.row(i) = pts[static_cast<size_t>(i)].transpose();
  if (fixed_out) *fixed_out = fixed_new;
  if (m < 3 || wavelength <= 0.0) return X;
  const double ratio = wavelength / (2.0 * M_PI * spacing);
  const double lambda = ratio * ratio * ratio * ratio;
  std::vector<int> free_index(static_cast<size_t>(m), -1);
  int nf = 0;
  std::vector<char> is_fixed(static_cast<size_t>(m), 0);
  for (int i : fixed_new) is_fixed[static_cast<size_t>(i)] = 1;
  for (int i = 0; i < m; ++i)
    if (!is_fixed[static_cast<size_t>(i)]) free_index[static_cast<size_t>(i)] = nf++;
  if (nf == 0) return X;
  // The minimizer of sum w_i |X_i - S_i|^2 + lambda sum |second differences|^2
  // for data weights w (the samples S are X's rows on entry).
  const Eigen::MatrixXd S = X;
  auto solve = [&](const std::vector<double>& w) {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(nf, 2);
    for (int i = 0; i < m; ++i)
      if (free_index[static_cast<size_t>(i)] >= 0) {
        const double wi = w[static_cast<size_t>(i)];
        trip.emplace_back(free_index[static_cast<size_t>(i)], free_index[static_cast<size_t>(i)], wi);
        b.row(free_index[static_cast<size_t>(i)]) += wi * S.row(i);
      }
    // Second differences X_(i-1) - 2 X_i + X_(i+1), i = 1 .. m-2.
    for (int i = 1; i + 1 < m; ++i) {
      const int idx[3] = {i - 1, i, i + 1};
      const double c[3] = {1.0, -2.0, 1.0};
      for (int r = 0; r < 3; ++r) {
        const int fr = free_index[static_cast<size_t>(idx[r])];
        if (fr < 0) continue;
        for (int q = 0; q < 3; ++q) {
          const int fs = free_index[static_cast<size_t>(idx[q])];
          const double wq = lambda * c[r] * c[q];
          if (fs >= 0) trip.emplace_back(fr, fs, wq);
          else b.row(fr) -= wq * S.row(idx[q]);
        }
      }
    }
    Eigen::SparseMatrix<double> A(nf, nf);
    A.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
    if (solver.info() != Eigen::Success) throw NumericalError("smoothing a seam curve: the solve failed");
    const Eigen::MatrixXd Y = solver.solve(b);
    Eigen::MatrixXd out = S;
    for (int i = 0; i < m; ++i)
      if (free_index[static_cast<size_t>(i)] >= 0) out.row(i) = Y.row(free_index[static_cast<size_t>(i)]);
    return out;
  };
  std::vector<double> w(static_cast<size_t>(m), 1.0);
  if (!(tolerance > 0.0)) return solve(w);
  // Within the tolerance the polyline says nothing: an edge path stands for
  // its curve only up to the mesh's resolution, and its staircase has every
  // wavelength, so no wavelength alone removes it. The data weights start
  // low (a curve stiffer by 1 / min_weight^(1/4) in wavelength) and grow,
  // continuously in the distance, where the curve leaves the tolerance
  // (iteratively reweighted least squares, a fixed number of rounds).
  const double min_weight = 1e-4;
  std::fill(w.begin(), w.end(), min_weight);
  // Kept rows (a seam's clicked points) may grow beyond full weight until
  // the curve passes within their tolerance of them.
  std::vector<double> cap(static_cast<size_t>(m), 1.0);
  for (int i : kept_new) cap[static_cast<size_t>(i)] = 1e8;
  for (int round = 0; round < 12; ++round) {
    X = solve(w);
    for (int i = 0; i < m; ++i) {
      // A kept row's distance is to its own point, any other's to the polyline.
      const double d = cap[static_cast<size_t>(i)] > 1.0 ? (X.row(i) - S.row(i)).norm()
                                                         : distance_to_polyline(P, X.row(i).transpose());
      const double r = d / (cap[static_cast<size_t>(i)] > 1.0 ? kept_tolerance : tolerance);
      w[static_cast<size_t>(i)] = std::min(cap[static_cast<size_t>(i)], w[static_cast<size_t>(i)] * std::max(1.0, r * r));
    }
  }
  return solve(w);
}

namespace {

// The edge path as a curve of vertex points.
SurfaceCurve vertex_curve(const std::vector<int>& ids, bool closed) {
  SurfaceCurve c;
  for (int v : ids) c.push_back(CurvePoint::at_vertex(v));
  if (closed && !ids.empty()) c.push_back(CurvePoint::at_vertex(ids.front()));
  return c;
}

// One open path (first and last vertex fixed) smoothed in a band chart.
SurfaceCurve smooth_open_path(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                              const std::vector<std::vector<int>>& neighbors, const std::vector<std::vector<int>>& vf,
                              const std::vector<int>& ids, const std::vector<char>& fixed_vertex,
                              const EdgePathSmoothing& options, bool& smoothed) {
  smoothed = false;
  if (ids.size() < 3) return vertex_curve(ids, false);
  double length = 0.0;
  for (size_t i = 0; i + 1 < ids.size(); ++i) length += (V.row(ids[i + 1]) - V.row(ids[i])).norm();
  const double spacing = 0.5 * length / static_cast<double>(ids.size() - 1);
  for (int rings = options.band_rings; rings >= 1; --rings) {
    // Vertices within `rings - 1` rings of the path; the band is their faces.
    std::vector<int> ring(static_cast<size_t>(V.rows()), -1);
    std::deque<int> queue;
    for (int v : ids) {
      ring[static_cast<size_t>(v)] = 0;
      queue.push_back(v);
    }
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop_front();
      if (ring[static_cast<size_t>(v)] >= rings - 1) continue;
      for (int w : neighbors[static_cast<size_t>(v)])
        if (ring[static_cast<size_t>(w)] < 0) {
          ring[static_cast<size_t>(w)] = ring[static_cast<size_t>(v)] + 1;
          queue.push_back(w);
        }
    }
    std::vector<char> in_band(static_cast<size_t>(F.rows()), 0);
    for (int v = 0; v < V.rows(); ++v)
      if (ring[static_cast<size_t>(v)] >= 0)
        for (int f : vf[static_cast<size_t>(v)]) in_band[static_cast<size_t>(f)] = 1;
    std::vector<int> band_faces, local(static_cast<size_t>(V.rows()), -1), band_vertices;
    for (int f = 0; f < F.rows(); ++f)
      if (in_band[static_cast<size_t>(f)]) band_faces.push_back(f);
    Eigen::MatrixXi Fb(static_cast<int>(band_faces.size()), 3);
    for (size_t i = 0; i < band_faces.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int v = F(band_faces[i], k);
        if (local[static_cast<size_t>(v)] < 0) {
          local[static_cast<size_t>(v)] = static_cast<int>(band_vertices.size());
          band_vertices.push_back(v);
        }
        Fb(static_cast<int>(i), k) = local[static_cast<size_t>(v)];
      }
    if (boundary_loops(Fb).size() != 1 || euler_characteristic(Fb) != 1) continue;
    Eigen::MatrixXd Vb(static_cast<int>(band_vertices.size()), 3);
    for (size_t i = 0; i < band_vertices.size(); ++i) Vb.row(static_cast<int>(i)) = V.row(band_vertices[i]);
    const std::vector<int> loop = boundary_loops(Fb).front();
    Eigen::MatrixXd UV;
    try {
      UV = lscm_flatten(Vb, Fb, loop);
    } catch (const NumericalError&) {
      UV.resize(0, 2);
    }
    if (UV.rows() == 0 || distortion_stats(Vb, Fb, UV).flipped_triangles > 0) {
      FlattenOptions o;
      o.boundary_weight = 0.0;
      UV = flatten_piece(Vb, Fb, o).UV;
    }
    Eigen::MatrixXd P(static_cast<int>(ids.size()), 2);
    std::vector<int> fixed_rows, kept_rows;
    for (size_t i = 0; i < ids.size(); ++i) {
      P.row(static_cast<int>(i)) = UV.row(local[static_cast<size_t>(ids[i])]);
      const char kind = fixed_vertex[static_cast<size_t>(ids[i])];
      if (kind == 1) fixed_rows.push_back(static_cast<int>(i));
      if (kind == 2) kept_rows.push_back(static_cast<int>(i));
    }
    // Chart units: LSCM keeps the band's scale only roughly, so spacing and
    // wavelength are taken in the chart's own length of the path.
    double chart_length = 0.0;
    for (int i = 0; i + 1 < P.rows(); ++i) chart_length += (P.row(i + 1) - P.row(i)).norm();
    const double scale = length > 0.0 ? chart_length / length : 1.0;
    for (double wavelength = options.wavelength; wavelength >= 2.0 * spacing; wavelength *= 0.5) {
      std::vector<int> fixed_new;
      const Eigen::MatrixXd X =
          smooth_polyline_2d(P, fixed_rows, scale * spacing, scale * wavelength, &fixed_new,
                             scale * 2.0 * spacing * options.tolerance, kept_rows,
                             scale * 2.0 * spacing * options.click_tolerance);
      // A path that is smooth already (a straight run of edges) stays on its edges.
      double off = 0.0;
      for (int r = 0; r < X.rows(); ++r) {
        off = std::max(off, distance_to_polyline(P, X.row(r).transpose()));
      }
      if (off < 1e-6 * scale * spacing) {
        smoothed = true;
        return vertex_curve(ids, false);
      }
      // Fixed rows sit on their vertices; P's fixed rows map to X's in order.
      std::vector<int> row_vertex(static_cast<size_t>(X.rows()), -1);
      std::vector<int> fixed_all = fixed_rows;
      fixed_all.push_back(0);
      fixed_all.push_back(static_cast<int>(ids.size()) - 1);
      std::sort(fixed_all.begin(), fixed_all.end());
      fixed_all.erase(std::unique(fixed_all.begin(), fixed_all.end()), fixed_all.end());
      for (size_t k = 0; k < fixed_new.size() && k < fixed_all.size(); ++k)
        row_vertex[static_cast<size_t>(fixed_new[k])] = local[static_cast<size_t>(ids[static_cast<size_t>(fixed_all[k])])];
      SurfaceCurve c = trace_polyline(UV, Fb, CurvePoint::at_vertex(local[static_cast<size_t>(ids.front())]),
                                              CurvePoint::at_vertex(local[static_cast<size_t>(ids.back())]), X,
                                              row_vertex, options.trace);
      if (c.empty()) continue;
      for (CurvePoint& p : c) {
        if (p.is_vertex()) p.vertex = band_vertices[static_cast<size_t>(p.vertex)];
        else if (p.is_edge()) p = CurvePoint::on_edge(band_vertices[static_cast<size_t>(p.a)],
                                                      band_vertices[static_cast<size_t>(p.b)], p.t);
        else p.face = band_faces[static_cast<size_t>(p.face)];
      }
      smoothed = true;
      return c;
    }
  }
  // No chart holds the whole curve (it passes where the band folds or meets
  // the garment's edge): its two halves, joined at the middle vertex, each
  // in a chart of its own.
  if (ids.size() >= 8) {
    const size_t half = ids.size() / 2;
    const std::vector<int> a(ids.begin(), ids.begin() + static_cast<long>(half) + 1);
    const std::vector<int> b(ids.begin() + static_cast<long>(half), ids.end());
    bool ok_a = false, ok_b = false;
    SurfaceCurve c = smooth_open_path(V, F, neighbors, vf, a, fixed_vertex, options, ok_a);
    const SurfaceCurve second = smooth_open_path(V, F, neighbors, vf, b, fixed_vertex, options, ok_b);
    c.insert(c.end(), second.begin() + 1, second.end());
    smoothed = ok_a && ok_b;
    return c;
  }
  return vertex_curve(ids, false);
}

}  // namespace

SurfaceCurve smooth_edge_path(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& vertex_ids,
                              const std::vector<int>& fixed_vertex_ids, bool closed, const EdgePathSmoothing& options,
                              bool* smoothed, const std::vector<int>& kept_vertex_ids) {
  const int n = static_cast<int>(V.rows());
  const auto neighbors = vertex_neighbors(F, n);
  const auto vf = vertex_faces(F, n);
  std::vector<char> fixed(static_cast<size_t>(n), 0);
  for (int v : kept_vertex_ids) fixed[static_cast<size_t>(v)] = 2;
  for (int v : fixed_vertex_ids) fixed[static_cast<size_t>(v)] = 1;
  bool ok = true;
  SurfaceCurve out;
  if (!closed) {
    out = smooth_open_path(V, F, neighbors, vf, vertex_ids, fixed, options, ok);
  } else {
    // A closed path's band is an annulus, no chart: two open halves, joined
    // at the first vertex and the one halfway round.
    const size_t half = vertex_ids.size() / 2;
    std::vector<int> a(vertex_ids.begin(), vertex_ids.begin() + static_cast<long>(half) + 1);
    std::vector<int> b(vertex_ids.begin() + static_cast<long>(half), vertex_ids.end());
    b.push_back(vertex_ids.front());
    bool ok_a = true, ok_b = true;
    out = smooth_open_path(V, F, neighbors, vf, a, fixed, options, ok_a);
    const SurfaceCurve second = smooth_open_path(V, F, neighbors, vf, b, fixed, options, ok_b);
    out.insert(out.end(), second.begin() + 1, second.end());
    ok = ok_a && ok_b;
  }
  if (smoothed) *smoothed = ok;
  return out;
}

}  // namespace gp
