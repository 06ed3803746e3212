#pragma once
// Checks the generated body must pass: a closed, oriented 2-manifold of one
// genus-0 component, and no self-intersection in the rest pose.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace gp {

// Throws GeometryError naming `what` unless F (#F by 3) has no boundary edge,
// every edge in exactly two faces (consistently oriented), a single
// component and Euler characteristic 2.
void check_closed_genus0(const Eigen::MatrixXi& F, const std::string& what);

// True if two non-adjacent triangles intersect (CGAL's
// Polygon_mesh_processing::does_self_intersect, exact predicates).
bool has_self_intersection(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Ids of all triangles that intersect a non-adjacent triangle (ascending).
std::vector<int> self_intersecting_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace gp
