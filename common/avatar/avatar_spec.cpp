#include "avatar/avatar_spec.h"

#include <cmath>
#include <sstream>

#include "avatar/skeleton.h"
#include "core/error.h"
#include "pose/pose_set.h"
#include "spec/spec_object.h"

namespace gp {
namespace {

std::string metres(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v << " m";
  return s.str();
}

// A girth or length checked against fractions of the height (NaN fails too): bounds taken
// wide around anthropometric survey ranges (adults 1.2 to 2.1 m) so that real
// customers pass and typing errors (cm for m, a swapped field) do not.
void check_relative(double value, const char* field, double lo, double hi, double height,
                    const std::string& where) {
  if (!(value >= lo * height && value <= hi * height)) {
    std::ostringstream s;
    s << field << " " << metres(value) << " is implausible for a height of " << metres(height)
      << " (expected " << metres(lo * height) << " to " << metres(hi * height) << ")";
    throw SpecError(s.str(), where + "/" + field);
  }
}

}  // namespace

Measurements scaled_default_measurements(double height) {
  Measurements m;
  const double s = height / m.height;
  m.height = height;
  m.neck *= s;
  m.chest *= s;
  m.under_bust *= s;
  m.waist *= s;
  m.hip *= s;
  m.thigh *= s;
  m.shoulder_width *= s;
  m.arm_length *= s;
  m.upper_arm *= s;
  m.wrist *= s;
  m.inseam *= s;
  return m;
}

AvatarSpec default_avatar_spec() { return AvatarSpec{}; }

void validate_measurements(const Measurements& m, const std::string& where) {
  const double H = m.height;
  if (!(H >= 0.9 && H <= 2.5))
    throw SpecError("height " + metres(H) + " outside 0.9 m to 2.5 m", where + "/height");
  check_relative(m.neck, "neck", 0.13, 0.32, H, where);
  check_relative(m.chest, "chest", 0.35, 1.0, H, where);
  check_relative(m.under_bust, "under_bust", 0.32, 0.95, H, where);
  check_relative(m.waist, "waist", 0.3, 0.9, H, where);
  check_relative(m.hip, "hip", 0.4, 1.0, H, where);
  check_relative(m.thigh, "thigh", 0.2, 0.55, H, where);
  check_relative(m.belly_depth, "belly_depth", 0.0, 0.12, H, where);
  check_relative(m.shoulder_width, "shoulder_width", 0.18, 0.3, H, where);
  check_relative(m.arm_length, "arm_length", 0.26, 0.42, H, where);
  check_relative(m.upper_arm, "upper_arm", 0.1, 0.3, H, where);
  check_relative(m.wrist, "wrist", 0.07, 0.14, H, where);
  check_relative(m.inseam, "inseam", 0.35, 0.55, H, where);
  if (m.under_bust > m.chest)
    throw SpecError("under_bust " + metres(m.under_bust) + " is larger than chest " + metres(m.chest),
                    where + "/under_bust");
  if (m.wrist > 0.8 * m.upper_arm)
    throw SpecError(
        "wrist " + metres(m.wrist) + " must be less than 0.8 x upper_arm (" + metres(0.8 * m.upper_arm) + ")",
        where + "/wrist");
  // Both thighs sit side by side under the seat.
  if (m.thigh > 0.7 * m.hip)
    throw SpecError("thigh " + metres(m.thigh) + " must be less than 0.7 x hip (" + metres(0.7 * m.hip) + ")",
                    where + "/thigh");
  if (m.neck > 0.6 * m.chest)
    throw SpecError("neck " + metres(m.neck) + " must be less than 0.6 x chest", where + "/neck");
  if (!(std::abs(m.arm_length_difference) <= 0.1 * m.arm_length))
    throw SpecError(
        "arm_length_difference " + metres(m.arm_length_difference) + " exceeds 10 % of arm_length",
        where + "/arm_length_difference");
  if (!(std::abs(m.leg_length_difference) <= 0.06 * m.inseam))
    throw SpecError("leg_length_difference " + metres(m.leg_length_difference) + " exceeds 6 % of inseam",
                    where + "/leg_length_difference");
}

AvatarSpec parse_avatar_spec(const Json& j, const std::string& file) {
  check_schema(j, "avatar-spec", {1}, file);
  SpecObject root(j, file);
  root.allow("schema");
  AvatarSpec spec;
  spec.name = root.string("name", spec.name);
  if (auto mo = root.optional_object("measurements")) {
    const SpecObject& o = *mo;
    const double H = o.number("height", 1.70, Range::between(0.9, 2.5));
    Measurements m = scaled_default_measurements(H);
    const Range girth = Range::positive();
    m.neck = o.number("neck", m.neck, girth);
    m.chest = o.number("chest", m.chest, girth);
    m.under_bust = o.number("under_bust", m.under_bust, girth);
    m.waist = o.number("waist", m.waist, girth);
    m.hip = o.number("hip", m.hip, girth);
    m.thigh = o.number("thigh", m.thigh, girth);
    m.belly_depth = o.number("belly_depth", m.belly_depth, Range::non_negative());
    m.shoulder_width = o.number("shoulder_width", m.shoulder_width, girth);
    m.arm_length = o.number("arm_length", m.arm_length, girth);
    m.upper_arm = o.number("upper_arm", m.upper_arm, girth);
    m.wrist = o.number("wrist", m.wrist, girth);
    m.inseam = o.number("inseam", m.inseam, girth);
    m.arm_length_difference = o.number("arm_length_difference", 0.0);
    m.leg_length_difference = o.number("leg_length_difference", 0.0);
    o.finish();
    validate_measurements(m, o.where());
    spec.measurements = m;
  }
  if (auto pa = root.optional_array("poses")) {
    for (size_t i = 0; i < pa->size(); ++i) {
      const SpecObject po = pa->object(i);
      JointAnglePose pose;
      pose.name = po.required_string("name");
      if (!is_valid_pose_name(pose.name))
        throw SpecError("pose name must be 1 to 64 letters, digits, '-' or '_'", po.where("name"));
      const SpecObject jo = po.object("joints");
      for (auto it = jo.json().begin(); it != jo.json().end(); ++it) {
        if (avatar_joint_index(it.key()) < 0)
          throw SpecError("unknown joint '" + it.key() + "' (known: " + avatar_joint_list() + ")",
                          jo.where(it.key()));
        const std::vector<double> a = jo.numbers(it.key(), 3, Range::between(-360.0, 360.0));
        pose.joints.emplace_back(it.key(), Eigen::Vector3d(a[0], a[1], a[2]));
      }
      jo.finish();
      po.finish();
      spec.poses.push_back(pose);
    }
  }
  root.finish();
  return spec;
}

AvatarSpec read_avatar_spec(const std::filesystem::path& path) {
  return parse_avatar_spec(read_json_file(path), path.string());
}

OrderedJson to_json(const Measurements& m) {
  OrderedJson j;
  j["height"] = m.height;
  j["neck"] = m.neck;
  j["chest"] = m.chest;
  j["under_bust"] = m.under_bust;
  j["waist"] = m.waist;
  j["hip"] = m.hip;
  j["thigh"] = m.thigh;
  j["belly_depth"] = m.belly_depth;
  j["shoulder_width"] = m.shoulder_width;
  j["arm_length"] = m.arm_length;
  j["upper_arm"] = m.upper_arm;
  j["wrist"] = m.wrist;
  j["inseam"] = m.inseam;
  j["arm_length_difference"] = m.arm_length_difference;
  j["leg_length_difference"] = m.leg_length_difference;
  return j;
}

}  // namespace gp
