#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "core/error.h"
#include "interp/deformation_gradient.h"
#include "interp/gradient_poisson.h"
#include "interp/polar_decomposition.h"
#include "interp/rotation_log.h"
#include "interp_fixtures.h"
#include "testing/test_meshes.h"

using interp_test::deg;
using interp_test::kPi;
using interp_test::rot;

namespace {

std::vector<Eigen::Vector3d> test_axes() {
  return {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(),
          Eigen::Vector3d(1, 2, 3).normalized(), Eigen::Vector3d(-0.3, 0.1, 0.95).normalized(),
          Eigen::Vector3d(1e-9, 1, -1e-9).normalized()};
}

}  // namespace

TEST_CASE("rotation log and exp invert each other at every angle, including 0 and 180 degrees",
          "[interp][rotation]") {
  const std::vector<double> angles = {0.0,        1e-12,      1e-7,        1e-3,        0.5,
                                      kPi / 2,    2.0,        kPi - 1e-3,  kPi - 1e-7,  kPi - 1e-12,
                                      kPi};
  for (const Eigen::Vector3d& axis : test_axes())
    for (double angle : angles) {
      const Eigen::Matrix3d R = rot(axis, angle);
      const Eigen::Vector3d w = gp::rotation_log(R);
      CHECK(w.norm() == Approx(angle).margin(1e-9));
      CHECK((gp::rotation_exp(w) - R).norm() < 1e-12);
      if (angle > 1e-6 && angle < kPi - 1e-6) CHECK((w - angle * axis).norm() < 1e-9);
    }
  // exp of angles beyond pi is still a rotation (a long way round).
  const Eigen::Vector3d w(0.0, deg(270), 0.0);
  CHECK((gp::rotation_exp(w) - rot(Eigen::Vector3d::UnitY(), deg(-90))).norm() < 1e-12);
}

TEST_CASE("the closest log branch continues a rotation past 180 degrees", "[interp][rotation]") {
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  // 270 degrees: the principal log says -90; next to a neighbour at 260 the
  // branch must be +270.
  const Eigen::Vector3d principal = gp::rotation_log(rot(y, deg(270)));
  CHECK((principal - deg(-90) * y).norm() < 1e-9);
  CHECK((gp::closest_log_branch(principal, deg(260) * y) - deg(270) * y).norm() < 1e-9);
  // Near the reference, the principal branch is kept.
  CHECK((gp::closest_log_branch(principal, deg(-80) * y) - principal).norm() < 1e-12);
  // Two full turns away.
  CHECK((gp::closest_log_branch(deg(10) * y, deg(700) * y) - deg(730) * y).norm() < 1e-9);
  // Identity next to a full turn stays a full turn about the neighbour's axis.
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 1, 0).normalized();
  CHECK((gp::closest_log_branch(Eigen::Vector3d::Zero(), deg(355) * axis) - 2 * kPi * axis).norm() <
        1e-9);
  // Every branch is the same rotation.
  const Eigen::Vector3d b = gp::closest_log_branch(principal, deg(-500) * y);
  CHECK((gp::rotation_exp(b) - rot(y, deg(270))).norm() < 1e-12);
}

