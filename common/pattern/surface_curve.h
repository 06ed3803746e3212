#pragma once
// Smooth curves on a triangle mesh that run through its triangles rather
// than along its edges, as cut lines for seams and darts.
//
// A curve: points at vertices, on edges or inside faces (a dart's tip),
// consecutive points sharing a face, chords between them. Curves are drawn
// as polylines in a flat chart (a conformally flattened band around an edge
// path, or a flat piece) and traced across its triangles; insert_curves()
// (curve_insertion.h) makes them edge paths and mesh_cut.h cuts them. A
// crossing within snap_fraction of an edge's end is that vertex, so a small
// change of the mesh moves the curve as little.
#include <string>
#include <vector>
#include <Eigen/Core>

#include "spec/option_fields.h"

namespace gp {

struct CurvePoint {
  int vertex = -1;              // a mesh vertex, or -1
  int a = -1, b = -1;           // else a point on edge (a, b), a < b, at (1 - t) a + t b
  double t = 0.0;
  int face = -1;                // else a point inside face `face` at barycentric `bary`
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();

  static CurvePoint at_vertex(int v);
  static CurvePoint on_edge(int a, int b, double t);  // any order of a, b
  static CurvePoint in_face(int face, const Eigen::Vector3d& bary);
  bool is_vertex() const { return vertex >= 0; }
  bool is_edge() const { return vertex < 0 && a >= 0; }
  bool is_face() const { return vertex < 0 && a < 0; }
};
using SurfaceCurve = std::vector<CurvePoint>;

// Position of a curve point on the mesh (V #V by 3 or #V by 2, F #F by 3).
Eigen::VectorXd curve_point_position(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const CurvePoint& p);

// Positions of every point of the curve, #points by V.cols().
Eigen::MatrixXd curve_positions(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const SurfaceCurve& curve);

// Length of the curve's polyline on V (metres).
double curve_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const SurfaceCurve& curve);

struct TraceOptions {
  double snap_fraction = 1e-6;      // a crossing this near an edge's end (fraction) is that end
  double min_edge_fraction = 0.02;  // other crossings keep this fraction from the ends
  int max_steps = 100000;  // triangles walked, a guard against loops
};

struct TraceOptionFields {
  template <class Fields>
  void operator()(TraceOptions& o, Fields& f) const {
    f.number("snap_fraction", o.snap_fraction, Range::between(0.0, 0.5));
    f.number("min_edge_fraction", o.min_edge_fraction, Range::between(0.0, 0.5));
    f.integer("max_steps", o.max_steps, Range::between(1, 1e9));
  }
};

// Traces the polyline P (#P by 2) in the chart UV (#V by 2, F counter-
// clockwise) from `start` to `end` (vertex, boundary-edge or face points at
// P's first and last rows); `row_vertex` (per row, -1: none) names vertices
// the curve passes exactly. Empty when P leaves the chart or the walk fails.
SurfaceCurve trace_polyline(const Eigen::MatrixXd& UV, const Eigen::MatrixXi& F, const CurvePoint& start,
                            const CurvePoint& end, const Eigen::MatrixXd& P, const std::vector<int>& row_vertex = {},
                            const TraceOptions& options = {});

// The curve with its edge points within `fraction` of an edge's end moved to
// that vertex (and repeated vertices dropped).
SurfaceCurve snap_to_vertices(const SurfaceCurve& curve, double fraction);

// A smoothing spline of P (#P by 2) resampled every `spacing`: the minimizer
// of sum w_i |X_i - P_i|^2 + lambda sum |X_(i-1) - 2 X_i + X_(i+1)|^2, lambda
// = (wavelength / (2 pi spacing))^4, with `fixed_rows` (and both ends) in
// place (their result rows in `fixed_out`). With `tolerance` > 0 the weights
// start at 1e-4 and grow by (d_i / tolerance)^2 per round up to 1 where the
// curve is farther than that from P (12 rounds of iteratively reweighted
// least squares), removing a staircase within the tolerance at any
// wavelength; `kept_rows` stay within `kept_tolerance` (weights unbounded).
Eigen::MatrixXd smooth_polyline_2d(const Eigen::MatrixXd& P, const std::vector<int>& fixed_rows, double spacing,
                                   double wavelength, std::vector<int>* fixed_out = nullptr, double tolerance = 0.0,
                                   const std::vector<int>& kept_rows = {}, double kept_tolerance = 0.0);

struct EdgePathSmoothing {
  double wavelength = 0.12;   // metres: wiggles shorter than this are smoothed away
  double tolerance = 0.5;        // of the mean edge length: the path's staircase is free within it
  double click_tolerance = 1.0;  // the same for clicked points (snapped to a corner of their face)
  int band_rings = 4;         // the chart: faces within this many vertex rings of the path
  TraceOptions trace;
};

struct EdgePathSmoothingFields {
  template <class Fields>
  void operator()(EdgePathSmoothing& o, Fields& f) const {
    f.number("wavelength_m", o.wavelength, Range::non_negative());
    f.number("tolerance", o.tolerance, Range::non_negative());
    f.number("click_tolerance", o.click_tolerance, Range::non_negative());
    f.integer("band_rings", o.band_rings, Range::between(0, 1000));
    f.group("trace", o.trace, TraceOptionFields{});
  }
};

// The edge path `vertex_ids` (V #V by 3, F #F by 3; `closed` returns to its
// first vertex) as a smooth curve through nearby triangles: exactly through
// its ends and `fixed_vertex_ids`, within click_tolerance of
// `kept_vertex_ids` (pinning clicks would kink the curve). The chart is the
// band around the path, by LSCM or injectively; when none holds the curve,
// the edge path is returned, and `smoothed` says so.
SurfaceCurve smooth_edge_path(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& vertex_ids,
                              const std::vector<int>& fixed_vertex_ids, bool closed, const EdgePathSmoothing& options,
                              bool* smoothed = nullptr, const std::vector<int>& kept_vertex_ids = {});

}  // namespace gp
