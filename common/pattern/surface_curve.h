#pragma once
// Smooth curves on a triangle mesh that run through its triangles rather
// than along its edges, as cut lines for seams and darts.
//
// A curve is a sequence of points, each a mesh vertex, a point on a mesh edge
// or a point inside a face (a dart's tip), consecutive points lying in one
// common face; between two points the curve is the straight chord inside
// that face. insert_curves() (curve_insertion.h) refines the mesh so that
// every curve becomes an edge path, which mesh_cut.h then cuts open.
//
// Curves are drawn in a flat chart of the part of the surface they cross (a
// band around an edge path, flattened conformally, or a flattened pattern
// piece): a polyline in the chart is traced across the chart's triangles,
// each crossing of a triangle edge becoming a curve point. A crossing within
// `snap_fraction` (1e-6) of an edge's end becomes that vertex; otherwise the
// crossings are where the polyline meets the edges, so that a small change of
// the mesh moves the curve by as little (the thin triangles a curve leaves
// near a vertex are handled where pieces are flattened and measured).
#include <string>
#include <vector>
#include <Eigen/Core>

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
  // A crossing closer than this fraction of its edge to an end is that end.
  double snap_fraction = 1e-6;
  // Crossings are kept at least this fraction of their edge from its ends.
  double min_edge_fraction = 0.02;
  int max_steps = 100000;  // triangles walked, a guard against loops
};

// Traces the 2D polyline P (#P by 2, in the chart UV #V by 2 of the mesh with
// faces F, counter-clockwise) from `start` (a vertex, a point on a boundary
// edge or a point inside a face; P's first row must be its position) to
// `end` (the same kinds; P's last row its position). `row_vertex` (optional, one entry per row
// of P) names the mesh vertex a row sits on (-1: none): the curve passes
// exactly through those vertices. Returns the curve, its first point
// `start`, its last `end` (a face point re-expressed in the face the walk
// reached). Empty when the polyline leaves the chart (crosses its boundary)
// or the walk fails.
SurfaceCurve trace_polyline(const Eigen::MatrixXd& UV, const Eigen::MatrixXi& F, const CurvePoint& start,
                            const CurvePoint& end, const Eigen::MatrixXd& P, const std::vector<int>& row_vertex = {},
                            const TraceOptions& options = {});

// The curve with its edge points within `fraction` of an edge's end moved to
// that vertex (and repeated vertices dropped).
SurfaceCurve snap_to_vertices(const SurfaceCurve& curve, double fraction);

// Smooths the 2D polyline P (#P by 2) resampled every `spacing` (same unit),
// keeping its rows listed in `fixed_rows` (first and last always) in place:
// the minimizer of sum |X_i - P_i|^2 + lambda sum |X_(i-1) - 2 X_i + X_(i+1)|^2,
// lambda = (wavelength / (2 pi spacing))^4, which removes wiggles shorter than
// about `wavelength` and follows the polyline beyond (a smoothing spline).
// With `tolerance` > 0 (same unit) the polyline is trusted only up to that
// distance: the weights w_i of |X_i - P_i|^2 start at 1e-4 (a curve stiffer
// by a factor 10 in wavelength) and grow by (d_i / tolerance)^2 per round, up
// to 1, where the curve lies farther than the tolerance from the polyline
// (d_i: distance to it), for 12 rounds (iteratively reweighted least
// squares), so that wiggles within the tolerance are removed whatever their
// wavelength, as an edge path's staircase needs. Rows listed in `kept_rows`
// are kept within `kept_tolerance` of their point rather than fixed (their
// weight grows without bound); without a tolerance they are fixed.
// Returns the smoothed polyline; fixed rows keep their exact coordinates and
// their rows in the result are written to `fixed_out` (in order, first and
// last included).
Eigen::MatrixXd smooth_polyline_2d(const Eigen::MatrixXd& P, const std::vector<int>& fixed_rows, double spacing,
                                   double wavelength, std::vector<int>* fixed_out = nullptr, double tolerance = 0.0,
                                   const std::vector<int>& kept_rows = {}, double kept_tolerance = 0.0);

struct EdgePathSmoothing {
  double wavelength = 0.12;   // metres: wiggles shorter than this are smoothed away
  // Fraction of the path's mean edge length within which the curve may leave
  // the edge path freely: an edge path follows its curve only up to the
  // mesh's resolution, in a staircase whose steps repeat at any wavelength
  // (0: the smoothing spline alone).
  double tolerance = 0.5;
  // The same for a seam's clicked points: the vertex a click snapped to is a
  // corner of the face the click lies in, within about one edge of it.
  double click_tolerance = 1.0;
  int band_rings = 4;         // the chart: faces within this many vertex rings of the path
  TraceOptions trace;
};

// The edge path `vertex_ids` (V #V by 3, F #F by 3) as a smooth curve through
// the triangles near it, passing exactly through its vertices listed in
// `fixed_vertex_ids` and its two ends (for a closed path, pass closed = true:
// the first vertex is fixed and the curve returns to it), and within the
// tolerance of those in `kept_vertex_ids` (a seam's clicked points: a vertex
// names a clicked point only up to the mesh's resolution, and pinning the
// curve to it puts a kink at every click). The chart is the
// band of faces around the path, flattened by LSCM (or, where LSCM flips a
// triangle or the band is no disk with fewer rings, injectively); when no
// chart holds the smoothed curve, the edge path itself is returned (its
// points at vertices). `smoothed` tells which.
SurfaceCurve smooth_edge_path(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& vertex_ids,
                              const std::vector<int>& fixed_vertex_ids, bool closed, const EdgePathSmoothing& options,
                              bool* smoothed = nullptr, const std::vector<int>& kept_vertex_ids = {});

}  // namespace gp