TEST_CASE("polar decomposition gives a rotation and a symmetric stretch", "[interp][polar]") {
  Eigen::Matrix3d R, S;
  const Eigen::Matrix3d Rtrue = rot(Eigen::Vector3d(1, -2, 0.5), deg(140));
  Eigen::Matrix3d Strue;
  Strue << 2.0, 0.3, 0.0, 0.3, 0.5, 0.1, 0.0, 0.1, 1.2;  // SPD
  gp::polar_decomposition(Rtrue * Strue, R, S);
  CHECK((R - Rtrue).norm() < 1e-12);
  CHECK((S - Strue).norm() < 1e-12);
  // A reflection still yields a proper rotation; R S reproduces Q.
  const Eigen::Matrix3d Q = Eigen::Vector3d(1, 1, -1).asDiagonal() * Rtrue;
  gp::polar_decomposition(Q, R, S);
  CHECK(R.determinant() == Approx(1.0).margin(1e-12));
  CHECK((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
  CHECK((R * S - Q).norm() < 1e-12);
  CHECK((S - S.transpose()).norm() < 1e-14);
  // Rank-deficient (a flattened triangle frame).
  gp::polar_decomposition(Eigen::Vector3d(1, 1, 0).asDiagonal(), R, S);
  CHECK(R.determinant() == Approx(1.0).margin(1e-12));
  CHECK(R.allFinite());
}

TEST_CASE("deformation gradients map pose A's triangles onto pose B's", "[interp][gradient]") {
  gp::Mesh m = gp::testing::make_icosphere(1);
  Eigen::MatrixXd V_B = m.V;
  for (Eigen::Index v = 0; v < V_B.rows(); ++v)
    V_B.row(v) = Eigen::RowVector3d(1.5 * m.V(v, 0) + 0.2 * m.V(v, 1), m.V(v, 1), 0.7 * m.V(v, 2));
  V_B = (V_B * rot(Eigen::Vector3d(0, 0, 1), deg(100)).transpose()).eval();
  std::vector<Eigen::Matrix3d> Q;
  std::vector<bool> valid;
  gp::deformation_gradients(m.V, V_B, m.F, Q, valid);
  for (int f = 0; f < m.F.rows(); ++f) {
    REQUIRE(valid[f]);
    const Eigen::Matrix3d WA = gp::triangle_frame(m.V, m.F, f), WB = gp::triangle_frame(V_B, m.F, f);
    CHECK((Q[f] * WA.leftCols<2>() - WB.leftCols<2>()).norm() < 1e-12);
    CHECK(Q[f].determinant() > 0.0);
  }
  // A collapsed triangle in B is flagged, not inverted.
  Eigen::MatrixXd V_C = m.V;
  V_C.row(m.F(3, 2)) = 0.5 * (V_C.row(m.F(3, 0)) + V_C.row(m.F(3, 1)));
  gp::deformation_gradients(m.V, V_C, m.F, Q, valid);
  CHECK_FALSE(valid[3]);
  CHECK(Q[3] == Eigen::Matrix3d::Identity());
}

TEST_CASE("consistent rotation logs follow a 270 degree twist along a tube", "[interp][rotation]") {
  const gp::Mesh tube = gp::testing::make_open_cylinder(12, 90, 0.05, 2.0);
  const Eigen::MatrixXd V_twist = interp_test::twist_tube(tube.V, 270.0, 2.0);
  std::vector<Eigen::Matrix3d> Q, R(tube.F.rows());
  std::vector<bool> valid;
  gp::deformation_gradients(tube.V, V_twist, tube.F, Q, valid);
  Eigen::Matrix3d S;
  for (int f = 0; f < tube.F.rows(); ++f) gp::polar_decomposition(Q[f], R[f], S);
  const Eigen::MatrixXd omega = gp::consistent_rotation_logs(R, valid, tube.F);
  // The twist angle of a face grows with its height; the logs must follow it
  // beyond 180 degrees rather than wrap to negative angles.
  double max_error = 0.0;
  for (int f = 0; f < tube.F.rows(); ++f) {
    const double y = (tube.V(tube.F(f, 0), 1) + tube.V(tube.F(f, 1), 1) + tube.V(tube.F(f, 2), 1)) / 3;
    max_error = std::max(max_error, std::abs(omega(f, 1) - deg(270) * y / 2.0));
  }
  CHECK(max_error < deg(3));
  CHECK(omega.col(1).maxCoeff() > deg(260));
  // Principal logs alone would wrap: their largest angle is at most 180.
  double principal_max = 0.0;
  for (int f = 0; f < tube.F.rows(); ++f) principal_max = std::max(principal_max, gp::rotation_log(R[f]).norm());
  CHECK(principal_max <= kPi + 1e-9);
}

TEST_CASE("the Poisson solve recovers a mesh from its own edges, up to translation", "[interp][poisson]") {
  gp::Mesh m = gp::testing::make_torus(24, 12);
  // Rest shape differs from the target (the operator is built on another pose).
  Eigen::MatrixXd V_target = m.V;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    V_target.row(v) = Eigen::RowVector3d(m.V(v, 0) * (1 + 0.3 * m.V(v, 1)), 2.0 * m.V(v, 1) + 0.1 * m.V(v, 0) * m.V(v, 0),
                                         m.V(v, 2));
  gp::GradientPoissonSolver poisson(m.V, m.F);
  CHECK(poisson.component_count() == 1);
  Eigen::MatrixXd V;
  poisson.solve(gp::face_edges(V_target, m.F), V);
  const Eigen::RowVector3d shift = V_target.row(0) - V.row(0);
  CHECK((V.rowwise() + shift - V_target).cwiseAbs().maxCoeff() < 1e-9);
  CHECK(V.row(0).norm() == 0.0);  // the pinned vertex
  CHECK(poisson.factorization_seconds() >= 0.0);
  CHECK_THROWS_AS(poisson.solve(gp::FaceEdges(3, 6), V), gp::UsageError);
}

TEST_CASE("the Poisson solve handles several components and unused vertices", "[interp][poisson]") {
  const gp::Mesh a = gp::testing::make_icosphere(1), b = gp::testing::make_icosphere(2);
  Eigen::MatrixXd V(a.V.rows() + b.V.rows() + 1, 3);
  V << a.V, (b.V.rowwise() + Eigen::RowVector3d(3, 0, 0)), Eigen::RowVector3d(9, 9, 9);
  Eigen::MatrixXi F(a.F.rows() + b.F.rows(), 3);
  F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  gp::GradientPoissonSolver poisson(V, F);
  CHECK(poisson.component_count() == 2);
  CHECK(poisson.vertex_component()(V.rows() - 1) == -1);
  const Eigen::MatrixXd V_scaled = 2.0 * V;
  Eigen::MatrixXd X;
  poisson.solve(gp::face_edges(V_scaled, F), X);
  // Each component matches up to its own translation.
  const Eigen::RowVector3d s0 = V_scaled.row(0) - X.row(0);
  const int first_b = static_cast<int>(a.V.rows());
  const Eigen::RowVector3d s1 = V_scaled.row(first_b) - X.row(first_b);
  CHECK((X.topRows(first_b).rowwise() + s0 - V_scaled.topRows(first_b)).cwiseAbs().maxCoeff() < 1e-9);
  CHECK((X.middleRows(first_b, b.V.rows()).rowwise() + s1 - V_scaled.middleRows(first_b, b.V.rows()))
            .cwiseAbs()
            .maxCoeff() < 1e-9);
  CHECK(X.row(V.rows() - 1).norm() == 0.0);
}

TEST_CASE("a degenerate rest triangle is a geometry error naming the face", "[interp][poisson]") {
  gp::Mesh m = gp::testing::make_icosphere(1);
  m.V.row(m.F(5, 2)) = m.V.row(m.F(5, 0));
  try {
    gp::GradientPoissonSolver poisson(m.V, m.F);
    FAIL("no error");
  } catch (const gp::GeometryError& e) {
    CHECK(e.where().find("face") != std::string::npos);
  }
}
