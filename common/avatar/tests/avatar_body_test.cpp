// The generated body: girths, closedness, self-intersection, volume across
// poses and connectivity, for the example specs in testdata/avatars (small
// resolution, so the whole file runs in a few seconds).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "avatar/body_checks.h"
#include "avatar/girth.h"
#include "avatar/make_avatar.h"
#include "core/error.h"
#include "geometry/self_intersections.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "testing/command.h"

namespace {

gp::AvatarResult small_body(const gp::AvatarSpec& spec, std::vector<std::string> poses = {}) {
  gp::AvatarOptions o;
  o.target_vertices = gp::kAvatarSmallVertices;
  o.poses = std::move(poses);
  return gp::make_avatar(spec, o);
}

gp::AvatarSpec example(const std::string& name) {
  return gp::read_avatar_spec(gp::testing::source_dir() / "testdata" / "avatars" / (name + ".json"));
}

// Everything the issue asks of a generated body.
void check_body(const gp::AvatarResult& r) {
  const gp::PoseSet& ps = r.poses;
  REQUIRE(ps.names.size() == ps.V.size());
  REQUIRE(ps.names.front() == "apose");
  // Closed, manifold, one component, sphere topology (shared by all poses).
  CHECK(gp::boundary_loops(ps.F).empty());
  CHECK((gp::triangle_adjacency(ps.F).array() >= 0).all());
  Eigen::VectorXi comp;
  CHECK(gp::face_components(ps.F, comp) == 1);
  CHECK(gp::euler_characteristic(ps.F) == 2);
  CHECK_NOTHROW(gp::check_closed_genus0(ps.F, "body"));
  // No self-intersection in the rest pose.
  CHECK_FALSE(gp::has_self_intersection(ps.V[0], ps.F));
  double vmin = 1e300, vmax = -1e300;
  for (size_t i = 0; i < ps.V.size(); ++i) {
    INFO("pose " << ps.names[i]);
    REQUIRE(ps.V[i].rows() == ps.V[0].rows());
    CHECK(ps.V[i].allFinite());
    // Feet on the floor; outward orientation (positive volume).
    CHECK(ps.V[i].col(1).minCoeff() == 0.0);
    const double vol = gp::signed_volume(ps.V[i], ps.F);
    CHECK(vol > 0);
    CHECK(vol == Approx(r.volumes[i]).epsilon(1e-12));
    vmin = std::min(vmin, vol);
    vmax = std::max(vmax, vol);
  }
  CHECK(vmax / vmin - 1.0 < 0.03);
  // Girths, re-measured here on the rest pose, within 1 cm.
  REQUIRE(r.girths.size() == 11);
  for (const gp::GirthResult& g : r.girths) {
    INFO("girth " << g.name);
    const double measured = gp::mesh_girth(ps.V[0], ps.F, g.center, g.normal);
    CHECK(measured == Approx(g.measured).margin(1e-9));
    CHECK(std::abs(measured - g.target) < 0.01);
  }
}

}  // namespace

TEST_CASE("very short adult (1.25 m): girths, closed, no self-intersection, volume", "[avatar][body]") {
  const gp::AvatarSpec spec = example("short_125");
  REQUIRE(spec.measurements.height == 1.25);
  const gp::AvatarResult r = small_body(spec);
  CHECK(r.poses.names.size() == 8);
  check_body(r);
  CHECK(r.height == Approx(1.25).margin(0.01));
}

TEST_CASE("very tall asymmetric body (2.0 m) with joint-angle poses", "[avatar][body]") {
  const gp::AvatarSpec spec = example("tall_200");
  const gp::AvatarResult r = small_body(spec);
  CHECK(r.poses.names.size() == 10);
  CHECK(r.poses.names[8] == "wave");
  check_body(r);
  CHECK(r.height == Approx(2.0).margin(0.01));
  // The left arm is 12 mm longer than the right.
  const Eigen::MatrixXd& J = r.joints[0];
  const double left = (J.row(gp::kLWrist) - J.row(gp::kLShoulder)).norm();
  const double right = (J.row(gp::kRWrist) - J.row(gp::kRShoulder)).norm();
  CHECK(left - right == Approx(0.012).margin(1e-9));
  // "wave" raises the left wrist above the head; the right arm stays.
  const Eigen::MatrixXd& W = r.joints[8];
  CHECK(W(gp::kLWrist, 1) > J(gp::kHead, 1));
  CHECK((W.row(gp::kRWrist) - J.row(gp::kRWrist)).norm() < 1e-9);
}

