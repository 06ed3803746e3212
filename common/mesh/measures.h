#pragma once
// Basic measures of a triangle mesh. V is #V by 3, F is #F by 3.
#include <Eigen/Core>

namespace gp {

// Triangle areas, #F.
Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Total area, summed face by face in order (the same bits as summing face_areas).
double mesh_area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// The value below which `fraction` (0..1) of the total weight (>= 0, one per value) lies: the first
// of the values sorted ascending (ties by index) whose cumulative weight reaches fraction * total;
// the largest if rounding leaves it short, 0 for none. Face areas as weights make it independent
// of the mesh's resolution.
double area_weighted_percentile(const Eigen::VectorXd& values, const Eigen::VectorXd& weights, double fraction);

// Unit face normals (right-hand rule over the corner order), #F by 3; zero rows if degenerate.
Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Unit area-weighted vertex normals, #V by 3.
Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Signed enclosed volume by the divergence theorem (positive for a closed, outward mesh).
double signed_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Area-weighted centroid of the triangles; zero when the area is zero.
Eigen::Vector3d area_centroid(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Angle defect (discrete Gaussian curvature), #V: 2 pi minus the sum of corner angles [rad],
// meaningful for inner vertices (the same formula on the boundary; 2 pi where no face).
Eigen::VectorXd angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

double bounding_box_diagonal(const Eigen::MatrixXd& V);

// Edge lengths for the unique edges E (#E by 2).
Eigen::VectorXd edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E);

}  // namespace gp
