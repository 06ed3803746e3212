#pragma once
// Girths as a tape measure takes them: the perimeter of the convex hull of a
// body's cross-section (the tape bridges concave parts such as the cleft
// between the breasts). The cross-section is cut with a plane and the loop
// around a given centre point is kept, so that a slice through the chest
// ignores the arms.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "mesh/slice_mesh.h"

namespace gp {

// Perimeter of the convex hull of 2-D points (Andrew's monotone chain);
// 0 for fewer than two distinct points.
double convex_hull_perimeter(std::vector<Eigen::Vector2d> points);

// Girth [m] of the mesh at a plane: convex-hull perimeter of the slice loop
// that encloses `point` (in the plane). Returns -1 if no loop encloses it.
double mesh_girth(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal);

// Same, also returning the length of the loop itself (not its hull) [m].
double mesh_girth(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal, double* loop_length);

}  // namespace gp
