#pragma once
// Skinning of the generated body: smooth per-vertex bone weights derived from
// the body's parts, and dual-quaternion linear blending (Kavan, Collins,
// Zara, O'Sullivan, "Geometric skinning with approximate dual quaternion
// blending", ACM TOG 2008), which keeps volume at shoulders and elbows where
// linear blend skinning collapses ("candy wrapper").
#include <Eigen/Core>
#include <vector>

#include "avatar/body_shape.h"
#include "avatar/skeleton.h"

namespace gp {

struct SkinningOptions {
  // Width of the weight transition between neighbouring parts, as a fraction
  // of the body scale (height / 1.70 m) [m at 1.70 m].
  double falloff = 0.05;
  // Jacobi smoothing passes of the weights over the mesh (each mixes half of
  // the one-ring average in) for a mesh of mean edge `reference_edge`; the
  // count scales with (reference_edge / mean edge)^2 so the smoothing radius
  // stays the same in metres at every resolution.
  int smoothing_iterations = 4;
  double reference_edge = 0.016;  // [m at 1.70 m]
  // The hip folds far more than the shoulder in common poses (sitting); a
  // wider transition between pelvis and thigh spreads the crease over more
  // skin (factor on `falloff` for the torso-thigh pair).
  double hip_falloff_scale = 2.5;
};

// #V by kJointCount weights, rows summing to 1. Each vertex is weighted by
// the parts within `falloff` of its nearest part (by signed distance); parts
// of a different limb (left and right thigh, say) never share a vertex
// unless it lies on the torso.
Eigen::MatrixXd skinning_weights(const BodyShape& shape, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const SkinningOptions& options = {});

// Posed positions (#V by 3) from rest positions V (#V by 3), weights W
// (#V by #bones) and per-bone rest-to-pose transforms.
Eigen::MatrixXd dual_quaternion_skinning(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                         const std::vector<RigidTransform>& bones);

}  // namespace gp
