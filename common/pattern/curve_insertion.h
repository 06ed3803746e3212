#pragma once
// Refining a triangle mesh so that curves through its triangles
// (surface_curve.h) become edge paths: every curve point on an edge splits
// the edge, every point inside a face is added to it, and every face a curve
// crosses is retriangulated with the curve's chords as constraints (a
// constrained triangulation of the face's points in the face's own
// plane, CGAL). The refined mesh lies exactly on the input surface.
#include <vector>
#include <Eigen/Core>

#include "garment/surface_point.h"
#include "pattern/surface_curve.h"

namespace gp {

struct RefinedMesh {
  Eigen::MatrixXd V;                 // #Vr by 3: the input's vertices first (same ids), then the new points
  Eigen::MatrixXi F;                 // #Fr by 3, oriented like the input
  std::vector<int> parent_face;      // #Fr: the input face each face lies in
  std::vector<SurfacePoint> origin;  // #Vr: each vertex as a point of the input mesh
  std::vector<std::vector<int>> paths;    // per curve: its vertex path in the refined mesh
  std::vector<std::vector<int>> carried;  // per carried path: the same path with the new points on its edges
};

// V #V by 3, F #F by 3 (edge-manifold, consistently oriented). `curves`
// (surface_curve.h) may share points (the same vertex, the same point of an
// edge or of a face) but must not cross inside a face. Points that coincide
// exactly become one vertex: an edge point at t = 0 or 1 is that end, a face
// point with a zero barycentric coordinate is the point of that edge (or
// corner), and points that still coincide in their face's plane (the same
// face point given twice) are merged into the lowest id. `carried` are edge paths of the
// input mesh (e.g. curves inserted earlier) that are returned with the
// points that now split their edges. New vertices are numbered in a
// deterministic order (edge points by edge and position, then face points).
// Throws GeometryError when two curves cross inside a face, a curve leaves
// the mesh (consecutive points share no face) or crosses a degenerate face.
RefinedMesh insert_curves(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SurfaceCurve>& curves,
                          const std::vector<std::vector<int>>& carried = {});

}  // namespace gp
