// Pin targets kept clear of the body (pin_targets.h), and a
// body part rising into the cloth beside its pins during a motion.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "adapt/garment_motion.h"
#include "adapt/pin_targets.h"
#include "collision/body_collider.h"
#include "core/error.h"
#include "garment/garment_file.h"
#include "garment/surface_point.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "mesh/topology.h"
#include "pose/pose_set.h"
#include "testing/test_meshes.h"

using gp::adapt::keep_off_body;
using gp::adapt::PinClearanceStats;

namespace {

// Two meshes as one (b's vertex ids after a's).
gp::Mesh joined(const gp::Mesh& a, const gp::Mesh& b, const Eigen::Vector3d& b_shift) {
  gp::Mesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V.rowwise() + b_shift.transpose();
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, b.F.array() + static_cast<int>(a.V.rows());
  return m;
}

double distance_to_sphere(const Eigen::Vector3d& p, const Eigen::Vector3d& centre, double radius) {
  return (p - centre).norm() - radius;
}

}  // namespace

TEST_CASE("pin targets within the clearance move out to it; those beyond it stay bit for bit", "[adapt][pins]") {
  // A sphere of radius 10 cm (faceted: 2,562 vertices, so the faces lie up to
  // 0.12 mm inside the sphere), clearance 1 cm. Targets: at 2 cm (clear), at
  // 4 mm, 1 mm inside, 5 cm inside (near the centre).
  const double radius = 0.1, clearance = 0.01;
  const gp::Mesh body = gp::testing::make_icosphere(4, radius);
  gp::collision::BodyCollider collider(body.F);
  collider.set_body(body.V);
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, 0.8, -0.5).normalized();
  Eigen::MatrixXd T(4, 3);
  T.row(0) = (radius + 0.02) * dir.transpose();
  T.row(1) = (radius + 0.004) * dir.transpose();
  T.row(2) = (radius - 0.001) * dir.transpose();
  T.row(3) = (radius - 0.05) * dir.transpose();
  const Eigen::MatrixXd before = T;
  std::vector<int> hints(4, -1);
  PinClearanceStats stats;
  keep_off_body(T, collider, clearance, hints, stats);

  CHECK(T.row(0) == before.row(0));
  for (int k = 1; k < 4; ++k) {
    INFO("target " << k);
    const gp::collision::Proximity q = collider.query(T.row(k).transpose());
    CHECK(q.signed_distance == Approx(clearance).margin(1e-6));
    // Out along the sphere's radius (up to the facets' normals).
    CHECK(T.row(k).normalized().dot(dir.transpose()) > 0.999);
    CHECK(hints[static_cast<size_t>(k)] >= 0);
  }
  CHECK(stats.pushed == 3);
  CHECK(stats.closest_before == Approx(-0.05).margin(2e-4));
  CHECK(stats.largest_push == Approx(0.06).margin(2e-4));

  // A second call on the same body leaves them all where they are.
  const Eigen::MatrixXd cleared = T;
  keep_off_body(T, collider, clearance, hints, stats);
  CHECK(T == cleared);
  CHECK(stats.pushed == 3);
}

TEST_CASE(
    "a pin target between two body parts nearer than twice the clearance "
    "goes to the middle",
    "[adapt][pins]") {
  // Two spheres of 5 cm with a gap of 12 mm between them along x, clearance
  // 1 cm: no point keeps 1 cm from both. A target 2 mm off the left one on
  // the line between them ends in the middle, 6 mm from each.
  const double radius = 0.05, gap = 0.012, clearance = 0.01;
  const gp::Mesh sphere = gp::testing::make_icosphere(4, radius);
  const Eigen::Vector3d right_centre(2.0 * radius + gap, 0.0, 0.0);
  const gp::Mesh body = joined(sphere, sphere, right_centre);
  gp::collision::BodyCollider collider(body.F);
  collider.set_body(body.V);
  Eigen::MatrixXd T(1, 3);
  T << radius + 0.002, 0.0, 0.0;
  std::vector<int> hints(1, -1);
  PinClearanceStats stats;
  keep_off_body(T, collider, clearance, hints, stats);
  const Eigen::Vector3d t = T.row(0).transpose();
  // The facets lie up to 0.1 mm inside the spheres at this resolution.
  CHECK(distance_to_sphere(t, Eigen::Vector3d::Zero(), radius) == Approx(0.5 * gap).margin(2e-4));
  CHECK(distance_to_sphere(t, right_centre, radius) == Approx(0.5 * gap).margin(2e-4));
  CHECK(stats.pushed == 1);
}

