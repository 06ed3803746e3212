#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
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

TEST_CASE("the face list and the yes/no test agree with the pair list", "[geometry]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(2);
  CHECK_FALSE(gp::has_self_intersection(sphere.V, sphere.F));
  CHECK(gp::self_intersecting_faces(sphere.V, sphere.F).empty());

  gp::Mesh dented = sphere;
  dented.V.row(0) *= -1.5;
  const auto pairs = gp::self_intersections(dented.V, dented.F, 1 << 20);
  std::vector<int> from_pairs;
  for (const auto& [a, b] : pairs.first_pairs) {
    from_pairs.push_back(a);
    from_pairs.push_back(b);
  }
  std::sort(from_pairs.begin(), from_pairs.end());
  from_pairs.erase(std::unique(from_pairs.begin(), from_pairs.end()), from_pairs.end());
  const std::vector<int> faces = gp::self_intersecting_faces(dented.V, dented.F);
  CHECK(faces == from_pairs);
  CHECK(std::is_sorted(faces.begin(), faces.end()));
  CHECK(gp::has_self_intersection(dented.V, dented.F));
}

TEST_CASE("a non-manifold face is named, not guessed", "[geometry]") {
  gp::Mesh sphere = gp::testing::make_icosphere(1);
  // Repeat face 3 with its orientation: its edges would be used twice the same way.
  Eigen::MatrixXi F(sphere.F.rows() + 1, 3);
  F << sphere.F, sphere.F.row(3);
  const std::string where = "face " + std::to_string(F.rows() - 1);
  auto location_of = [&](auto&& call) -> std::string {
    try {
      call();
    } catch (const gp::GeometryError& e) {
      return e.where();
    }
    return "no error";
  };
  CHECK(location_of([&] { gp::self_intersecting_faces(sphere.V, F); }) == where);
  CHECK(location_of([&] { gp::has_self_intersection(sphere.V, F); }) == where);
}
