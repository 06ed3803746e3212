#pragma once
// The body as an implicit surface: a smooth union of simple parts, each an
// approximate signed distance (metres, negative inside):
//   torso  a generalized cylinder with super-elliptic cross-sections whose
//          half-width, front and back depth are interpolated (monotone cubic)
//          between rows at anatomical landmark heights (crotch, hip, waist,
//          under-bust, chest, armpit, shoulder, neck base);
//   neck, trapezius (shoulder slope), arms and legs as chains of round cones
//          (spheres joined by tangent cones); head, hands as ellipsoids; feet
//          as flattened round cones.
// Parts are joined by polynomial smooth minimum (Quilez), so junctions at
// armpits, crotch and neck are smooth by construction and the zero level set
// is a closed surface. The rest pose is an A-pose: arms 42 degrees from the
// vertical, legs slightly apart, facing +z, +y up, feet at y = 0.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "avatar/avatar_spec.h"
#include "avatar/skeleton.h"

namespace gp {

// Body parts; each is carried by one bone (the torso by pelvis/spine/chest,
// blended along the height).
enum BodyPart : int {
  kTorso = 0,
  kNeckPart,
  kHeadPart,
  kLTrapezius,
  kRTrapezius,
  kLUpperArm,
  kLForearm,
  kLHand,
  kRUpperArm,
  kRForearm,
  kRHand,
  kLThigh,
  kLShin,
  kLFoot,
  kRThigh,
  kRShin,
  kRFoot,
  kPartCount
};

// Limb chain of a part: 0 torso group (torso, neck, head, trapezius),
// 1 left arm, 2 right arm, 3 left leg, 4 right leg.
int body_part_chain(int part);

// A sphere of a round-cone chain.
struct Ball {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double r = 0.0;
};

// One row of the torso profile.
struct TorsoRow {
  double y = 0.0;           // height [m]
  double half_width = 0.0;  // half-width along x [m]
  double front = 0.0;       // depth in front of the centre line [m]
  double back = 0.0;        // depth behind the centre line [m]
  double center_z = 0.0;    // centre line position along z [m]
};

// A girth landmark: a plane through `center` with normal `normal`, where the
// girth is the convex-hull perimeter of the cross-section loop around `center`.
struct GirthLandmark {
  std::string name;     // "chest", "upper_arm_left", ...
  std::string field;    // measurement it reproduces ("chest", "upper_arm", ...)
  double target = 0.0;  // [m]
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  int bone = 0;  // joint whose bone carries the landmark (for posing)
};

struct BodyShape {
  Measurements m;
  double scale = 1.0;  // height / 1.70, for sizes not given by measurements

  std::vector<TorsoRow> torso_rows;            // ascending y
  double torso_bottom = 0.0, torso_top = 0.0;  // cap heights [m]
  double belly_y = 0.0, belly_sigma = 1.0;     // belly bump centre and width [m]
  double torso_exponent = 2.3;                 // super-ellipse exponent

  std::array<Ball, 2> neck;                      // base, top
  Eigen::Vector3d head_center, head_radii;       // ellipsoid
  std::array<std::array<Ball, 2>, 2> trapezius;  // [side][neck end, shoulder end]
  std::array<std::array<Ball, 5>, 2> arm;        // [side][shoulder, mid upper arm, elbow, forearm, wrist]
  std::array<std::array<Ball, 2>, 2> hand;       // [side][palm, finger tips], flattened
  std::array<Eigen::Vector3d, 2> hand_breadth;   // direction across the palm
  double hand_widening = 2.9;                    // palm breadth / palm thickness
  std::array<std::array<Ball, 4>, 2> leg;        // [side][upper thigh, knee, calf, ankle]
  std::array<Eigen::Vector3d, 2> hip_joint;      // centre of rotation of the hip
  std::array<std::array<Ball, 2>, 2> foot;       // [side][heel, toe]
  double foot_widening = 1.35;                   // lateral stretch of the foot cone

  // Smooth-union widths [m].
  double blend_torso = 0.03, blend_limb = 0.035, blend_leg = 0.03, blend_small = 0.012;

  Skeleton skeleton;
  std::vector<GirthLandmark> landmarks;

  // Derived data, refreshed by update_bounds(): monotone-cubic slopes of the
  // torso rows (d/dy of half_width, front, back, center_z) and part bounds.
  std::vector<Eigen::Vector4d> torso_slopes;
  std::array<Eigen::Vector3d, kPartCount> part_min, part_max;

  // Axis-aligned bounds of the whole body [m] (min, max) with a margin.
  Eigen::Vector3d box_min, box_max;
};

// Builds the rest-pose shape from measurements (initial guess; fit_girths
// then corrects the girths). Side index 0 is the body's left (+x).
BodyShape build_body_shape(const Measurements& m);

// The body's implicit function at p [m]: negative inside.
double body_field(const BodyShape& shape, const Eigen::Vector3d& p);

// Per-part signed distances at p (no blending), kPartCount values.
void body_part_distances(const BodyShape& shape, const Eigen::Vector3d& p, std::array<double, kPartCount>& d);

// Weights of pelvis, spine and chest for a torso point at height y (sum 1).
Eigen::Vector3d torso_bone_weights(const BodyShape& shape, double y);

// Joint whose bone carries `part` (the torso returns kPelvis; see torso_bone_weights).
int body_part_bone(int part);

// Recomputes the derived data (torso slopes, part bounds, box_min/box_max)
// after parameters changed.
void update_bounds(BodyShape& shape);

// Adjusts the parameter behind each girth landmark by fixed-point iteration
// (scale by target / measured, measured on the implicit surface by ray
// casting in the landmark plane) until every girth is within `tolerance` [m]
// or `max_iterations` is reached. `target_scale` (one per landmark, default 1)
// lets a caller aim the implicit surface off target to compensate for the
// polygonization. Returns the largest remaining error [m].
double fit_girths(BodyShape& shape, double tolerance = 2e-4, int max_iterations = 12,
                  const std::vector<double>& target_scale = {});

// Girth of the implicit surface at a landmark: convex-hull perimeter of the
// cross-section points found by casting `rays` rays from the landmark centre.
double field_girth(const BodyShape& shape, const GirthLandmark& landmark, int rays = 180);

// Scales the shape parameter a landmark controls by `factor`.
void scale_landmark_parameter(BodyShape& shape, size_t landmark, double factor);

}  // namespace gp