TEST_CASE("a pin target in a crease keeps the clearance from both sides", "[adapt][pins]") {
  // Two spheres of 5 cm overlapping by 2 cm (their union has a concave crease
  // around the circle where they meet), clearance 1 cm. A target just above the
  // crease: one push clears it from the nearer sphere only; the repeated
  // pushes clear both.
  const double radius = 0.05, clearance = 0.01;
  const gp::Mesh sphere = gp::testing::make_icosphere(4, radius);
  const Eigen::Vector3d right_centre(2.0 * radius - 0.02, 0.0, 0.0);
  // Both whole spheres as one body: the part of each inside the other is
  // never the closest to a point above the crease.
  const gp::Mesh both = joined(sphere, sphere, right_centre);
  gp::collision::BodyCollider collider(both.F);
  collider.set_body(both.V);
  const double crease_x = 0.5 * right_centre.x();
  Eigen::MatrixXd T(1, 3);
  T << crease_x - 0.003, std::sqrt(radius * radius - crease_x * crease_x) + 0.002, 0.0;
  std::vector<int> hints(1, -1);
  PinClearanceStats stats;
  keep_off_body(T, collider, clearance, hints, stats);
  const Eigen::Vector3d t = T.row(0).transpose();
  CHECK(distance_to_sphere(t, Eigen::Vector3d::Zero(), radius) > clearance - 3e-4);
  CHECK(distance_to_sphere(t, right_centre, radius) > clearance - 3e-4);
  CHECK(collider.query(t).signed_distance > clearance - 1e-4);
}

TEST_CASE("pin targets need one hint each and a non-negative clearance", "[adapt][pins]") {
  const gp::Mesh body = gp::testing::make_icosphere(2, 0.1);
  gp::collision::BodyCollider collider(body.F);
  collider.set_body(body.V);
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(2, 3);
  std::vector<int> hints(1, -1);
  PinClearanceStats stats;
  CHECK_THROWS_AS(keep_off_body(T, collider, 0.01, hints, stats), gp::UsageError);
  hints.assign(2, -1);
  CHECK_THROWS_AS(keep_off_body(T, collider, -0.01, hints, stats), gp::UsageError);
  CHECK_THROWS_AS(keep_off_body(T, collider, std::nan(""), hints, stats), gp::UsageError);
}

namespace {

// A "shrug" on a sphere of radius 10 cm: the body below a ring at 60 degrees
// from the top (the neckline) rises by up to 2 cm along +y on the +z side,
// the most right beside the ring, so that a shelf of body comes up level
// with the ring where a shoulder would. A band of cloth 1 cm out (radius
// 11 cm, latitudes 60 to 95 degrees, 14 mm edges) hangs from the ring, which
// is pinned and bound to the body as make-garment binds a neckline.
struct ShrugScene {
  gp::PoseSet poses;
  gp::Mesh garment;
  gp::GarmentFile file;
};

ShrugScene shrug_scene() {
  const double radius = 0.1, offset = 0.01, rise = 0.02;
  const double ring = 60.0 * M_PI / 180.0;
  ShrugScene s;
  const gp::Mesh body = gp::testing::make_icosphere(4, radius);
  Eigen::MatrixXd raised = body.V;
  for (Eigen::Index v = 0; v < body.V.rows(); ++v) {
    const Eigen::Vector3d p = body.V.row(v).transpose();
    const double polar = std::acos(std::clamp(p.y() / radius, -1.0, 1.0));
    const double azimuth = std::atan2(p.x(), p.z());
    // Full rise from 3 to 15 degrees below the ring, none from 40 on; over
    // +-50 degrees of azimuth around +z.
    const double below = (polar - ring) * 180.0 / M_PI;
    double w_polar = 0.0;
    if (below >= 3.0 && below <= 15.0)
      w_polar = 1.0;
    else if (below > 0.0 && below < 3.0)
      w_polar = below / 3.0;
    else if (below > 15.0 && below < 40.0)
      w_polar = 0.5 + 0.5 * std::cos(M_PI * (below - 15.0) / 25.0);
    const double w_azimuth =
        std::abs(azimuth) < 50.0 * M_PI / 180.0 ? std::pow(std::cos(azimuth * 90.0 / 50.0), 2) : 0.0;
    raised(v, 1) += rise * w_polar * w_azimuth;
  }
  s.poses.names = {"rest", "shrug"};
  s.poses.V = {body.V, raised};
  s.poses.F = body.F;
  s.poses.reference = "rest";

  const gp::Mesh cloth_sphere = gp::testing::make_icosphere(3, radius + offset);
  std::vector<int> band;
  for (int f = 0; f < cloth_sphere.F.rows(); ++f) {
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
      const double y = cloth_sphere.V(cloth_sphere.F(f, k), 1) / (radius + offset);
      inside = inside && y <= std::cos(ring) + 1e-9 && y >= std::cos(95.0 * M_PI / 180.0);
    }
    if (inside) band.push_back(f);
  }
  s.garment = gp::testing::face_subset(cloth_sphere, band).mesh;
  gp::SurfaceLocator locator(body.V, body.F);
  gp::GarmentLoop neck;
  neck.name = "neck";
  neck.pinned = true;
  for (const std::vector<int>& loop : gp::boundary_loops(s.garment.F)) {
    double mean_y = 0.0;
    for (int v : loop) mean_y += s.garment.V(v, 1) / loop.size();
    if (mean_y < 0.0) continue;  // the free hem
    for (int v : loop) {
      neck.vertex_ids.push_back(v);
      neck.binding.push_back(locator.closest(s.garment.V.row(v).transpose()).at);
    }
  }
  s.file.name = "collar";
  s.file.vertex_count = s.garment.V.rows();
  s.file.face_count = s.garment.F.rows();
  s.file.body.design_pose = "rest";
  s.file.offset = offset;
  s.file.loops = {neck};
  return s;
}

