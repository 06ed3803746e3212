#include <catch2/catch.hpp>

#include "mesh/measures.h"
#include "mesh/topology.h"
#include "testing/test_meshes.h"

TEST_CASE("closed surfaces have the Euler characteristic of their genus", "[mesh]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(2);
  CHECK(gp::euler_characteristic(sphere.F) == 2);
  CHECK(gp::boundary_loops(sphere.F).empty());
  const gp::Mesh torus = gp::testing::make_torus(20, 10);
  CHECK(gp::euler_characteristic(torus.F) == 0);
  Eigen::VectorXi comp;
  CHECK(gp::face_components(torus.F, comp) == 1);
  CHECK((gp::triangle_adjacency(torus.F).array() >= 0).all());
}

TEST_CASE("boundary loops of an open cylinder follow the faces", "[mesh]") {
  const gp::Mesh cyl = gp::testing::make_open_cylinder(16, 4);
  const auto loops = gp::boundary_loops(cyl.F);
  REQUIRE(loops.size() == 2);
  CHECK(loops[0].size() == 16);
  CHECK(loops[1].size() == 16);
  CHECK(gp::euler_characteristic(cyl.F) == 0);
  // Surface on the left: consecutive loop vertices form a directed edge of some face.
  const auto& loop = loops[0];
  int matches = 0;
  for (Eigen::Index f = 0; f < cyl.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (cyl.F(f, k) == loop[0] && cyl.F(f, (k + 1) % 3) == loop[1]) ++matches;
  CHECK(matches == 1);
}

TEST_CASE("measures of a sphere approach the analytic values", "[mesh]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(4, 2.0);
  CHECK(gp::face_areas(sphere.V, sphere.F).sum() == Approx(4 * M_PI * 4).epsilon(0.01));
  CHECK(gp::signed_volume(sphere.V, sphere.F) == Approx(4.0 / 3.0 * M_PI * 8).epsilon(0.01));
  const Eigen::MatrixXd N = gp::vertex_normals(sphere.V, sphere.F);
  for (Eigen::Index i = 0; i < sphere.V.rows(); ++i)
    CHECK(N.row(i).dot(sphere.V.row(i).normalized()) > 0.999);
  Eigen::VectorXi comp;
  gp::Mesh two;
  two.V.resize(2 * sphere.V.rows(), 3);
  two.V << sphere.V, sphere.V;
  two.F.resize(2 * sphere.F.rows(), 3);
  two.F << sphere.F, sphere.F.array() + static_cast<int>(sphere.V.rows());
  CHECK(gp::face_components(two.F, comp) == 2);
}

TEST_CASE("area centroid weighs each triangle by its area", "[mesh]") {
  // Two triangles: a unit right triangle at the origin (area 0.5, centroid
  // (1/3, 1/3, 0)) and one three times as large far away (area 1.5).
  Eigen::MatrixXd V(6, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 10, 0, 0, 13, 0, 0, 10, 1, 0;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 3, 4, 5;
  const Eigen::Vector3d c = gp::area_centroid(V, F);
  const Eigen::Vector3d expected = (0.5 * Eigen::Vector3d(1.0 / 3, 1.0 / 3, 0) + 1.5 * Eigen::Vector3d(11, 1.0 / 3, 0)) / 2.0;
  CHECK((c - expected).norm() < 1e-12);
  // Degenerate triangles only: no area, the origin.
  Eigen::MatrixXd flat(3, 3);
  flat << 0, 0, 0, 1, 1, 1, 2, 2, 2;
  CHECK(gp::area_centroid(flat, F.topRows(1)).norm() == 0.0);
}
