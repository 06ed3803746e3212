#pragma once
// Tool T1, second half: the closed edge paths smoothed into curves on the
// body, and the body cut exactly along them; the part holding the region
// point is the garment region.
//
// The side of every body vertex is phi = +1 inside (a face flood fill that
// does not cross the paths), -1 outside, 0 on the paths; phi is smoothed by
// Jacobi diffusion in a band around the paths and the curve is its zero
// level set. That smooths like a curve-shortening flow and is by
// construction closed, free of self-crossings and on the surface: chords
// inside body faces, stored as face + barycentric coordinates, valid in
// every pose.
#include <string>
#include <vector>
#include <Eigen/Core>

#include "garment/surface_point.h"

namespace gp {

// One closed edge path to cut along, with its spec name and location.
struct LoopPath {
  std::string name;
  std::vector<int> vertex_ids;  // closed body vertex path, first vertex not repeated
  std::string where;            // spec field of the loop, for errors
};

struct RegionCutOptions {
  int smoothing_iterations = 12;  // Jacobi diffusion steps of phi (0 keeps the curve near the path)
  int band_rings = 5;             // phi changes only within this many edge rings of the paths
  // |phi| below this is pushed to +-min_level so that no curve point falls on a
  // body vertex (which would create zero-length edges); moves the curve by at
  // most a few percent of a body edge.
  double min_level = 0.02;
};

// A closed curve on the body: segment i runs inside body face segments[i].face
// from bary_start to bary_end (barycentric coordinates in that face); the end
// of segment i is the start of segment i+1. The region lies on the left when
// walking along the curve with the outward normal up.
struct CurveSegment {
  int face = -1;
  Eigen::Vector3d bary_start = Eigen::Vector3d::Zero();
  Eigen::Vector3d bary_end = Eigen::Vector3d::Zero();
};
struct BodyCurve {
  std::string name;
  std::vector<CurveSegment> segments;
};

// Curve points (segment starts) evaluated on a pose: #segments by 3.
Eigen::MatrixXd evaluate_curve(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const BodyCurve& curve);
// Length of the closed polyline of evaluate_curve.
double curve_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const BodyCurve& curve);

struct RegionCut {
  Eigen::MatrixXd V;                 // region mesh, #Vr by 3, on the body surface
  Eigen::MatrixXi F;                 // #Fr by 3, oriented like the body
  std::vector<BodyCurve> curves;     // one per loop, in the order of the loops
  std::vector<std::vector<int>> boundary_vertex_ids;  // region boundary per loop (region ids)
  double area = 0.0;                 // region area, m^2
};

// Cuts the body (V #V by 3, F #F by 3, closed and manifold where the loops
// run) along the smoothed loops and returns the part holding body vertex
// `region_vertex`. `region_where` names the region field for errors.
// Throws GeometryError when loops share vertices, a loop does not separate the
// region from the rest of the body (the message names the loop that leaks),
// the region point lies on a loop or outside every loop, a loop does not bound
// the region, or the smoothed region is empty, degenerate or reaches an open
// border of the body.
RegionCut cut_region(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const std::vector<LoopPath>& loops, int region_vertex,
                     const std::string& region_where, const RegionCutOptions& options = {});

}  // namespace gp
