#pragma once
// A generated body with its arms hanging beside the hips (a custom pose
// "armsdown": from the A-pose the shoulders turned 22 degrees down and the
// elbows 15 degrees in, the hands at mid-thigh a few centimetres from the
// legs; registered against it, armsup stretches no edge beyond 8 times and
// the pose has no self-intersection) and a skirt designed on it: a
// waistband from the under-bust to the waist, whose waist loop is extended
// into a cone that passes through the middle of both hands and, at the back,
// through the seat. For the tests of extend-boundary's body clearance and of
// contact through a motion (arms up and back). Header only: the tests that
// use it link the avatar and garment modules.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "avatar/make_avatar.h"
#include "spec/json_file.h"
#include "testing/test_meshes.h"

namespace gp::testing {

struct SkirtScene {
  AvatarSpec spec;             // the default body plus the pose "armsdown"
  AvatarOptions options;       // poses apose, armsdown, armsup
  AvatarResult avatar;
  int design_pose = 1;         // index of "armsdown" in avatar.poses
  Json top_spec;               // garment-spec/1: the waistband, designed on "armsdown"
  Json extend_spec;            // extend-spec/1: its waist loop through the hands
  std::vector<Eigen::Vector3d> hands;  // centres of the hands in the design pose [m]
};

inline SkirtScene make_skirt_scene() {
  SkirtScene s;
  s.spec = default_avatar_spec();
  s.spec.poses.push_back({"armsdown",
                          {{"l_shoulder", Eigen::Vector3d(0, 0, -22)},
                           {"r_shoulder", Eigen::Vector3d(0, 0, 22)},
                           {"l_elbow", Eigen::Vector3d(0, 0, -15)},
                           {"r_elbow", Eigen::Vector3d(0, 0, 15)}}});
  s.options.poses = {"apose", "armsdown", "armsup"};
  s.options.check_self_intersection = false;  // the hands come close to the hips
  s.avatar = make_avatar(s.spec, s.options);
  const Eigen::MatrixXd& rest = s.avatar.poses.V[0];
  const Eigen::MatrixXd& V = s.avatar.poses.V[static_cast<size_t>(s.design_pose)];
  auto girth = [&](const std::string& name) -> const GirthResult& {
    for (const GirthResult& g : s.avatar.girths)
      if (g.name == name) return g;
    return s.avatar.girths.front();
  };
  // Loops from rings of the rest pose (vertex ids hold in every pose).
  auto ring = [&](const std::string& name) {
    const GirthResult& g = girth(name);
    return Json(ring_vertex_ids(rest, g.center, g.normal, 1.5 * g.target / (2 * M_PI)));
  };
  s.top_spec = {{"schema", "garment-spec/1"},
                {"name", "skirt"},
                {"design_pose", "armsdown"},
                {"loops", Json::array({{{"name", "top"}, {"pinned", true}, {"points", ring("under_bust")}},
                                       {{"name", "waist"}, {"points", ring("waist")}}})},
                {"resolution", {{"edge_length", 0.025}}},
                {"offset", 0.008}};
  // Region: the front-most vertex half-way between the loops.
  const double band_y = 0.5 * (girth("waist").center.y() + girth("under_bust").center.y());
  int front = 0;
  for (int v = 0; v < rest.rows(); ++v) {
    if (std::abs(rest(v, 1) - band_y) < 0.02 && std::abs(rest(v, 0)) < 0.05 && rest(v, 2) > rest(front, 2)) front = v;
  }
  s.top_spec["region"] = front;
  // Hands: half-way between the wrist and the lowest point within 25 cm of it.
  const Eigen::Vector3d waist = girth("waist").center;
  for (const char* side : {"wrist_left", "wrist_right"}) {
    int wrist = 0;
    for (int v = 0; v < rest.rows(); ++v) {
      if ((rest.row(v).transpose() - girth(side).center).norm() <
          (rest.row(wrist).transpose() - girth(side).center).norm()) {
        wrist = v;
      }
    }
    int tip = wrist;
    for (int v = 0; v < V.rows(); ++v) {
      if ((V.row(v) - V.row(wrist)).norm() < 0.25 && V(v, 1) < V(tip, 1)) tip = v;
    }
    s.hands.push_back(0.5 * (V.row(wrist) + V.row(tip)).transpose());
  }
  // The cone: from the waist loop (radius about waist / 2 pi) to a hem 6 cm
  // below the hands, scaled so that it passes through the hands' centres.
  const Eigen::Vector3d& hand = s.hands.front();
  const double radius = girth("waist").target / (2 * M_PI);
  const double reach = std::hypot(hand.x() - waist.x(), hand.z() - waist.z());
  const double distance = waist.y() - (hand.y() - 0.06);
  const double scale = 1.0 + (reach / radius - 1.0) * distance / (waist.y() - hand.y());
  s.extend_spec = {{"schema", "extend-spec/1"}, {"loop", "waist"}, {"target", {{"distance", distance}}}, {"scale", scale}};
  return s;
}

}  // namespace gp::testing
