#pragma once
// Generalized winding number of a triangle mesh at a point (Jacobson, Kavan &
// Sorkine-Hornung 2013, "Robust inside-outside segmentation using generalized
// winding numbers"): the sum of its triangles' signed solid angles seen from
// the point (Van Oosterom & Strackee 1983) over 4 pi. 1 inside and 0 outside
// a closed, outward-oriented mesh; for an open one (a garment) it varies
// smoothly, near 1 in the space it wraps and near 0 away from it.
#include <Eigen/Core>

namespace gp {

// V #V by 3, F #F by 3, p a point; a point on the surface gets its one-sided
// limit or the average, whichever rounding gives.
double winding_number(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& p);

}  // namespace gp
