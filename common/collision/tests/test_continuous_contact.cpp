// Intersection-free contact in both directions: a finger through a sheet in
// one step and in many, a cloth tunnelling through a thin plate, pins, and a
// simulated sheet lifted by a finger, which pierces it with the cloth-vertex
// contacts alone and never with the continuous contact added.
#include <catch2/catch.hpp>

#include <cmath>

#include <Eigen/Geometry>

#include "cloth/cloth_simulator.h"
#include "collision/body_collider.h"
#include "collision/continuous_contact.h"
#include "collision/crossings.h"
#include "core/error.h"
#include "testing/test_meshes.h"
#include "cloth/tests/function_contact.h"

using namespace gp::collision;

namespace {

// A closed finger along +y: radius `radius` across, tip at y = tip, 6 cm long.
gp::Mesh finger(double radius, double tip) {
  gp::Mesh m = gp::testing::make_icosphere(3, 1.0);
  for (int v = 0; v < m.V.rows(); ++v) {
    m.V(v, 0) *= radius;
    m.V(v, 2) *= radius;
    m.V(v, 1) = 0.03 * (m.V(v, 1) - 1.0) + tip;
  }
  return m;
}

// A coarse square sheet in the xz-plane at height y, side 0.2 m, 3 by 3
// cells (normals +y), moved so that the finger's axis lies 1.2 cm or more
// from every cloth edge.
gp::Mesh sheet(double y) {
  gp::Mesh m = gp::testing::make_grid(3, 3, 0.2, 0.2);
  for (int v = 0; v < m.V.rows(); ++v) {
    m.V(v, 0) += -0.1 + 0.2 / 12.0;
    m.V(v, 2) -= 0.1;
    m.V(v, 1) = y;
  }
  return m;
}

std::vector<int> border(const gp::Mesh& m) {
  std::vector<int> ids;
  for (int v = 0; v < m.V.rows(); ++v) {
    const double u = m.V(v, 0), w = m.V(v, 2);
    if (std::abs(u - m.V.col(0).minCoeff()) < 1e-9 || std::abs(u - m.V.col(0).maxCoeff()) < 1e-9 ||
        std::abs(w - m.V.col(2).minCoeff()) < 1e-9 || std::abs(w - m.V.col(2).maxCoeff()) < 1e-9) {
      ids.push_back(v);
    }
  }
  return ids;
}

}  // namespace

TEST_CASE("a finger pushed through a sheet in one step lifts the sheet instead", "[collision][contact]") {
  const gp::Mesh start = finger(0.005, -0.005), end = finger(0.005, 0.01);
  const gp::Mesh cloth = sheet(0.0);
  ContinuousContact contact(cloth.F, start.F);
  contact.set_body(start.V);
  contact.set_body(end.V);
  Eigen::MatrixXd X = cloth.V;
  // With the cloth left in place, the finger would come through.
  REQUIRE(find_crossings(end.V, end.F, X, cloth.F).body_edge_crossings > 0);
  contact.enforce(cloth.V, X);
  const CrossingReport r = find_crossings(end.V, end.F, X, cloth.F);
  CHECK(r.intersection_free());
  CHECK(contact.stats().crossings > 0);
  CHECK(contact.stats().unresolved == 0);
  // The sheet moved up only: over the tip, by at least the finger's rise.
  CHECK((X - cloth.V).col(1).minCoeff() >= -1e-12);
  CHECK((X - cloth.V).col(1).maxCoeff() >= 0.01);
}

TEST_CASE("a finger rising through a sheet step by step never crosses it", "[collision][contact]") {
  const gp::Mesh cloth = sheet(0.0);
  const gp::Mesh body = finger(0.004, -0.02);
  ContinuousContact contact(cloth.F, body.F);
  const std::vector<int> pins = border(cloth);
  contact.set_pinned(pins);
  Eigen::MatrixXd X = cloth.V;
  contact.set_body(body.V);
  for (int step = 1; step <= 25; ++step) {
    const gp::Mesh at = finger(0.004, -0.02 + 0.002 * step);  // 2 mm per step, 3 cm in all
    contact.set_body(at.V);
    const Eigen::MatrixXd X_start = X;
    contact.enforce(X_start, X);
    const CrossingReport r = find_crossings(at.V, at.F, X, cloth.F);
    INFO("step " << step);
    CHECK(r.crossings() == 0);
    CHECK(r.cloth_vertices_inside == 0);
  }
  for (int v : pins) CHECK((X.row(v) - cloth.V.row(v)).norm() == 0.0);
  // The tip is 3 cm above the sheet's plane now; the sheet is over it.
  CHECK(X.col(1).maxCoeff() >= 0.01 + contact.options().thickness - 1e-9);
  CHECK(contact.stats().unresolved == 0);
}

