// Cloth in a gap narrower than twice its comfort offset (a skirt between a
// hand and the thigh): the collider lets the offset shrink to half the gap,
// never below the cloth's thickness, so that the cloth passes through the gap
// instead of being pushed from one side into the other.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "cloth/cloth_simulator.h"
#include "core/error.h"
#include "collision/body_collider.h"
#include "io/mesh.h"
#include "testing/test_meshes.h"
#include "cloth/tests/function_contact.h"

using gp::collision::BodyCollider;

namespace {

// Two axis-aligned boxes as one closed body: [x0, x1] x [y0, y1] x [z0, z1]
// each, outward oriented, 12 triangles a box.
gp::Mesh two_boxes(const Eigen::Matrix<double, 2, 6>& boxes) {
  gp::Mesh m;
  m.V.resize(16, 3);
  m.F.resize(24, 3);
  for (int b = 0; b < 2; ++b) {
    for (int i = 0; i < 8; ++i) {
      m.V.row(8 * b + i) << boxes(b, i & 1 ? 1 : 0), boxes(b, i & 2 ? 3 : 2), boxes(b, i & 4 ? 5 : 4);
    }
    Eigen::Matrix<int, 12, 3> f;
    f << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5;
    m.F.middleRows(12 * b, 12) = f.array() + 8 * b;
  }
  return m;
}

// Signed distance of p to an axis-aligned box (negative inside).
double box_distance(const Eigen::Matrix<double, 1, 6>& b, const Eigen::Vector3d& p) {
  Eigen::Vector3d q;
  for (int k = 0; k < 3; ++k) q(k) = std::max(b(2 * k) - p(k), p(k) - b(2 * k + 1));
  const double outside = q.cwiseMax(0.0).norm();
  return outside > 0.0 ? outside : q.maxCoeff();
}

}  // namespace

TEST_CASE("in a 3 mm gap the offset is half the gap, and never below the cloth's thickness", "[collision]") {
  Eigen::Matrix<double, 2, 6> boxes;
  boxes << -0.1, 0.1, -0.2, 0.0, -0.1, 0.1,  // below the gap
      -0.1, 0.1, 0.003, 0.2, -0.1, 0.1;      // above it
  const gp::Mesh body = two_boxes(boxes);
  BodyCollider collider(body.F);
  collider.set_body(body.V);
  Eigen::MatrixXd X(2, 3), Vel = Eigen::MatrixXd::Zero(2, 3);
  X << 0.0, 0.0005, 0.0,  // 0.5 mm above the lower box
      0.02, 0.0028, 0.0;  // 0.2 mm below the upper one
  collider.resolve(X, Vel, 0.008);
  CHECK(X(0, 1) == Approx(0.0015).margin(1e-9));
  CHECK(X(1, 1) == Approx(0.0015).margin(1e-9));
  CHECK(collider.stats().pinched == 2);

  // A gap of 1.2 mm leaves half of it, 0.6 mm, less than a 1 mm cloth: the
  // vertex keeps the cloth's thickness from the nearer part.
  boxes(1, 2) = 0.0012;
  const gp::Mesh narrow = two_boxes(boxes);
  BodyCollider tight(narrow.F);
  tight.set_body(narrow.V);
  tight.set_min_pinch_offset(0.001);
  Eigen::MatrixXd Y(1, 3), W = Eigen::MatrixXd::Zero(1, 3);
  Y << 0.0, 0.0002, 0.0;
  tight.resolve(Y, W, 0.008);
  CHECK(Y(0, 1) == Approx(0.001).margin(1e-9));
  CHECK_THROWS_AS(tight.set_min_pinch_offset(-1.0), gp::UsageError);
}

TEST_CASE("a sheet in a 3 mm gap with an 8 mm offset settles unstretched and clear of both parts",
          "[collision][simulator]") {
  // Two boxes 3 mm apart (a hand 3 mm from the thigh) and a 0.4 m by 0.16 m
  // strip lying across the gap, its ends free to fall over the lower box's
  // edges (a skirt passing between the hand and the thigh).
  // Expectation: the sheet settles (slow), keeps 1.5 mm from both boxes in
  // the gap and its offset elsewhere less a millimetre of solver slack, is
  // stretched less than 1.10 (the fit's limit), and no vertex enters a box.
  // Without the half-gap rule a vertex pushed 8 mm out of one box lands
  // 5 mm inside the other; with the gap along the normal only, the offset
  // jumps from 1.5 to 8 mm at the boxes' rims and the strip ends stretched
  // 1.14 and still moving (0.11 m/s) after these 400 steps.
  Eigen::Matrix<double, 2, 6> boxes;
  boxes << -0.1, 0.1, -0.2, 0.0, -0.1, 0.1, -0.1, 0.1, 0.003, 0.2, -0.1, 0.1;
  const gp::Mesh body = two_boxes(boxes);
  const double offset = 0.008;
  gp::Mesh cloth = gp::testing::make_grid(40, 16, 0.4, 0.16);
  cloth.V.rowwise() += Eigen::RowVector3d(-0.2, 0.0015, -0.08);
  BodyCollider collider(body.F);
  collider.set_body(body.V);
  collider.set_min_pinch_offset(0.001);
  collider.set_facing_gaps(true);
  gp::cloth::ClothSimulator sim(cloth.V, cloth.F);
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [&](Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) { collider.resolve(X, Vel, offset); };
  step_body.on_constraints = [&](const Eigen::MatrixXd& X, double h, std::vector<gp::cloth::VelocityConstraint>& out) {
    for (const gp::collision::Contact& c : collider.contacts(X, offset, 5e-4)) {
      gp::cloth::VelocityConstraint k;
      k.vertex = c.vertex;
      k.normal = c.outward;
      k.normal_velocity = std::min(std::max(c.offset - c.signed_distance, 0.0) / h, 0.5);
      k.touching = c.signed_distance <= c.offset + 1e-6;
      out.push_back(k);
    }
  };
  for (int s = 0; s < 400; ++s) sim.step();
  const Eigen::MatrixXd& X = sim.positions();
  double deepest = 0.0, in_gap_low = 1.0, in_gap_high = -1.0;
  for (int v = 0; v < X.rows(); ++v) {
    const Eigen::Vector3d p = X.row(v).transpose();
    deepest = std::min({deepest, box_distance(boxes.row(0), p), box_distance(boxes.row(1), p)});
    if (std::abs(p.x()) < 0.09) {
      in_gap_low = std::min(in_gap_low, p.y());
      in_gap_high = std::max(in_gap_high, p.y());
    }
  }
  const double stretch = gp::testing::max_edge_stretch(X, cloth.V, cloth.F);
  INFO("deepest " << deepest << " m, in the gap y " << in_gap_low << " .. " << in_gap_high << " m, stretch "
                  << stretch << ", speed " << sim.max_speed() << " m/s, pinched " << collider.stats().pinched);
  CHECK(deepest >= 0.0);
  CHECK(in_gap_low >= 0.0015 - 1e-4);
  CHECK(in_gap_high <= 0.0015 + 1e-4);
  CHECK(stretch < 1.10);
  CHECK(sim.max_speed() < 0.05);
  CHECK(collider.stats().pinched > 0);
  // The outer parts hang: the corners fell well below the gap.
  CHECK(X(0, 1) < -0.05);
}
