#pragma once
// Basic measures of a triangle mesh. V is #V by 3, F is #F by 3.
#include <Eigen/Core>

namespace gp {

// Triangle areas, #F.
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Total area, summed face by face in order (the same bits as summing face_areas sequentially).
double mesh_area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// The value below which `fraction` (0..1) of the total weight lies: of the values sorted ascending
// (ties by index), the first whose cumulative weight reaches fraction * total; the largest if
// rounding keeps the sum short, 0 for none. Weights >= 0, one per value (face areas: a figure
// independent of the mesh's resolution).
double area_weighted_percentile(const Eigen::VectorXd& values, const Eigen::VectorXd& weights, double fraction);

// Unit face normals (right-hand rule over the corner order), #F by 3; zero rows if degenerate.
Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Area-weighted vertex normals, normalized, #V by 3.
Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Signed enclosed volume by the divergence theorem (positive for a closed, outward mesh).
double signed_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Area-weighted centroid of the triangles (#V by 3, #F by 3): sum of area * centroid over the
// total area; zero when the area is zero.
Eigen::Vector3d area_centroid(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Angle defect (discrete Gaussian curvature), #V: 2 pi minus the sum of corner angles [rad].
// Meaningful for inner vertices; a boundary vertex gets the same formula (pi minus its turning
// angle plus pi), a vertex used by no face 2 pi.
Eigen::VectorXd angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Length of the bounding box diagonal.
double bounding_box_diagonal(const Eigen::MatrixXd& V);

// Edge lengths for the unique edges E (#E by 2).
Eigen::VectorXd edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E);

}  // namespace gp
