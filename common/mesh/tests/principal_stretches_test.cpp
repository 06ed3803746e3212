#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "core/error.h"
#include "mesh/principal_stretches.h"
#include "testing/test_meshes.h"

TEST_CASE("closed-form 2x2 singular values agree with an SVD", "[mesh]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double scale : {1e-8, 1.0, 1e8}) {
    for (int i = 0; i < 200; ++i) {
      Eigen::Matrix2d J;
      J << u(rng), u(rng), u(rng), u(rng);
      J *= scale;
      const Eigen::Vector2d s = gp::singular_values_2x2(J);
      const Eigen::Vector2d ref = Eigen::JacobiSVD<Eigen::Matrix2d>(J).singularValues();
      CHECK(s(0) >= s(1));
      CHECK(s(1) >= 0.0);
      CHECK(s(0) == Approx(ref(0)).epsilon(1e-12));
      // The smaller value loses digits to cancellation when J is near
      // singular: its error is relative to s1.
      CHECK(std::abs(s(1) - ref(1)) <= 1e-12 * ref(0));
    }
  }
}

TEST_CASE("2x2 singular values: zero, rank one, reflections and NaN", "[mesh]") {
  CHECK(gp::singular_values_2x2(Eigen::Matrix2d::Zero()) == Eigen::Vector2d::Zero());
  // Rank one: a triangle collapsed to a segment.
  Eigen::Matrix2d R1;
  R1 << 3.0, 4.0, 0.0, 0.0;
  const Eigen::Vector2d r1 = gp::singular_values_2x2(R1);
  CHECK(r1(0) == Approx(5.0).epsilon(1e-15));
  CHECK(r1(1) == Approx(0.0).margin(1e-15));
  // A reflection (an inverted flat triangle) has the same values as the map itself.
  Eigen::Matrix2d A;
  A << 1.2, 0.3, -0.1, 0.9;
  const Eigen::Matrix2d mirror = Eigen::Vector2d(1.0, -1.0).asDiagonal();
  const Eigen::Vector2d a = gp::singular_values_2x2(A), m = gp::singular_values_2x2(mirror * A);
  CHECK(m(0) == Approx(a(0)).epsilon(1e-14));
  CHECK(m(1) == Approx(a(1)).epsilon(1e-14));
  Eigen::Matrix2d N = A;
  N(1, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK(std::isnan(gp::singular_values_2x2(N)(0)));
}

TEST_CASE("principal stretches of a sheet stretched along a direction, moved rigidly", "[mesh]") {
  const gp::Mesh grid = gp::testing::make_grid(4, 3, 0.2, 0.15);  // y = 0
  // Stretch by 1.3 along (1, 0, 1)/sqrt2 and compress by 0.8 across it in the
  // sheet's plane, then rotate the result about a tilted axis and translate it.
  const Eigen::Vector3d d = Eigen::Vector3d(1.0, 0.0, 1.0).normalized(), c(-d.z(), 0.0, d.x());
  const Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity() + 0.3 * d * d.transpose() - 0.2 * c * c.transpose();
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -1.0, 0.5).normalized()).matrix();
  for (double scale : {1e-5, 1.0, 1e5}) {
    const Eigen::MatrixXd V_rest = scale * grid.V;
    const Eigen::MatrixXd V_def =
        (V_rest * (rotation * stretch).transpose()).rowwise() + scale * Eigen::RowVector3d(1.0, 2.0, 3.0);
    const Eigen::MatrixXd S = gp::principal_stretches(V_rest, V_def, grid.F);
    REQUIRE(S.rows() == grid.F.rows());
    for (int f = 0; f < S.rows(); ++f) {
      CHECK(S(f, 0) == Approx(1.3).epsilon(1e-9));
      CHECK(S(f, 1) == Approx(0.8).epsilon(1e-9));
    }
  }
}

TEST_CASE("principal stretches name a degenerate rest face and take collapsed deformed ones", "[mesh]") {
  const gp::Mesh grid = gp::testing::make_grid(2, 2, 1.0, 1.0);
  Eigen::MatrixXd V_rest = grid.V;
  // Deformed: every vertex onto one point, so every face collapses to zero.
  const Eigen::MatrixXd collapsed = Eigen::MatrixXd::Zero(grid.V.rows(), 3);
  CHECK(gp::principal_stretches(V_rest, collapsed, grid.F).cwiseAbs().maxCoeff() == 0.0);
  // A rest face with its corners on a line: the error names it.
  const int f = 3;
  V_rest.row(grid.F(f, 2)) = 0.5 * (V_rest.row(grid.F(f, 0)) + V_rest.row(grid.F(f, 1)));
  try {
    gp::principal_stretches(V_rest, grid.V, grid.F);
    FAIL("a degenerate rest face must throw");
  } catch (const gp::GeometryError& e) {
    CHECK(std::string(e.what()).find("degenerate") != std::string::npos);
    CHECK(e.where().find("face") != std::string::npos);
  }
  V_rest = grid.V;
  V_rest(0, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(gp::principal_stretches(V_rest, grid.V, grid.F), gp::GeometryError);
}
