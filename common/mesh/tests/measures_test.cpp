#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "mesh/measures.h"
#include "testing/test_meshes.h"

TEST_CASE("area-weighted percentiles count area, not faces", "[mesh]") {
  // Nine small faces at 1.0 and one face as large as all of them at 2.0: by
  // face count the median is 1.0, by area it sits at the boundary.
  Eigen::VectorXd values(10), weights(10);
  values << 2.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0;
  weights << 9.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0;
  CHECK(gp::area_weighted_percentile(values, weights, 0.5) == 1.0);
  CHECK(gp::area_weighted_percentile(values, weights, 0.51) == 2.0);
  CHECK(gp::area_weighted_percentile(values, weights, 0.0) == 1.0);
  CHECK(gp::area_weighted_percentile(values, weights, 1.0) == 2.0);
  // Zero weights are never reached before a weighted value above them.
  Eigen::VectorXd v(3), w(3);
  v << 5.0, 3.0, 4.0;
  w << 0.0, 1.0, 1.0;
  CHECK(gp::area_weighted_percentile(v, w, 0.5) == 3.0);
  CHECK(gp::area_weighted_percentile(v, w, 0.99) == 4.0);
  // A fraction beyond 1 (or a sum rounded short) gives the largest value.
  CHECK(gp::area_weighted_percentile(v, w, 1.5) == 5.0);
  CHECK(gp::area_weighted_percentile(Eigen::VectorXd(), Eigen::VectorXd(), 0.5) == 0.0);
}

TEST_CASE("mesh_area sums the face areas, at tiny and huge scales", "[mesh]") {
  const gp::Mesh grid = gp::testing::make_grid(3, 2, 3.0, 2.0);
  for (double scale : {1e-6, 1.0, 1e6}) {
    const Eigen::MatrixXd V = scale * grid.V;
    CHECK(gp::mesh_area(V, grid.F) == Approx(6.0 * scale * scale).epsilon(1e-12));
    CHECK(gp::mesh_area(V, grid.F) == Approx(gp::face_areas(V, grid.F).sum()).epsilon(1e-14));
  }
  // A degenerate triangle adds nothing; a NaN corner makes the total NaN.
  Eigen::MatrixXd V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  const Eigen::MatrixXi F = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  CHECK(gp::mesh_area(V, F) == 0.0);
  V(2, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK(std::isnan(gp::mesh_area(V, F)));
}