gp::adapt::MotionRunResult run_shrug(const ShrugScene& s, double pin_clearance) {
  gp::Json j;
  j["schema"] = "motion/1";
  j["steps"] = 20;
  j["sequence"] = {"rest", "shrug", "rest"};
  const gp::MotionSpec motion = gp::parse_motion_spec(j, "motion.json", s.poses);
  gp::PoseInterpolator interpolator(s.poses);
  gp::adapt::MotionRunOptions o;
  o.adaptation.enabled = false;
  o.settle.max_steps = 60;
  o.contact.pin_clearance = pin_clearance;
  return gp::adapt::run_garment_motion(interpolator, motion, s.garment.V, s.garment.F, s.file, o);
}

}  // namespace

TEST_CASE("a body part rising beside pinned cloth does not pass through it", "[adapt][pins][body]") {
  // The shrug scene (192 cloth vertices, 42 of them pinned), rest -> shrug
  // -> rest in 20 frames each, no adaptation. With the pins following their
  // binding alone, the shelf rises over the ring's targets: the body goes
  // through the cloth beside the pins or, pushed against pins it cannot
  // move, the cloth tears (the step fails). With the targets kept half the
  // offset from the body (the default), no body edge crosses the cloth and no cloth edge
  // the body at any key pose, and the contact resolves every passage.
  const ShrugScene scene = shrug_scene();
  REQUIRE(scene.file.loops[0].vertex_ids.size() >= 20);
  const gp::adapt::MotionRunResult cleared = run_shrug(scene, 0.5);
  REQUIRE(cleared.continuous_contact);
  REQUIRE(cleared.keys.size() == 3);
  for (const gp::adapt::KeyPoseResult& k : cleared.keys) {
    INFO("key " << k.key << " " << k.pose << ": " << k.crossings.crossings() << " crossings, deepest "
                << k.deepest_penetration << " m; targets moved " << cleared.pins.pushed << " times, up to "
                << cleared.pins.largest_push << " m, closest " << cleared.pins.closest_before << " m");
    CHECK(k.crossings.intersection_free());
    CHECK(k.deepest_penetration < 1e-3);
  }
  CHECK(cleared.contact.unresolved == 0);
  CHECK(cleared.pins.pushed > 0);
  // The binding alone inside the shelf.
  CHECK(cleared.pins.closest_before < 0.0);

  long bound_crossings = -1;
  try {
    const gp::adapt::MotionRunResult bound = run_shrug(scene, 0.0);
    bound_crossings = bound.keys.at(1).crossings.crossings();
  } catch (const gp::NumericalError& e) {
    INFO(e.what());
    bound_crossings = -2;
  }
  // Measured: the step fails (the pinned vertices, held on the shelf's
  // surface, are pushed through by the rising part). The test used to accept
  // crossings at the shrug as well, so it could not fail.
  INFO("binding alone: " << (bound_crossings == -2 ? "the step failed" : "it finished") << ", crossings at the shrug "
                         << bound_crossings);
  CHECK(bound_crossings == -2);
  // A clearance is a fraction of the offset.
  CHECK_THROWS_AS(run_shrug(scene, 1.5), gp::UsageError);
  CHECK_THROWS_AS(run_shrug(scene, -0.1), gp::UsageError);
}
