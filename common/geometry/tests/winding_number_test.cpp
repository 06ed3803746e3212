#include <catch2/catch.hpp>

#include "geometry/winding_number.h"
#include "testing/test_meshes.h"

TEST_CASE("the winding number is 1 inside a closed mesh, 0 outside, -1 when reversed", "[geometry]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(2, 0.5);
  CHECK(gp::winding_number(sphere.V, sphere.F, Eigen::Vector3d(0.1, -0.2, 0.05)) == Approx(1.0).margin(1e-9));
  CHECK(gp::winding_number(sphere.V, sphere.F, Eigen::Vector3d(0.6, 0.3, 0.0)) == Approx(0.0).margin(1e-9));
  CHECK(gp::winding_number(sphere.V, sphere.F, Eigen::Vector3d(1e3, 0.0, 0.0)) == Approx(0.0).margin(1e-9));
  gp::Mesh reversed = sphere;
  reversed.F.col(1).swap(reversed.F.col(2));
  CHECK(gp::winding_number(reversed.V, reversed.F, Eigen::Vector3d(0.0, 0.1, 0.0)) == Approx(-1.0).margin(1e-9));
}

TEST_CASE("an open tube wraps its inside: the winding number falls off at its openings", "[geometry]") {
  // A tube (normals outwards) of radius 0.2 from y = 0 to y = 2.
  const gp::Mesh tube = gp::testing::make_open_cylinder(48, 20, 0.2, 2.0);
  const double middle = gp::winding_number(tube.V, tube.F, Eigen::Vector3d(0.0, 1.0, 0.0));
  const double opening = gp::winding_number(tube.V, tube.F, Eigen::Vector3d(0.0, 0.0, 0.0));
  const double beyond = gp::winding_number(tube.V, tube.F, Eigen::Vector3d(0.0, -1.0, 0.0));
  const double beside = gp::winding_number(tube.V, tube.F, Eigen::Vector3d(0.5, 1.0, 0.0));
  CHECK(middle > 0.9);
  CHECK(opening == Approx(0.5).margin(0.05));  // half the solid angle is the tube's
  CHECK(std::abs(beyond) < 0.05);
  CHECK(std::abs(beside) < 0.05);
}
