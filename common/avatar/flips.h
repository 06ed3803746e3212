#pragma once
// Edge flips that raise the smallest angle of triangle pairs (the local
// Delaunay criterion on the surface), restricted to nearly flat pairs so the
// shape does not change. Cleans up needle and cap triangles left by
// decimation without moving vertices.
#include <Eigen/Core>

namespace gp {

struct FlipOptions {
  // Largest angle between the normals of the two triangles of a flippable
  // pair, before and after the flip [degrees].
  double max_dihedral = 20.0;
  // Pairs whose smaller angle is below this are flipped if the new pair
  // bends by less than twice max_dihedral [degrees].
  double needle_angle = 5.0;
  int max_passes = 10;
};

// Flips edges of the closed, oriented mesh (V #V by 3, F #F by 3, modified in
// place; orientation kept) while that raises the smaller of the two minimum
// angles. Never creates an edge that exists already or a vertex of valence
// below 3. Deterministic (edges visited in face order). Returns the number of flips.
int flip_for_angles(const Eigen::MatrixXd& V, Eigen::MatrixXi& F, const FlipOptions& options = {});

}  // namespace gp