TEST_CASE("maternity belly: waist over the belly within 1 cm", "[avatar][body]") {
  const gp::AvatarSpec spec = example("maternity");
  REQUIRE(spec.measurements.belly_depth == 0.12);
  const gp::AvatarResult r = small_body(spec);
  check_body(r);
  // The belly sticks out: the front of the waist slice is well ahead of the chest's.
  auto front = [&](double y) {
    double z = -1;
    for (const auto& loop :
         gp::slice_mesh(r.poses.V[0], r.poses.F, Eigen::Vector3d(0, y, 0), Eigen::Vector3d::UnitY()))
      for (const auto& p : loop)
        if (std::abs(p.x()) < 0.1) z = std::max(z, p.z());
    return z;
  };
  const auto waist =
      std::find_if(r.girths.begin(), r.girths.end(), [](const auto& g) { return g.name == "waist"; });
  const auto chest =
      std::find_if(r.girths.begin(), r.girths.end(), [](const auto& g) { return g.name == "chest"; });
  CHECK(front(waist->center.y()) > front(chest->center.y()) + 0.05);
}

TEST_CASE("default body: budget, orientation, determinism", "[avatar][body]") {
  const gp::AvatarResult a = small_body(gp::default_avatar_spec(), {"tpose", "seated"});
  const gp::AvatarResult b = small_body(gp::default_avatar_spec(), {"tpose", "seated"});
  REQUIRE(a.poses.names == std::vector<std::string>{"apose", "tpose", "seated"});
  check_body(a);
  const Eigen::Index nv = a.poses.V[0].rows();
  CHECK(nv <= gp::kAvatarSmallVertices);
  CHECK(nv >= gp::kAvatarSmallVertices * 9 / 10);
  CHECK(a.height == Approx(1.70).margin(0.01));
  // Facing +z: the toes are in front of the heels' line; left (+x) arm.
  const Eigen::MatrixXd& V = a.poses.V[0];
  double toe = -1, heel = 1;
  for (Eigen::Index i = 0; i < nv; ++i)
    if (V(i, 1) < 0.03) {
      toe = std::max(toe, V(i, 2));
      heel = std::min(heel, V(i, 2));
    }
  CHECK(toe > 0.15);
  CHECK(heel > -0.1);
  CHECK(a.joints[0](gp::kLWrist, 0) > 0.3);
  CHECK(a.joints[0](gp::kRWrist, 0) < -0.3);
  // T-pose: wrists at shoulder height, far out.
  CHECK(a.joints[1](gp::kLWrist, 1) == Approx(a.joints[1](gp::kLShoulder, 1)).margin(1e-9));
  // Seated: knees a little below the hips and well in front of them, the
  // shins vertical.
  const Eigen::MatrixXd& S = a.joints[2];
  CHECK(S(gp::kLKnee, 1) < S(gp::kLHip, 1));
  CHECK(S(gp::kLKnee, 1) > S(gp::kLHip, 1) - 0.12);
  CHECK(S(gp::kLKnee, 2) > S(gp::kLHip, 2) + 0.3);
  CHECK(S(gp::kLAnkle, 2) == Approx(S(gp::kLKnee, 2)).margin(0.02));
  // Identical results from identical inputs, to the last bit.
  REQUIRE(b.poses.V.size() == a.poses.V.size());
  for (size_t i = 0; i < a.poses.V.size(); ++i) CHECK(a.poses.V[i] == b.poses.V[i]);
  CHECK(a.poses.F == b.poses.F);
  // Weights are a partition of unity.
  CHECK((a.weights.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-12);
  CHECK(a.weights.minCoeff() >= 0.0);
}

TEST_CASE("extreme statures still give a valid body", "[avatar][body]") {
  for (double h : {0.95, 2.4}) {
    INFO("height " << h);
    gp::AvatarSpec spec;
    spec.measurements = gp::scaled_default_measurements(h);
    const gp::AvatarResult r = small_body(spec, {"armsup"});
    check_body(r);
    CHECK(r.height == Approx(h).margin(0.01 * h));
  }
}

TEST_CASE("spec reading: defaults, strictness, plausibility", "[avatar][spec]") {
  auto parse = [](const std::string& text) { return gp::parse_avatar_spec(gp::Json::parse(text), "s.json"); };
  SECTION("missing measurements scale with the height") {
    const gp::AvatarSpec s = parse(R"({"schema": "avatar-spec/1", "measurements": {"height": 1.87}})");
    CHECK(s.measurements.chest == Approx(0.92 * 1.1));
    CHECK(s.measurements.inseam == Approx(0.77 * 1.1));
    CHECK(s.measurements.belly_depth == 0.0);
    const gp::AvatarSpec d = parse(R"({"schema": "avatar-spec/1"})");
    CHECK(d.measurements.height == 1.70);
  }
  auto where = [&](const std::string& text) {
    try {
      parse(text);
    } catch (const gp::SpecError& e) {
      return e.where();
    }
    return std::string("no error");
  };
  CHECK(where(R"({"schema": "avatar-spec/1", "measurements": {"waist": -0.7}})") ==
        "s.json: /measurements/waist");
  CHECK(where(R"({"schema": "avatar-spec/1", "measurements": {"waist": 2.5}})") ==
        "s.json: /measurements/waist");
  CHECK(where(R"({"schema": "avatar-spec/1", "measurements": {"wasit": 0.7}})") ==
        "s.json: /measurements/wasit");
  CHECK(where(R"({"schema": "avatar-spec/1", "measurements": {"height": 17}})") ==
        "s.json: /measurements/height");
  CHECK(where(R"({"schema": "avatar-spec/1", "measurements": {"wrist": "thin"}})") ==
        "s.json: /measurements/wrist");
  CHECK(where(R"({"schema": "avatar-spec/1", "measurements": {"thigh": 0.8}})") ==
        "s.json: /measurements/thigh");
  CHECK(where(R"({"schema": "avatar-spec/1", "colour": "red"})") == "s.json: /colour");
  CHECK(where(R"({"schema": "avatar-spec/2"})").find("/schema") != std::string::npos);
  CHECK(
      where(R"({"schema": "avatar-spec/1", "poses": [{"name": "x", "joints": {"l_sholder": [0, 0, 1]}}]})") ==
      "s.json: /poses/0/joints/l_sholder");
  CHECK(where(R"({"schema": "avatar-spec/1", "poses": [{"name": "x", "joints": {"l_elbow": [0, 1]}}]})") ==
        "s.json: /poses/0/joints/l_elbow");
  CHECK(where(R"({"schema": "avatar-spec/1", "poses": [{"name": "a b", "joints": {}}]})") ==
        "s.json: /poses/0/name");
  // Measurements set in code are validated too, NaN included.
  gp::AvatarSpec nan_spec;
  nan_spec.measurements.waist = std::nan("");
  CHECK_THROWS_WITH(small_body(nan_spec), Catch::Contains("waist"));
  nan_spec.measurements = gp::Measurements{};
  nan_spec.measurements.leg_length_difference = std::nan("");
  CHECK_THROWS_AS(small_body(nan_spec), gp::SpecError);
  nan_spec.measurements = gp::Measurements{};
  nan_spec.measurements.height = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(small_body(nan_spec), gp::SpecError);
  // Pose names that clash or are unknown are spec errors too.
  gp::AvatarSpec s = parse(R"({"schema": "avatar-spec/1", "poses": [{"name": "tpose", "joints": {}}]})");
  CHECK_THROWS_AS(small_body(s), gp::SpecError);
  CHECK_THROWS_AS(small_body(gp::default_avatar_spec(), {"cartwheel"}), gp::SpecError);
}

// The pose the scanned customer stands in: the hands beside the thighs, a few
// millimetres from them (the capture's left hand: 6.5 mm), and not through
// them. Hand: vertices whose largest skinning weight is a wrist's; hip and
// thigh: the pelvis's and the hips'. Measured 5.7 mm on both sides at the
// default resolution (0.5 degree more elbow bend: 2.3 mm; 1 degree more: the
// hand passes into the hip).
TEST_CASE("hands on thighs: each hand a few millimetres from its hip, the body not through itself", "[avatar][body]") {
  gp::AvatarOptions o;
  o.poses = {"handsonthighs"};
  const gp::AvatarResult r = gp::make_avatar(gp::default_avatar_spec(), o);
  REQUIRE(r.poses.names == std::vector<std::string>{"apose", "handsonthighs"});
  const Eigen::MatrixXd& V = r.poses.V[1];
  auto dominant = [&](Eigen::Index v) {
    Eigen::Index j = 0;
    r.weights.row(v).maxCoeff(&j);
    return static_cast<int>(j);
  };
  for (const auto& [wrist, hip] : {std::pair{gp::kLWrist, gp::kLHip}, std::pair{gp::kRWrist, gp::kRHip}}) {
    double gap = std::numeric_limits<double>::infinity(), rest_gap = gap;
    for (Eigen::Index h = 0; h < V.rows(); ++h) {
      if (dominant(h) != wrist) continue;
      for (Eigen::Index b = 0; b < V.rows(); ++b) {
        const int j = dominant(b);
        if (j != hip && j != gp::kPelvis) continue;
        gap = std::min(gap, (V.row(h) - V.row(b)).norm());
        rest_gap = std::min(rest_gap, (r.poses.V[0].row(h) - r.poses.V[0].row(b)).norm());
      }
    }
    INFO("wrist joint " << wrist << ": " << 1000.0 * gap << " mm from the hip (A-pose " << 1000.0 * rest_gap << " mm)");
    CHECK(gap > 0.002);
    CHECK(gap < 0.009);
    CHECK(rest_gap > 0.2);
  }
  CHECK(gp::self_intersecting_faces(V, r.poses.F).empty());
}
