#include "avatar/skeleton.h"

#include <tuple>

#include <cmath>

#include "core/error.h"
#include "core/math.h"

namespace gp {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Quaterniond about(const Eigen::Vector3d& axis, double degrees) {
  // As Eigen::AngleAxisd, with the portable sine and cosine (core/math.h).
  const auto [s, c] = gp::math::sincos(0.5 * degrees * kDeg);
  const Eigen::Vector3d v = s * axis.normalized();
  return Eigen::Quaterniond(c, v.x(), v.y(), v.z());
}

Eigen::Vector3d bone_direction(const Skeleton& s, int from, int to) {
  return (s.rest.row(to) - s.rest.row(from)).transpose().normalized();
}

// Builds local rotations from wanted global (rest-to-posed) rotations of some
// bones; bones not listed keep their local rest orientation (identity).
class PoseBuilder {
 public:
  explicit PoseBuilder(const Skeleton& s)
      : s_(s), global_(kJointCount, Eigen::Quaterniond::Identity()), set_(kJointCount, false) {}
  void set_global(int j, const Eigen::Quaterniond& q) {
    global_[j] = q;
    set_[j] = true;
  }
  JointRotations local() const {
    JointRotations out(kJointCount, Eigen::Quaterniond::Identity());
    std::vector<Eigen::Quaterniond> g(kJointCount);
    for (int j = 0; j < kJointCount; ++j) {
      const int p = s_.parents[j];
      const Eigen::Quaterniond gp = p < 0 ? Eigen::Quaterniond::Identity() : g[p];
      if (set_[j]) {
        out[j] = (gp.conjugate() * global_[j]).normalized();
        g[j] = global_[j];
      } else {
        g[j] = gp;
      }
    }
    return out;
  }

 private:
  const Skeleton& s_;
  std::vector<Eigen::Quaterniond> global_;
  std::vector<bool> set_;
};

// Smallest rotation taking the rest direction of bone (from -> to) onto `target`.
Eigen::Quaterniond swing(const Skeleton& s, int from, int to, const Eigen::Vector3d& target) {
  return Eigen::Quaterniond::FromTwoVectors(bone_direction(s, from, to), target.normalized());
}

}  // namespace

const std::vector<std::string>& avatar_joint_names() {
  static const std::vector<std::string> names = {
      "pelvis",  "spine",   "chest",      "neck",       "head",    "l_clavicle", "l_shoulder",
      "l_elbow", "l_wrist", "r_clavicle", "r_shoulder", "r_elbow", "r_wrist",    "l_hip",
      "l_knee",  "l_ankle", "r_hip",      "r_knee",     "r_ankle"};
  return names;
}

const std::vector<int>& avatar_joint_parents() {
  static const std::vector<int> parents = {
      -1,         kPelvis,    kSpine,  kChest,  kNeck, kChest, kLClavicle, kLShoulder, kLElbow, kChest,
      kRClavicle, kRShoulder, kRElbow, kPelvis, kLHip, kLKnee, kPelvis,    kRHip,      kRKnee};
  return parents;
}

int avatar_joint_index(const std::string& name) {
  const auto& n = avatar_joint_names();
  for (size_t i = 0; i < n.size(); ++i)
    if (n[i] == name) return static_cast<int>(i);
  return -1;
}

