#pragma once
// The measurement spec of a generated body (schema "avatar-spec/1"): optional measurements in
// metres, as a tailor takes them, and optional extra poses as joint angles (the format and an
// example: tools/make-avatar/README.md). A measurement left out defaults to the reference body
// (1.70 m) scaled by height / 1.70, so that a spec giving only the height is plausible.
//
// Pose joint angles are degrees of a rotation about the joint in the rest pose's axes (x to the
// body's left, y up, z forward), applied about x first, then y, then z; joint names as skeleton.h.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "spec/json_file.h"

namespace gp {

struct Measurements {  // metres
  double height = 1.70;                 // floor to top of head, standing
  double neck = 0.36;                   // girth at mid neck
  double chest = 0.92;                  // chest or bust girth at its fullest, under the arms
  double under_bust = 0.78;             // girth just below the bust (rib cage)
  double waist = 0.76;                  // natural waist girth (over the belly when belly_depth > 0)
  double hip = 0.98;                    // girth at the fullest part of the seat
  double thigh = 0.56;                  // girth of the upper thigh, just below the crotch
  double belly_depth = 0.0;             // extra forward protrusion of the belly at the waist (maternity)
  double shoulder_width = 0.39;         // straight distance between the shoulder points (acromia)
  double arm_length = 0.57;             // shoulder point to wrist along the straight arm
  double upper_arm = 0.29;              // girth of the upper arm half-way from shoulder to elbow
  double wrist = 0.16;                  // wrist girth
  double inseam = 0.77;                 // crotch to floor
  double arm_length_difference = 0.0;   // left arm minus right arm length
  double leg_length_difference = 0.0;   // left leg minus right leg length
};

// A pose given as joint angles: joint name -> (rx, ry, rz) in degrees.
struct JointAnglePose {
  std::string name;
  std::vector<std::pair<std::string, Eigen::Vector3d>> joints;
};

struct AvatarSpec {
  std::string name = "default";
  Measurements measurements;
  std::vector<JointAnglePose> poses;  // extra poses beyond the built-in ones
};

// The reference body: a 1.70 m adult with the defaults above.
AvatarSpec default_avatar_spec();

// Measurements of the reference body scaled to `height` (lengths and girths
// by height / 1.70; belly depth and left/right differences stay zero).
Measurements scaled_default_measurements(double height);

// Reads and validates a spec file. InputError if it cannot be read or parsed,
// SpecError naming the JSON pointer of a wrong, unknown or implausible field.
AvatarSpec read_avatar_spec(const std::filesystem::path& path);

// Same from parsed JSON; `file` names the source in errors.
AvatarSpec parse_avatar_spec(const Json& j, const std::string& file);

// Checks the plausibility of a set of measurements (girths against the height
// and each other); throws SpecError naming "<where>/<field>".
void validate_measurements(const Measurements& m, const std::string& where);

// The effective measurements as JSON (every field, defaults included).
OrderedJson to_json(const Measurements& m);

}  // namespace gp
