#pragma once
// In-between bodies for a pose set: frame(a, b, t) gives the body at t in
// [0, 1] on the way from pose a to pose b, in memory, for interp-poses and for
// simulate-adapt (which calls it every frame).
//
// Nonlinear method (Xu et al. 2005, Sumner & Popovic 2004; tools/interp-poses/README.md):
//  1. Per triangle, the deformation gradient Q = W_b W_a^-1 from pose a to b,
//     with the scaled normal as third frame column (interp/deformation_gradient.h).
//  2. Polar decomposition Q = R S (interp/polar_decomposition.h).
//  3. Rotation logs omega with branches consistent across the face adjacency
//     (interp/rotation_log.h), so that turns beyond 180 degrees and arms raised
//     from the side to above the head do not flip or take the short way.
//  4. Q(t) = exp(t omega) ((1 - t) I + t S); the target edges of triangle f are
//     Q(t) [e1_a e2_a] = exp(t omega) ((1 - t) E_a + t U_b), U_b = R^T E_b,
//     so the per-frame work is one small rotation per triangle.
//  5. Positions by the Poisson solve on the reference pose's cotangent
//     Laplacian (interp/gradient_poisson.h), factored once per pose set.
//  6. Translation of each connected component: the centroid of its anchor
//     vertices follows (1 - t) c_a + t c_b.
// Steps 1-3 run once per (a, b) pair and are cached; frames at t = 0 and 1
// reproduce poses a and b up to round-off.
//
// Linear method (baseline): (1 - t) V_a + t V_b, which shortens rotating parts.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "interp/gradient_poisson.h"
#include "linalg/cholmod_solver.h"
#include "pose/pose_set.h"
#include "spec/option_fields.h"

namespace gp {

enum class InterpolationMethod { nonlinear, linear };

const char* to_string(InterpolationMethod method);
// "nonlinear" or "linear"; UsageError otherwise.
InterpolationMethod parse_interpolation_method(const std::string& name);

// Which vertices fix the translation (step 6).
struct AnchorOptions {
  // Explicit anchor vertex ids; empty means automatic.
  std::vector<int> vertex_ids;
  // Automatic anchor: this fraction of the vertices, those closest to the
  // reference pose's vertex centroid (the torso of a body), in (0, 1].
  double fraction = 0.2;
};

struct InterpolationOptions {
  InterpolationMethod method = InterpolationMethod::nonlinear;
  AnchorOptions anchor;
  // Factorization of the Poisson system. Simplicial by default: its 3-column back-substitution,
  // which dominates the per-frame path, is faster than the supernodal factor's on a body-sized
  // mesh (tools/interp-poses/README.md, "Speed and accuracy").
  CholmodOptions solver = {CholmodOptions::Method::simplicial};
};

// The options as a report records them (spec/option_fields.h); explicit
// anchor ids come from the motion spec, which the report carries whole.
struct InterpolationOptionFields {
  template <class Fields>
  void operator()(InterpolationOptions& o, Fields& f) const {
    f.choice("method", o.method,
             ChoiceNames<InterpolationMethod>{{InterpolationMethod::nonlinear, "nonlinear"},
                                              {InterpolationMethod::linear, "linear"}});
    f.number("anchor_fraction", o.anchor.fraction, Range::between(0.0, 1.0));
    f.choice("solver", o.solver.method,
             ChoiceNames<CholmodOptions::Method>{{CholmodOptions::Method::supernodal, "supernodal"},
                                                 {CholmodOptions::Method::simplicial, "simplicial"}});
  }
};

// What was computed for one pose pair.
struct TransitionInfo {
  double max_rotation_deg = 0.0;      // largest |omega| over the faces
  int faces_off_principal_branch = 0; // faces whose log was moved off [0, 180] degrees
  int degenerate_faces = 0;           // faces degenerate in a or b (rotation from a neighbour)
  double prepare_seconds = 0.0;       // wall-clock time of steps 1-3
};

class PoseInterpolator {
 public:
  // Keeps a copy of the poses. Throws GeometryError for an empty set, poses
  // with differing vertex counts, face indices out of range or non-finite
  // coordinates (naming the pose and vertex), a degenerate triangle in the
  // reference pose (nonlinear method); SpecError for anchor ids out of range or
  // a fraction outside (0, 1]; NumericalError if the factorization fails.
  explicit PoseInterpolator(const PoseSet& poses, const InterpolationOptions& options = {});

  // Precomputes steps 1-3 for the pair (a, b); frame() calls it on demand.
  void prepare(int a, int b);

  // The body at t in [0, 1] between poses a and b: V_out becomes #V by 3.
  // UsageError for pose indices out of range or t outside [0, 1] or NaN.
  void frame(int a, int b, double t, Eigen::MatrixXd& V_out);
  Eigen::MatrixXd frame(int a, int b, double t);

  InterpolationMethod method() const { return options_.method; }
  const InterpolationOptions& options() const { return options_; }
  int pose_count() const { return static_cast<int>(V_.size()); }
  int vertex_count() const { return static_cast<int>(V_.empty() ? 0 : V_[0].rows()); }
  const Eigen::MatrixXi& faces() const { return F_; }
  const std::vector<std::string>& pose_names() const { return names_; }
  const Eigen::MatrixXd& pose(int i) const { return V_.at(static_cast<size_t>(i)); }
  // Anchor vertex ids actually used (sorted ascending).
  const std::vector<int>& anchor_vertex_ids() const { return anchor_ids_; }
  // Reference pose whose Laplacian is factored.
  int reference_pose() const { return reference_; }
  // Seconds spent building and factoring the Poisson system (0 for linear).
  double factorization_seconds() const;
  const TransitionInfo& transition_info(int a, int b);

 private:
  struct Transition {
    Eigen::MatrixXd omega;  // #F by 3 consistent rotation logs
    FaceEdges E_a;          // edges in pose a
    FaceEdges U_b;          // edges of pose b rotated back: R^T E_b = S E_a
    TransitionInfo info;
  };
  const Transition& transition(int a, int b);
  void check_frame_args(int a, int b, double t) const;

  InterpolationOptions options_;
  std::vector<std::string> names_;
  std::vector<Eigen::MatrixXd> V_;
  Eigen::MatrixXi F_;
  int reference_ = 0;
  std::vector<int> anchor_ids_;
  std::vector<std::vector<int>> component_anchor_ids_;  // per Poisson component
  std::unique_ptr<GradientPoissonSolver> poisson_;
  std::map<std::pair<int, int>, Transition> transitions_;
  FaceEdges target_;  // per-frame buffer
};

}  // namespace gp
