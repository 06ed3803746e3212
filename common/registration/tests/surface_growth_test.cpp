#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "core/error.h"
#include "registration/surface_growth.h"
#include "testing/test_meshes.h"

using namespace gp;

TEST_CASE("a rigid motion grows no neighbourhood and a uniform scale grows each by its square", "[surface_growth]") {
  const Mesh g = testing::make_grid(20, 20, 0.5, 0.5);
  Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::MatrixXd moved = (g.V * R.transpose()).rowwise() + Eigen::RowVector3d(3.0, -1.0, 2.0);
  const SurfaceGrowth rigid = surface_growth(g.V, moved, g.F, 0.05);
  CHECK(rigid.largest.factor == Approx(1.0).epsilon(1e-12));
  CHECK(rigid.smallest.factor == Approx(1.0).epsilon(1e-12));
  CHECK(rigid.share_above_1_25 == 0.0);
  // Huge and tiny scales alike: the factor is a ratio of areas.
  for (const double s : {1e-4, 1.3, 1e4}) {
    INFO("scale " << s);
    const SurfaceGrowth scaled = surface_growth(g.V, s * g.V, g.F, 0.05);
    CHECK(scaled.largest.factor == Approx(s * s).epsilon(1e-9));
    CHECK(scaled.smallest.factor == Approx(s * s).epsilon(1e-9));
    CHECK(scaled.p99 == Approx(s * s).epsilon(1e-9));
    CHECK(scaled.share_above_1_25 == (s * s > 1.25 ? 1.0 : 0.0));
  }
}

TEST_CASE("a stretched half of a sheet is found where it is stretched", "[surface_growth]") {
  // A 0.5 m square grid in x and z, its half beyond x = 0.25 stretched to twice its width: faces there
  // double their area, those on the other side keep theirs.
  const Mesh g = testing::make_grid(40, 40, 0.5, 0.5);
  Eigen::MatrixXd V = g.V;
  for (int v = 0; v < V.rows(); ++v)
    if (V(v, 0) > 0.25) V(v, 0) = 0.25 + 2.0 * (V(v, 0) - 0.25);
  const double radius = 0.04;
  const SurfaceGrowth s = surface_growth(g.V, V, g.F, radius);
  CHECK(s.largest.factor == Approx(2.0).epsilon(1e-9));
  CHECK(s.largest.at.x() > 0.25);
  CHECK(s.smallest.factor == Approx(1.0).epsilon(1e-9));
  CHECK(s.smallest.at.x() < 0.25);
  CHECK(s.p99 == Approx(2.0).epsilon(1e-9));
  // About half the sheet grows by more than a quarter (the band within the radius of the line in
  // between grows by less on its near side).
  CHECK(s.share_above_1_25 > 0.45);
  CHECK(s.share_above_1_25 < 0.55);
}

TEST_CASE("surface growth skips degenerate triangles and rejects bad input", "[surface_growth][hard]") {
  Mesh g = testing::make_grid(6, 6, 0.3, 0.3);
  Eigen::MatrixXd V = g.V;
  // One triangle collapsed to a segment in the reference: no area to compare, the rest still measured.
  g.V.row(g.F(0, 2)) = g.V.row(g.F(0, 0));
  V.row(g.F(0, 2)) = V.row(g.F(0, 0));
  const SurfaceGrowth s = surface_growth(g.V, 1.1 * V, g.F, 0.05);
  CHECK(std::isfinite(s.largest.factor));
  CHECK(s.smallest.factor == Approx(1.21).epsilon(1e-9));
  CHECK_THROWS_AS(surface_growth(g.V, V, g.F, 0.0), UsageError);
  CHECK_THROWS_AS(surface_growth(g.V, V.topRows(3), g.F, 0.05), UsageError);
  // A pose with a NaN vertex: its faces' areas are NaN, and no neighbourhood holding one is the
  // largest or the smallest.
  Eigen::MatrixXd bad = 1.1 * V;
  bad(5, 1) = std::numeric_limits<double>::quiet_NaN();
  const SurfaceGrowth n = surface_growth(g.V, bad, g.F, 0.05);
  CHECK(std::isfinite(n.smallest.factor));
  CHECK(std::isfinite(n.largest.factor));
  CHECK(n.largest.factor == Approx(1.21).epsilon(1e-9));
}
