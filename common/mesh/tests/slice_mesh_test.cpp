#include <catch2/catch.hpp>

#include <cmath>

#include "mesh/slice_mesh.h"
#include "testing/test_meshes.h"

TEST_CASE("a plane through a sphere cuts one closed loop of the circle's length", "[mesh][slice]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(4, 1.0);
  std::vector<bool> closed;
  const auto cut = gp::slice_mesh(sphere.V, sphere.F, Eigen::Vector3d(0, 0.5, 0), Eigen::Vector3d::UnitY(), &closed);
  REQUIRE(cut.size() == 1);
  REQUIRE(closed.size() == 1);
  CHECK(closed[0]);
  // Circle of radius sqrt(1 - 0.25); the inscribed polygon is a little shorter.
  CHECK(gp::polyline_length(cut[0], true) == Approx(2 * M_PI * std::sqrt(0.75)).epsilon(0.01));
  CHECK(gp::slice_mesh(sphere.V, sphere.F, Eigen::Vector3d(0, 2, 0), Eigen::Vector3d::UnitY()).empty());
}

TEST_CASE("a plane through a torus across its hole cuts two loops", "[mesh][slice]") {
  const gp::Mesh torus = gp::testing::make_torus(32, 16);
  std::vector<bool> closed;
  const auto cut = gp::slice_mesh(torus.V, torus.F, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), &closed);
  CHECK(cut.size() == 2);
  CHECK(closed == std::vector<bool>{true, true});
}

TEST_CASE("a plane along an open cylinder cuts open polylines, each whole", "[mesh][slice]") {
  const gp::Mesh cyl = gp::testing::make_open_cylinder(16, 4);
  // The cylinder stands along y from 0 to 2; the plane x = 0.001 runs along it.
  const Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  std::vector<bool> closed;
  const auto cut = gp::slice_mesh(cyl.V, cyl.F, 1e-3 * normal, normal, &closed);
  // Two lines along the wall, each from one rim to the other, each in one piece.
  REQUIRE(cut.size() == 2);
  CHECK(closed == std::vector<bool>{false, false});
  for (const auto& line : cut)
    CHECK(gp::polyline_length(line, false) == Approx(2.0).epsilon(0.02));
}
