// The up axis of generated bodies in every pose the project makes, turned to
// each of the six axis directions and mirrored, whole and without feet or
// hands (open stumps, which have no soles, and capped ones): each must be
// found, or refused as ambiguous; none may come out wrong.
#include <catch2/catch.hpp>

#include <array>
#include <cstdlib>
#include <map>
#include <sstream>

#include "mesh/topology.h"
#include "registration/units.h"
#include "testing/test_meshes.h"

#include "avatar/avatar_spec.h"
#include "avatar/make_avatar.h"
#include "testing/command.h"

namespace {

// Proper rotation taking +y to `up`; `mirror` first reflects x (and the faces
// are flipped with it, as a mirrored scan keeps its outward orientation).
Eigen::Matrix3d turn(const gp::UpAxis& up) {
  Eigen::Matrix3d R;
  if (up.axis == 1) R = Eigen::Vector3d(up.sign, up.sign, 1).asDiagonal();
  else if (up.axis == 0) R << 0, up.sign, 0, -up.sign, 0, 0, 0, 0, 1;
  else R << 1, 0, 0, 0, 0, -up.sign, 0, up.sign, 0;
  return R;
}

gp::Mesh oriented(const gp::Mesh& body, const gp::UpAxis& up, bool mirror) {
  gp::Mesh m = body;
  Eigen::Matrix3d R = turn(up);
  if (mirror) {
    R = R * Eigen::Vector3d(-1, 1, 1).asDiagonal();
    m.F.col(1).swap(m.F.col(2));
  }
  m.V = body.V * R.transpose();
  return m;
}

const std::array<gp::UpAxis, 6> kDirections = {gp::UpAxis{0, +1}, gp::UpAxis{0, -1}, gp::UpAxis{1, +1},
                                               gp::UpAxis{1, -1}, gp::UpAxis{2, +1}, gp::UpAxis{2, -1}};

// A stand-in body: an ellipsoid with a flat base like the soles of feet.
gp::Mesh flat_based_ellipsoid() {
  gp::Mesh m = gp::testing::make_icosphere(3, 1.0);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    m.V.row(i) = Eigen::RowVector3d(0.25 * m.V(i, 0), 0.85 * std::max(m.V(i, 1), -0.9), 0.15 * m.V(i, 2));
  return m;
}

}  // namespace

TEST_CASE("the soles alone give the sign; an ellipsoid without them is ambiguous", "[registration][up]") {
  const gp::Mesh body = flat_based_ellipsoid();
  for (const gp::UpAxis& up : kDirections)
    for (bool mirror : {false, true}) {
      const gp::Mesh m = oriented(body, up, mirror);
      const gp::UpAxisDetection d = gp::detect_up_axis(m.V, m.F);
      INFO(up.name() << (mirror ? " mirrored: " : ": ") << d.reason);
      CHECK_FALSE(d.ambiguous);
      CHECK(d.up.name() == up.name());
      REQUIRE(d.cues.size() == 2);
      CHECK(d.cues[0].name == "soles");
      CHECK(d.cues[0].vote == up.sign);
      CHECK(d.cues[1].vote == 0);  // one cross-section at both ends
    }
  // A plain ellipsoid: no end is flat, both have one cross-section.
  gp::Mesh egg = gp::testing::make_icosphere(3, 1.0);
  egg.V = egg.V * Eigen::Vector3d(0.25, 0.85, 0.15).asDiagonal();
  const gp::UpAxisDetection d = gp::detect_up_axis(egg.V, egg.F);
  INFO(d.reason);
  CHECK(d.ambiguous);
  CHECK(d.up.axis == 1);
  CHECK_THAT(d.reason, Catch::Contains("no cue tells which end is up"));
  // A ball: no axis is longer than another.
  const gp::Mesh ball = gp::testing::make_icosphere(3, 1.0);
  const gp::UpAxisDetection b = gp::detect_up_axis(ball.V, ball.F);
  CHECK(b.ambiguous);
  CHECK(b.spread_ratio > gp::kUpAxisSpreadMargin);
  CHECK_THAT(b.reason, Catch::Contains("too close to tell"));
}