TEST_CASE("a cloth vertex tunnelling through a thin plate is put back on its side", "[collision][contact]") {
  // A closed plate 2 mm thick (a squashed sphere), still; a small sheet above
  // it moves 3 cm down in one step, through the plate.
  gp::Mesh plate = gp::testing::make_icosphere(3, 1.0);
  for (int v = 0; v < plate.V.rows(); ++v) {
    plate.V(v, 0) *= 0.1;
    plate.V(v, 2) *= 0.1;
    plate.V(v, 1) *= 0.001;
  }
  gp::Mesh cloth = gp::testing::make_grid(2, 2, 0.04, 0.04);
  cloth.V.rowwise() += Eigen::RowVector3d(-0.02, 0.01, -0.02);
  ContinuousContact contact(cloth.F, plate.F);
  contact.set_body(plate.V);
  Eigen::MatrixXd X = cloth.V;
  X.col(1).array() -= 0.03;
  // Every cloth vertex ends below the plate: outside the body, yet through it.
  REQUIRE(find_crossings(plate.V, plate.F, X, cloth.F).cloth_vertices_inside == 0);
  contact.enforce(cloth.V, X);
  CHECK(contact.stats().cloth_vertex_contacts > 0);
  BodyCollider distance(plate.F);
  distance.set_body(plate.V);
  for (int v = 0; v < X.rows(); ++v) {
    CHECK(distance.query(X.row(v).transpose()).signed_distance >= 0.9 * contact.options().thickness);
  }
  CHECK(find_crossings(plate.V, plate.F, X, cloth.F).intersection_free());
}

TEST_CASE("continuous contact checks its inputs", "[collision][contact]") {
  const gp::Mesh body = finger(0.005, 0.0);
  const gp::Mesh cloth = sheet(0.02);
  ContinuousContact contact(cloth.F, body.F);
  Eigen::MatrixXd X = cloth.V;
  CHECK_THROWS_AS(contact.enforce(cloth.V, X), gp::UsageError);  // no body yet
  Eigen::MatrixXd bad = body.V;
  bad(3, 1) = std::nan("");
  CHECK_THROWS_AS(contact.set_body(bad), gp::GeometryError);
  contact.set_body(body.V);
  CHECK_THROWS_AS(contact.enforce(cloth.V, X, 0.6, 0.4), gp::UsageError);
  Eigen::MatrixXd short_X = X.topRows(3);
  CHECK_THROWS_AS(contact.enforce(cloth.V, short_X), gp::UsageError);
  CHECK_THROWS_AS(contact.set_pinned({-1}), gp::UsageError);
  CHECK_THROWS_AS(ContinuousContact(cloth.F, body.F, {}, ContinuousContactOptions{0.0}), gp::UsageError);
}

TEST_CASE("a simulated sheet lifted by a finger: pierced with vertex contacts alone, never with both directions",
          "[collision][contact][simulator]") {
  const double offset = 0.004;
  const gp::Mesh cloth = sheet(0.0);
  const std::vector<int> pins = border(cloth);
  auto run = [&](bool two_way) {
    gp::Mesh body = finger(0.003, -0.03);
    BodyCollider collider(body.F);
    collider.set_body(body.V);
    ContinuousContact contact(cloth.F, body.F);
    contact.set_pinned(pins);
    contact.set_body(body.V);
    gp::cloth::ClothParameters params;
    params.gravity.setZero();
    gp::cloth::SimulatorOptions options;
    options.dt = 0.01;
    gp::cloth::ClothSimulator sim(cloth.V, cloth.F, params, options);
    sim.set_pinned(pins);
    gp::cloth::testing::FunctionContact step_body;
    sim.set_contact(&step_body);
    step_body.on_project = [&](Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) { collider.resolve(X, Vel, offset); };
    if (two_way) {
      step_body.on_sweep = [&](const Eigen::MatrixXd& X0, Eigen::MatrixXd& X1, double s0, double s1) {
        contact.enforce(X0, X1, s0, s1);
      };
    }
    long worst = 0;
    for (int step = 1; step <= 40; ++step) {
      body = finger(0.003, -0.03 + 0.0015 * step);  // 15 cm/s, 3 cm above the sheet's plane at the end
      collider.set_body(body.V);
      contact.set_body(body.V);
      sim.step();
      worst = std::max(worst, find_crossings(body.V, body.F, sim.positions(), cloth.F).crossings());
    }
    return worst;
  };
  CHECK(run(false) > 0);
  CHECK(run(true) == 0);
}
