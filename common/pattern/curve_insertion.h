#pragma once
// A triangle mesh refined so that curves through its triangles
// (surface_curve.h) become edge paths: curve points split edges or are added
// to faces, and crossed faces are retriangulated with the chords as
// constraints (CGAL, in the face's plane). The result lies on the input.
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

// V #V by 3, F #F by 3 (edge-manifold, oriented). `curves` may share points
// but not cross inside a face; coinciding points (t = 0 or 1 on an edge, a
// zero barycentric coordinate, the same face point twice) become one vertex,
// the lowest id. `carried` edge paths come back with the points now on their
// edges. New vertices are numbered deterministically (edge points by edge
// and position, then face points). Throws GeometryError when curves cross in
// a face, a curve leaves the mesh or crosses a degenerate face.
RefinedMesh insert_curves(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SurfaceCurve>& curves,
                          const std::vector<std::vector<int>>& carried = {});

}  // namespace gp