TEST_CASE("two legs against one head give the sign where there are no soles", "[registration][up]") {
  // Two open tubes (legs) joined to one wider tube (torso) capped by a
  // smaller one (head) would need a builder; a coarse stand-in does: three
  // separate closed capsules, two thin low ones and one high one.
  gp::Mesh legs_and_head;
  auto add = [&](const gp::Mesh& part, const Eigen::RowVector3d& scale, const Eigen::RowVector3d& at) {
    const Eigen::Index v0 = legs_and_head.V.rows(), f0 = legs_and_head.F.rows();
    legs_and_head.V.conservativeResize(v0 + part.V.rows(), 3);
    legs_and_head.F.conservativeResize(f0 + part.F.rows(), 3);
    for (Eigen::Index i = 0; i < part.V.rows(); ++i)
      legs_and_head.V.row(v0 + i) = part.V.row(i).cwiseProduct(scale) + at;
    legs_and_head.F.bottomRows(part.F.rows()) = part.F.array() + static_cast<int>(v0);
  };
  const gp::Mesh sphere = gp::testing::make_icosphere(3, 1.0);
  add(sphere, {0.07, 0.45, 0.07}, {-0.1, 0.45, 0});   // left leg, 0-0.9
  add(sphere, {0.07, 0.45, 0.07}, {0.1, 0.45, 0});    // right leg
  add(sphere, {0.2, 0.45, 0.12}, {0, 1.15, 0});       // torso and head, 0.7-1.6 (one section)
  for (const gp::UpAxis& up : kDirections) {
    const gp::Mesh m = oriented(legs_and_head, up, false);
    const gp::UpAxisDetection d = gp::detect_up_axis(m.V, m.F);
    INFO(up.name() << ": " << d.reason);
    CHECK_FALSE(d.ambiguous);
    CHECK(d.up.name() == up.name());
    CHECK(d.cues[0].vote == 0);
    CHECK(d.cues[1].vote == up.sign);
  }
}

namespace {

// The faces of `m` that touch no vertex in `drop`, compacted; the stumps left
// open, or capped with a fan around each hole's centroid.
gp::Mesh without(const gp::Mesh& m, const std::vector<bool>& drop, bool cap) {
  std::vector<int> keep_faces;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    if (!drop[m.F(f, 0)] && !drop[m.F(f, 1)] && !drop[m.F(f, 2)]) keep_faces.push_back(static_cast<int>(f));
  std::vector<int> new_id(static_cast<size_t>(m.V.rows()), -1);
  gp::Mesh out;
  out.F.resize(static_cast<Eigen::Index>(keep_faces.size()), 3);
  int n = 0;
  for (size_t k = 0; k < keep_faces.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      int& id = new_id[static_cast<size_t>(m.F(keep_faces[k], c))];
      if (id < 0) id = n++;
      out.F(static_cast<Eigen::Index>(k), c) = id;
    }
  out.V.resize(n, 3);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i)
    if (new_id[static_cast<size_t>(i)] >= 0) out.V.row(new_id[static_cast<size_t>(i)]) = m.V.row(i);
  if (!cap) return out;
  for (const std::vector<int>& loop : gp::boundary_loops(out.F)) {
    Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
    for (int v : loop) c += out.V.row(v);
    c /= static_cast<double>(loop.size());
    const int centre = static_cast<int>(out.V.rows());
    out.V.conservativeResize(centre + 1, 3);
    out.V.row(centre) = c;
    const Eigen::Index f0 = out.F.rows();
    out.F.conservativeResize(f0 + static_cast<Eigen::Index>(loop.size()), 3);
    // The loop runs with the surface on its left; the cap closes it the other way.
    for (size_t k = 0; k < loop.size(); ++k)
      out.F.row(f0 + static_cast<Eigen::Index>(k)) << loop[(k + 1) % loop.size()], loop[k], centre;
  }
  return out;
}

// Vertices whose largest skinning weight belongs to one of `joints`.
std::vector<bool> part(const Eigen::MatrixXd& weights, std::initializer_list<int> joints) {
  std::vector<bool> in(static_cast<size_t>(weights.rows()), false);
  for (Eigen::Index i = 0; i < weights.rows(); ++i) {
    Eigen::Index j = 0;
    weights.row(i).maxCoeff(&j);
    for (int k : joints) in[static_cast<size_t>(i)] = in[static_cast<size_t>(i)] || j == k;
  }
  return in;
}

}  // namespace

