#pragma once
// The generated body's skeleton and its poses. Joints sit at anatomical
// centres of rotation; each joint's bone carries the body parts that hang
// below it (l_shoulder moves the upper arm, l_elbow the forearm, ...).
// A pose is one rotation per joint, about the joint's rest position and in
// the rest pose's axes (x to the body's left, y up, z forward); rotations
// compose from the root (pelvis) outwards.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace gp {

// Joint ids; the order lists every parent before its children.
enum AvatarJoint : int {
  kPelvis = 0,
  kSpine,
  kChest,
  kNeck,
  kHead,
  kLClavicle,
  kLShoulder,
  kLElbow,
  kLWrist,
  kRClavicle,
  kRShoulder,
  kRElbow,
  kRWrist,
  kLHip,
  kLKnee,
  kLAnkle,
  kRHip,
  kRKnee,
  kRAnkle,
  kJointCount
};

// "pelvis", "spine", ..., "r_ankle" in AvatarJoint order.
const std::vector<std::string>& avatar_joint_names();
// Parent joint id per joint (-1 for the pelvis).
const std::vector<int>& avatar_joint_parents();
// Joint id for a name, -1 if unknown.
int avatar_joint_index(const std::string& name);
// "pelvis, spine, ..." for messages.
std::string avatar_joint_list();

struct Skeleton {
  std::vector<std::string> names;  // kJointCount names
  std::vector<int> parents;        // kJointCount parents, -1 for the root
  Eigen::MatrixXd rest;            // kJointCount by 3 joint positions in the rest pose [m]
};

// x -> q x + t.
struct RigidTransform {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return q * x + t; }
};

// Local joint rotations of one pose (kJointCount, identity = rest).
using JointRotations = std::vector<Eigen::Quaterniond>;

// Rest-to-posed transform of every joint's bone: M_j = M_parent(j) o R_j about
// rest(j). Also returns nothing else; posed joint positions are M_j(rest(j)).
std::vector<RigidTransform> forward_kinematics(const Skeleton& skeleton, const JointRotations& local);

// Posed joint positions, kJointCount by 3.
Eigen::MatrixXd posed_joints(const Skeleton& skeleton, const std::vector<RigidTransform>& bones);

// Rotation from joint angles in degrees: about x, then y, then z (R = Rz Ry Rx).
Eigen::Quaterniond rotation_from_degrees(const Eigen::Vector3d& angles);

// The built-in poses, in output order: apose (the rest pose), tpose, armsup,
// armsforward, elbowsbent, stepforward (left leg forward), seated, handsonthighs
// (the hands resting beside the thighs).
const std::vector<std::string>& builtin_pose_names();
bool is_builtin_pose(const std::string& name);

// handsonthighs: the upper arms 30 degrees out from the vertical and the
// elbows bent inwards by `elbow_bend_degrees`. make_avatar bends them
// kHandsOnThighsBend (the wrist 5.7 mm from the hip on the default body, as
// the scanned customer's hand rests 6.5 mm from the thigh; 0.5 degree more
// makes it 2.3 mm), less on a body whose hips that bend would pass the hands
// into (MakeAvatar: the least bend back in steps of 2.5 degrees that leaves
// the pose free of self-intersection).
constexpr double kHandsOnThighsBend = 45.0;
JointRotations hands_on_thighs_pose(const Skeleton& skeleton, double elbow_bend_degrees);

// Local rotations of a built-in pose for this skeleton (the arm and leg rest
// directions are read from the joints). Throws SpecError for an unknown name.
JointRotations builtin_pose(const Skeleton& skeleton, const std::string& name);

}  // namespace gp
