#pragma once
// Isotropic remeshing (CGAL, Botsch and Kobbelt's split / collapse / flip /
// relax scheme) of garment patches, and the triangle-quality figures that
// make-garment reports.
#include <functional>
#include <vector>
#include <Eigen/Core>

namespace gp {

struct RemeshOptions {
  double target_edge_length = 0.0;  // metres, must be positive
  int iterations = 8;               // split/collapse/flip/relax rounds
  int relaxation_steps = 2;         // tangential relaxation steps per round
  int final_smoothing_rounds = 3;   // Laplacian rounds of interior vertices after CGAL (remesh_patch)
};

// Remeshes the whole open patch (V #V by 3, F #F by 3; replaced by the result)
// to near-even triangles. Boundary vertices are resampled along the boundary
// and after every move projected to the closest point of `boundary_curves`
// (closed polylines, each #P by 3, listed point by point), so the boundary
// stays on those curves; interior vertices are projected by `project_interior`
// (point -> point on the target surface) or, when it is empty, onto the input
// patch. A projection onto a surface extending beyond the boundary (such as
// the whole comfort-offset surface of the body) lets vertices near the
// boundary relax without being pinched onto it.
// Throws GeometryError if the patch is not a manifold triangle mesh.
using PointProjection = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;
void remesh_patch(Eigen::MatrixXd& V, Eigen::MatrixXi& F,
                  const std::vector<Eigen::MatrixXd>& boundary_curves, const RemeshOptions& options,
                  const PointProjection& project_interior = {});

// Remeshes only the faces with face_selected[f] != 0. Edges on the mesh
// border and between selected and other faces are kept exactly (neither
// split, collapsed nor moved), so the rest of the mesh is untouched: the
// vertices of unselected faces keep their ids and positions (they come first
// in the result, in their old order) and unselected faces keep their relative
// order. face_values (#F, may be empty) is carried along: new faces get
// `new_face_value`. Returns, per result vertex, its old id or -1 if new.
std::vector<int> remesh_selected_faces(Eigen::MatrixXd& V, Eigen::MatrixXi& F,
                                       const std::vector<char>& face_selected,
                                       const RemeshOptions& options, Eigen::VectorXd& face_values,
                                       double new_face_value);

struct MeshQuality {
  int vertex_count = 0;
  int face_count = 0;
  double min_angle_deg = 0.0;              // smallest triangle angle
  double fraction_min_angle_over_20 = 0.0;  // triangles whose smallest angle exceeds 20 degrees
  double mean_edge_length = 0.0;            // metres
  double min_edge_ratio = 0.0;              // shortest edge / target
  double max_edge_ratio = 0.0;              // longest edge / target
  double fraction_edges_within_30 = 0.0;    // edges within 30 % of the target length
  int faces_min_angle_under_5 = 0;          // slivers: triangles with an angle below 5 degrees
  // Inner vertices whose |angle defect| (mesh/measures.h) is 18 degrees or
  // more: cone points, where the mesh folds or pinches; none on a smooth garment.
  int cone_vertices = 0;
  double max_abs_angle_defect_deg = 0.0;    // inner vertices
  double abs_angle_defect_sum = 0.0;        // radians, over inner vertices
};
MeshQuality measure_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            double target_edge_length);
// The threshold of MeshQuality::cone_vertices, degrees.
constexpr double kConeDefectDeg = 18.0;

}  // namespace gp