TEST_CASE("generated bodies in every pose, turned and mirrored, with and without feet and hands",
          "[registration][up][avatar]") {
  struct Tally {
    int right = 0, refused = 0, wrong = 0;
  };
  std::map<std::string, Tally> by_variant, by_pose;
  std::ostringstream wrong_cases;
  std::map<std::string, std::string> refused_cases;  // body, pose, variant -> the reason (any orientation)
  int whole_refused = 0;
  for (const std::string spec_name : {"default", "short_125", "tall_200", "maternity"}) {
    const gp::AvatarSpec spec =
        gp::read_avatar_spec(gp::testing::source_dir() / "testdata" / "avatars" / (spec_name + ".json"));
    gp::AvatarOptions o;
    o.target_vertices = gp::kAvatarSmallVertices;
    const gp::AvatarResult body = gp::make_avatar(spec, o);
    const std::vector<bool> feet = part(body.weights, {gp::kLAnkle, gp::kRAnkle});
    const std::vector<bool> hands = part(body.weights, {gp::kLWrist, gp::kRWrist});
    std::vector<bool> both(feet.size());
    for (size_t i = 0; i < both.size(); ++i) both[i] = feet[i] || hands[i];
    for (size_t p = 0; p < body.poses.names.size(); ++p) {
      gp::Mesh whole;
      whole.V = body.poses.V[p];
      whole.F = body.poses.F;
      const std::vector<std::pair<std::string, gp::Mesh>> variants = {
          {"whole", whole},
          {"no feet (open)", without(whole, feet, false)},
          {"no feet (capped)", without(whole, feet, true)},
          {"no hands (capped)", without(whole, hands, true)},
          {"no feet or hands (open)", without(whole, both, false)},
          {"no feet or hands (capped)", without(whole, both, true)}};
      for (const auto& [variant, mesh] : variants)
        for (const gp::UpAxis& up : kDirections)
          for (bool mirror : {false, true}) {
            const gp::Mesh m = oriented(mesh, up, mirror);
            const gp::UpAxisDetection d = gp::detect_up_axis(m.V, m.F);
            const std::string pose = body.poses.names[p];
            Tally& v = by_variant[variant];
            Tally& q = by_pose[pose];
            if (d.ambiguous) {
              ++v.refused, ++q.refused;
              refused_cases[spec_name + " " + body.poses.names[p] + ", " + variant] = d.reason;
              if (variant == "whole") ++whole_refused;
            } else if (d.up.name() == up.name()) {
              ++v.right, ++q.right;
            } else {
              ++v.wrong, ++q.wrong;
              wrong_cases << spec_name << " " << pose << " " << variant << " " << up.name()
                          << (mirror ? " mirrored" : "") << " -> " << d.up.name() << ": " << d.reason << "\n";
            }
          }
    }
  }
  std::ostringstream table;
  for (const auto& [name, t] : by_variant)
    table << name << ": right " << t.right << ", refused " << t.refused << ", wrong " << t.wrong << "\n";
  for (const auto& [name, t] : by_pose)
    table << name << ": right " << t.right << ", refused " << t.refused << ", wrong " << t.wrong << "\n";
  table << "refused (in every orientation unless listed twice):\n";
  for (const auto& [name, reason] : refused_cases) table << "  " << name << "\n";
  INFO(table.str() << wrong_cases.str());
  if (std::getenv("GP_UP_AXIS_REASONS") != nullptr)
    for (const auto& [name, reason] : refused_cases) WARN(name << ": " << reason);
  CHECK(wrong_cases.str().empty());
  // The cues must also be useful: a whole body is never refused, and nearly
  // every case is told (2,136 of 2,160 when this was written: only the 2 m
  // body waving one arm above its head without feet and hands is refused).
  CHECK(whole_refused == 0);
  int right = 0, all = 0;
  for (const auto& [name, t] : by_variant) {
    right += t.right;
    all += t.right + t.refused + t.wrong;
  }
  CHECK(right > 0.95 * all);
  WARN(table.str());
}
