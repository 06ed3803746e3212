#pragma once
// Generalized winding number (Jacobson, Kavan & Sorkine-Hornung 2013, "Robust inside-outside
// segmentation using generalized winding numbers"): the triangles' signed solid angles seen from
// the point (Van Oosterom & Strackee 1983) over 4 pi. 1 inside and 0 outside a closed, outward
// mesh; for an open one (a garment) smooth, near 1 in the space it wraps and near 0 away from it.
#include <Eigen/Core>

namespace gp {

// V #V by 3, F #F by 3; a point on the surface gets a one-sided limit or the average (rounding).
double winding_number(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& p);

}  // namespace gp