std::string avatar_joint_list() {
  std::string s;
  for (const std::string& n : avatar_joint_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::vector<RigidTransform> forward_kinematics(const Skeleton& skeleton, const JointRotations& local) {
  std::vector<RigidTransform> M(kJointCount);
  for (int j = 0; j < kJointCount; ++j) {
    const Eigen::Vector3d p = skeleton.rest.row(j).transpose();
    const Eigen::Quaterniond& R = local[j];
    // Rotation about the rest joint position: x -> R x + (p - R p).
    RigidTransform L;
    L.q = R;
    L.t = p - R * p;
    const int parent = skeleton.parents[j];
    if (parent < 0) {
      M[j] = L;
    } else {
      M[j].q = (M[parent].q * L.q).normalized();
      M[j].t = M[parent].q * L.t + M[parent].t;
    }
  }
  return M;
}

Eigen::MatrixXd posed_joints(const Skeleton& skeleton, const std::vector<RigidTransform>& bones) {
  Eigen::MatrixXd P(kJointCount, 3);
  for (int j = 0; j < kJointCount; ++j)
    P.row(j) = bones[j].apply(skeleton.rest.row(j).transpose()).transpose();
  return P;
}

Eigen::Quaterniond rotation_from_degrees(const Eigen::Vector3d& a) {
  return (about(Eigen::Vector3d::UnitZ(), a.z()) * about(Eigen::Vector3d::UnitY(), a.y()) *
          about(Eigen::Vector3d::UnitX(), a.x()))
      .normalized();
}

const std::vector<std::string>& builtin_pose_names() {
  static const std::vector<std::string> names = {"apose",      "tpose",       "armsup", "armsforward",
                                                 "elbowsbent", "stepforward", "seated", "handsonthighs"};
  return names;
}

bool is_builtin_pose(const std::string& name) {
  for (const std::string& n : builtin_pose_names())
    if (n == name) return true;
  return false;
}

JointRotations hands_on_thighs_pose(const Skeleton& s, double elbow_bend_degrees) {
  // Upper arms 30 degrees out from the vertical, the forearms bent inwards
  // from there: the hands rest beside the thighs, as the scanned customer
  // stands (../shared/avatars: the A-pose's left hand 6.5 mm from the thigh).
  PoseBuilder b(s);
  for (const auto& [shoulder, elbow, wrist, side] : {std::tuple{kLShoulder, kLElbow, kLWrist, 1.0},
                                                      std::tuple{kRShoulder, kRElbow, kRWrist, -1.0}}) {
    const double fore = 30.0 - elbow_bend_degrees;  // the forearm's angle out from the vertical
    const Eigen::Vector3d upper(side * gp::math::sin(30.0 * kDeg), -gp::math::cos(30.0 * kDeg), 0.0);
    const Eigen::Vector3d forearm(side * gp::math::sin(fore * kDeg), -gp::math::cos(fore * kDeg), 0.0);
    b.set_global(shoulder, swing(s, shoulder, elbow, upper));
    b.set_global(elbow, swing(s, elbow, wrist, forearm));
  }
  return b.local();
}

JointRotations builtin_pose(const Skeleton& s, const std::string& name) {
  PoseBuilder b(s);
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY();
  // side = +1 for the left (+x) side, -1 for the right.
  struct Arm {
    int clav, shoulder, elbow, wrist;
    double side;
  };
  struct Leg {
    int hip, knee, ankle;
    double side;
  };
  const Arm arms[2] = {{kLClavicle, kLShoulder, kLElbow, kLWrist, 1.0},
                       {kRClavicle, kRShoulder, kRElbow, kRWrist, -1.0}};
  const Leg legs[2] = {{kLHip, kLKnee, kLAnkle, 1.0}, {kRHip, kRKnee, kRAnkle, -1.0}};
  if (name == "apose") {
  } else if (name == "tpose") {
    for (const Arm& a : arms) b.set_global(a.shoulder, swing(s, a.shoulder, a.elbow, a.side * X));
  } else if (name == "armsup") {
    // The shoulder joint alone lifts the arm: rotating the clavicles as well
    // (scapulohumeral rhythm) drags the whole shoulder girdle with skinning
    // and inflates the volume by about 4 %.
    for (const Arm& a : arms) {
      const Eigen::Vector3d up(a.side * gp::math::sin(30.0 * kDeg), gp::math::cos(30.0 * kDeg), 0.0);
      b.set_global(a.shoulder, swing(s, a.shoulder, a.elbow, up));
    }
  } else if (name == "armsforward") {
    for (const Arm& a : arms) {
      b.set_global(a.clav, about(Y, -a.side * 8.0));
      b.set_global(a.shoulder, swing(s, a.shoulder, a.elbow, Eigen::Vector3d(a.side * 0.12, -0.02, 1.0)));
    }
  } else if (name == "elbowsbent") {
    for (const Arm& a : arms)
      b.set_global(a.elbow, swing(s, a.elbow, a.wrist, Eigen::Vector3d(a.side * 0.25, 0.15, 1.0)));
  } else if (name == "stepforward") {
    // Left leg forward with a slightly bent knee, right leg behind; both feet flat.
    b.set_global(kLHip, about(X, -30.0));
    b.set_global(kLKnee, about(X, -12.0));
    b.set_global(kLAnkle, Eigen::Quaterniond::Identity());
    b.set_global(kRHip, about(X, 12.0));
    b.set_global(kRKnee, about(X, 18.0));
    b.set_global(kRAnkle, Eigen::Quaterniond::Identity());
  } else if (name == "seated") {
    // Torso reclined 15 degrees against a backrest, thighs sloping 10 degrees
    // down to the knees, shins vertical, feet flat: 65 degrees of hip flexion,
    // which skinning folds without crushing the groin.
    b.set_global(kPelvis, about(X, -15.0));
    for (const Leg& l : legs) {
      b.set_global(l.hip, about(X, -80.0));
      b.set_global(l.knee, Eigen::Quaterniond::Identity());
      b.set_global(l.ankle, Eigen::Quaterniond::Identity());
    }
  } else if (name == "handsonthighs") {
    return hands_on_thighs_pose(s, kHandsOnThighsBend);
  } else {
    throw SpecError("unknown built-in pose '" + name + "'", "--poses");
  }
  return b.local();
}

}  // namespace gp
