#pragma once
// Skinning of the generated body: smooth per-vertex bone weights from the body's parts, and
// dual-quaternion blending (Kavan, Collins, Zara, O'Sullivan, "Geometric skinning with approximate
// dual quaternion blending", ACM TOG 2008), which keeps volume at shoulders and elbows where linear
// blend skinning collapses ("candy wrapper").
#include <Eigen/Core>
#include <vector>

#include "avatar/body_shape.h"
#include "avatar/skeleton.h"
#include "spec/option_fields.h"

namespace gp {

struct SkinningOptions {
  double falloff = 0.05;  // width of the transition between parts [m at 1.70 m, scales with height]
  // Jacobi passes of the weights (each mixes half the one-ring average in) at mean edge
  // `reference_edge`, scaled by (reference_edge / mean edge)^2: the same radius in metres.
  int smoothing_iterations = 4;
  double reference_edge = 0.016;  // [m at 1.70 m]
  // Factor on `falloff` between torso and thigh: the hip folds far more than the shoulder
  // (sitting), and a wider transition spreads the crease over more skin.
  double hip_falloff_scale = 2.5;
};

// The options as a report records them (spec/option_fields.h).
struct SkinningOptionFields {
  template <class Fields>
  void operator()(SkinningOptions& o, Fields& f) const {
    f.number("falloff_m_at_1_70", o.falloff, Range::positive());
    f.integer("smoothing_iterations", o.smoothing_iterations, Range::between(0, 1e6));
    f.number("reference_edge_m_at_1_70", o.reference_edge, Range::positive());
    f.number("hip_falloff_scale", o.hip_falloff_scale, Range::positive());
  }
};

// #V by kJointCount weights, rows summing to 1: the parts within `falloff` of a vertex's nearest
// part (signed distance); parts of different limbs share a vertex only on the torso.
Eigen::MatrixXd skinning_weights(const BodyShape& shape, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const SkinningOptions& options = {});

// Posed positions (#V by 3) from rest positions V (#V by 3), weights W (#V by #bones) and per-bone
// rest-to-pose transforms.
Eigen::MatrixXd dual_quaternion_skinning(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                         const std::vector<RigidTransform>& bones);

}  // namespace gp
