#pragma once
// Where a plane cuts a triangle mesh: the cross-section as polylines.
#include <vector>

#include <Eigen/Core>

namespace gp {

// Polylines where the plane through `point` with normal `normal` cuts the
// triangle mesh (V #V by 3, F #F by 3), each ordered consistently with the
// faces' orientation. A vertex exactly on the plane counts as lying on its
// positive side, so every polyline is a closed loop (first point not
// repeated) on a closed mesh; on an open mesh a cut that runs into a hole is an
// open polyline from one border edge to another, listed before the loops.
// `closed`, if given, receives per polyline whether it is a closed loop.
std::vector<std::vector<Eigen::Vector3d>> slice_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                                     const Eigen::Vector3d& point,
                                                     const Eigen::Vector3d& normal,
                                                     std::vector<bool>* closed = nullptr);

// Length [units of V] of a polyline from slice_mesh, closed or open.
double polyline_length(const std::vector<Eigen::Vector3d>& polyline, bool closed);

}  // namespace gp
