#pragma once
// Edge flips that raise the smallest angle of nearly flat triangle pairs (the local Delaunay
// criterion on the surface, the shape unchanged): clean up decimation's needles and caps.
#include <Eigen/Core>

namespace gp {

struct FlipOptions {
  double max_dihedral = 20.0;  // [deg] largest angle between a pair's normals, before and after
  // [deg] pairs whose smaller angle is below this may bend by up to twice max_dihedral.
  double needle_angle = 5.0;
  int max_passes = 10;
};

// Flips edges of the closed, oriented mesh (V #V by 3, F #F by 3, modified in place; orientation
// kept) while that raises the smaller of the two minimum angles. Never creates an existing edge or a
// vertex of valence below 3. Deterministic (edges in face order). Returns the number of flips.
int flip_for_angles(const Eigen::MatrixXd& V, Eigen::MatrixXi& F, const FlipOptions& options = {});

}  // namespace gp
