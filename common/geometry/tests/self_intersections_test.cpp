#include <catch2/catch.hpp>

#include "geometry/self_intersections.h"
#include "testing/test_meshes.h"

TEST_CASE("a sphere does not intersect itself; two overlapping copies do", "[geometry]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(2);
  CHECK(gp::self_intersections(sphere.V, sphere.F).pair_count == 0);

  // Two spheres in one mesh, the second shifted by half a radius: their
  // surfaces cross along a circle.
  gp::Mesh two;
  const Eigen::Index n = sphere.V.rows(), m = sphere.F.rows();
  two.V.resize(2 * n, 3);
  two.V << sphere.V, sphere.V.rowwise() + Eigen::RowVector3d(0.5, 0, 0);
  two.F.resize(2 * m, 3);
  two.F << sphere.F, sphere.F.array() + static_cast<int>(n);
  const auto result = gp::self_intersections(two.V, two.F, 5);
  CHECK(result.pair_count > 20);
  REQUIRE(result.first_pairs.size() == 5);
  for (const auto& [a, b] : result.first_pairs) {
    CHECK(a < m);
    CHECK(b >= m);  // every pair joins the two spheres
  }
}

TEST_CASE("a vertex pushed through the opposite side is found", "[geometry]") {
  gp::Mesh sphere = gp::testing::make_icosphere(2);
  // Drag vertex 0 through the centre well past the far side.
  sphere.V.row(0) *= -1.5;
  CHECK(gp::self_intersections(sphere.V, sphere.F).pair_count > 0);
}
