#pragma once
// The measurement spec of a generated body (schema "avatar-spec/1"):
//
//   {
//     "schema": "avatar-spec/1",
//     "name": "default",                       (optional, free text)
//     "measurements": {                        (every field optional, metres)
//       "height": 1.70, "neck": 0.36, "chest": 0.92, "under_bust": 0.78,
//       "waist": 0.76, "hip": 0.98, "thigh": 0.56, "belly_depth": 0.0,
//       "shoulder_width": 0.39, "arm_length": 0.57, "upper_arm": 0.29,
//       "wrist": 0.16, "inseam": 0.77,
//       "arm_length_difference": 0.0, "leg_length_difference": 0.0
//     },
//     "poses": [                               (optional extra poses)
//       { "name": "wave", "joints": { "l_shoulder": [0, 0, 120], "l_elbow": [0, 0, 30] } }
//     ]
//   }
//
// Measurements (all metres, as a tailor takes them):
//   height                 floor to top of head, standing.
//   neck                   girth at mid neck.
//   chest                  chest or bust girth at its fullest, under the arms.
//   under_bust             girth just below the bust (rib cage).
//   waist                  natural waist girth (over the belly when belly_depth > 0).
//   hip                    girth at the fullest part of the seat.
//   thigh                  girth of the upper thigh, just below the crotch.
//   belly_depth            extra forward protrusion of the belly at the waist (maternity).
//   shoulder_width         straight distance between the two shoulder points (acromia).
//   arm_length             shoulder point to wrist along the straight arm.
//   upper_arm              girth of the upper arm half-way from shoulder to elbow.
//   wrist                  wrist girth.
//   inseam                 crotch to floor.
//   arm_length_difference  left arm minus right arm length.
//   leg_length_difference  left leg minus right leg length.
// A measurement left out defaults to the reference body below (height 1.70 m)
// scaled by height / 1.70, so that a spec giving only the height is plausible.
//
// Pose joint angles are degrees of a rotation about the joint in the rest
// pose's axes (x to the body's left, y up, z forward), applied about x first,
// then y, then z. Joint names are those of skeleton.h.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "spec/json_file.h"

namespace gp {

struct Measurements {
  double height = 1.70;
  double neck = 0.36;
  double chest = 0.92;
  double under_bust = 0.78;
  double waist = 0.76;
  double hip = 0.98;
  double thigh = 0.56;
  double belly_depth = 0.0;
  double shoulder_width = 0.39;
  double arm_length = 0.57;
  double upper_arm = 0.29;
  double wrist = 0.16;
  double inseam = 0.77;
  double arm_length_difference = 0.0;
  double leg_length_difference = 0.0;
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
