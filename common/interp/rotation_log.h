#pragma once
// Rotation log and exp in axis-angle form (omega = angle * unit axis), and logarithm branches
// omega + 2 pi k a consistent over a mesh (Xu et al. 2005, Sec. 4.1; tools/interp-poses/README.md).
#include <vector>

#include <Eigen/Core>

namespace gp {

// Principal logarithm, |omega| in [0, pi]; accurate near 0 and pi (axis from R's symmetric part).
Eigen::Vector3d rotation_log(const Eigen::Matrix3d& R);

// exp([omega]_x) by Rodrigues' formula (series near zero angle).
Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& omega);

// The logarithm omega + 2 pi k a closest to `reference`; for omega ~ 0 the reference's axis is used,
// which keeps a full turn (2 pi) continuous.
Eigen::Vector3d closest_log_branch(const Eigen::Vector3d& omega, const Eigen::Vector3d& reference);

// Consistent logarithms (#F by 3) of per-face rotations R (#F) over the mesh F (#F by 3): each
// component (faces joined by edges or, at a penalty, by vertices) is grown from its valid face of
// smallest angle (lowest id on ties) as a minimum spanning tree (Prim) weighted by the angles
// between neighbouring rotations; a face takes the branch closest to its parent's, an invalid
// (degenerate) face its parent's logarithm. Deterministic.
Eigen::MatrixXd consistent_rotation_logs(const std::vector<Eigen::Matrix3d>& R,
                                         const std::vector<bool>& valid, const Eigen::MatrixXi& F);

}  // namespace gp
