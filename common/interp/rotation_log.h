#pragma once
// Rotation logarithm and exponential in axis-angle form (omega = angle * unit
// axis, a 3-vector), and the choice of logarithm branch that keeps neighbouring
// triangles consistent.
//
// A rotation R has infinitely many logarithms omega + 2 pi k a (a = unit axis,
// k integer). The principal one has angle in [0, pi]; interpolating exp(t omega)
// with it takes the short way round, which is wrong for a body part turned by
// more than 180 degrees (a twisted chain) and unstable near 180 degrees, where
// neighbouring triangles can pick opposite axes and tear apart. Following
// Poisson shape interpolation (Xu et al. 2005, Sec. 4.1), the branch is chosen
// per triangle to be closest to its neighbour's, propagated over the face
// adjacency from the least-rotated triangle of each component.
#include <vector>

#include <Eigen/Core>

namespace gp {

// Principal logarithm of a rotation matrix: |omega| in [0, pi]. Accurate near
// 0 and near pi (where the axis comes from the symmetric part of R).
Eigen::Vector3d rotation_log(const Eigen::Matrix3d& R);

// exp([omega]_x) by Rodrigues' formula (series near zero angle).
Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& omega);

// Among the logarithms omega + 2 pi k a of the same rotation, the one closest
// to `reference`. For omega ~ 0 (identity) the axis is free, so the reference's
// axis is used: that keeps a full turn (2 pi) continuous.
Eigen::Vector3d closest_log_branch(const Eigen::Vector3d& omega, const Eigen::Vector3d& reference);

// Consistent logarithms of per-face rotations R (#F entries) over the triangle
// mesh F (#F by 3): #F by 3 axis-angle vectors. Each connected component
// (faces joined by edges or, at a penalty, by single vertices) is seeded at its
// valid face with the smallest rotation angle (lowest id on ties) and grown as
// a minimum spanning tree (Prim) whose weights are the angles between
// neighbouring rotations; each face takes the branch closest to its tree
// parent's. Faces with valid[f] false (degenerate) take their parent's
// logarithm unchanged. Deterministic.
Eigen::MatrixXd consistent_rotation_logs(const std::vector<Eigen::Matrix3d>& R,
                                         const std::vector<bool>& valid, const Eigen::MatrixXi& F);

}  // namespace gp
