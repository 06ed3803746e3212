// The verdict on a key pose: each bound fails on its own, just beyond its
// value, and holds just within it.
#include <catch2/catch.hpp>

#include <string>

#include "adapt/key_pose.h"

using gp::adapt::area_fraction_above;
using gp::adapt::check_pose;
using gp::adapt::FitCriteria;
using gp::adapt::KeyPoseResult;

namespace {

// A settled pose within every default bound (delta 0.1).
KeyPoseResult fitting_pose() {
  KeyPoseResult k;
  k.max_stretch = 1.3;  // the maximum alone is no criterion: one sliver may exceed it
  k.p99_stretch = 1.11;
  k.area_fraction_above = 0.009;
  k.deepest_penetration = 0.0019;
  k.settled = true;
  k.settle_steps = 200;
  // 1,000 faces of 1 cm^2, one stretched to 1.3: 0.1 % of the area beyond
  // 1.1, none beyond the tear stretch.
  k.face_rest_area = Eigen::VectorXd::Constant(1000, 1e-4);
  k.face_max_stretch = Eigen::VectorXd::Constant(1000, 1.02);
  k.face_max_stretch(7) = 1.3;
  return k;
}

bool mentions(const std::vector<std::string>& failures, const std::string& text) {
  for (const std::string& f : failures)
    if (f.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("a key pose fails each bound on its own", "[adapt][verdict]") {
  const FitCriteria criteria;
  const double delta = 0.1;
  CHECK(check_pose(fitting_pose(), delta, criteria).empty());

  KeyPoseResult k = fitting_pose();
  k.area_fraction_above = 0.01;  // at the bound: fails
  CHECK(mentions(check_pose(k, delta, criteria), "1.00 % of the area stretched above 1.100"));

  k = fitting_pose();
  k.p99_stretch = 1.1201;
  const auto p99 = check_pose(k, delta, criteria);
  REQUIRE(p99.size() == 1);
  CHECK(mentions(p99, "p99 stretch 1.1201 above 1.1200"));

  k = fitting_pose();
  k.deepest_penetration = 0.0021;
  CHECK(mentions(check_pose(k, delta, criteria), "2.1 mm inside the body"));

  k = fitting_pose();
  k.crossings.body_edge_crossings = 1;
  CHECK(mentions(check_pose(k, delta, criteria), "1 edge/triangle crossings"));
}

TEST_CASE("a key pose whose cloth still moves at the settle cap fails, unless allowed", "[adapt][verdict]") {
  KeyPoseResult k = fitting_pose();
  k.settled = false;
  k.settle_steps = 1000;
  k.max_net_speed = 0.083;
  FitCriteria criteria;
  const auto failures = check_pose(k, 0.1, criteria);
  REQUIRE(failures.size() == 1);
  CHECK(failures.front() ==
        "the cloth did not settle within 1000 steps (largest net vertex speed 0.083 m/s over the last check)");
  criteria.require_settled = false;
  CHECK(check_pose(k, 0.1, criteria).empty());
}

TEST_CASE("a key pose whose cloth would tear fails, however little of the budget that is", "[adapt][verdict]") {
  const FitCriteria criteria;  // tear stretch 1.5, at most 0.1 % of the area beyond it
  KeyPoseResult k = fitting_pose();
  CHECK(area_fraction_above(k, criteria.tear_stretch) == 0.0);
  // One small face at 3.6 (half a square centimetre): 0.05 % of the area.
  k.face_max_stretch(100) = 3.6;
  k.face_rest_area(100) = 0.5e-4;
  CHECK(area_fraction_above(k, criteria.tear_stretch) == Approx(0.5e-4 / (999 * 1e-4 + 0.5e-4)));
  CHECK(check_pose(k, 0.1, criteria).empty());
  k.face_rest_area(100) = 1e-4;
  // A hand gripping the skirt, two faces: 0.2 %, beyond the bound, and the
  // only bound that fails.
  k.face_max_stretch(101) = 1.51;
  const auto failures = check_pose(k, 0.1, criteria);
  REQUIRE(failures.size() == 1);
  CHECK(failures.front() == "0.20 % of the area stretched beyond 1.50, where cloth tears (at most 0.10 %)");
  // Weighted by rest area: the same two faces at a tenth of the area hold.
  k.face_rest_area(100) = k.face_rest_area(101) = 1e-5;
  CHECK(check_pose(k, 0.1, criteria).empty());
}
