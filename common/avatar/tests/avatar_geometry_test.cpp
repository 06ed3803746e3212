// Building blocks of the generated body: girth measurement, polygonization,
// decimation, skeleton and skinning, on meshes built by the tests themselves.
#include <catch2/catch.hpp>
#include <cmath>

#include "avatar/body_checks.h"
#include "avatar/girth.h"
#include "avatar/isosurface.h"
#include "avatar/simplify.h"
#include "avatar/skeleton.h"
#include "avatar/skinning.h"
#include "core/error.h"
#include "geometry/self_intersections.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "testing/test_meshes.h"

namespace {
constexpr double kPi = 3.14159265358979323846;

void require_closed_genus(const gp::Mesh& m, int euler) {
  CHECK(gp::boundary_loops(m.F).empty());
  const Eigen::MatrixXi TT = gp::triangle_adjacency(m.F);
  CHECK((TT.array() >= 0).all());
  Eigen::VectorXi comp;
  CHECK(gp::face_components(m.F, comp) == 1);
  CHECK(gp::euler_characteristic(m.F) == euler);
}
}  // namespace

TEST_CASE("convex hull perimeter bridges concavities", "[avatar][girth]") {
  // Unit square with a notch: the hull is the square.
  std::vector<Eigen::Vector2d> p = {{0, 0}, {1, 0}, {1, 1}, {0.5, 0.2}, {0, 1}};
  CHECK(gp::convex_hull_perimeter(p) == Approx(4.0).epsilon(1e-12));
  // Duplicates and collinear points do not count.
  p = {{0, 0}, {0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}, {1, 1}};
  CHECK(gp::convex_hull_perimeter(p) == Approx(6.0).epsilon(1e-12));
  CHECK(gp::convex_hull_perimeter({}) == 0.0);
  CHECK(gp::convex_hull_perimeter({{1, 1}}) == 0.0);
}

TEST_CASE("mesh girth of a sphere slice is the circle's perimeter", "[avatar][girth]") {
  const gp::Mesh s = gp::testing::make_icosphere(5, 0.3);
  for (double y : {0.0, 0.1, -0.2}) {
    const double r = std::sqrt(0.09 - y * y);
    double loop = 0;
    const double g = gp::mesh_girth(s.V, s.F, Eigen::Vector3d(0, y, 0), Eigen::Vector3d(0, 1, 0), &loop);
    // An inscribed polygon is shorter than the circle by O(h^2).
    CHECK(g == Approx(2 * kPi * r).epsilon(2e-3));
    CHECK(g <= 2 * kPi * r + 1e-9);
    CHECK(loop == Approx(g).epsilon(1e-6));
  }
  // A plane through a vertex still gives closed loops; a point outside
  // every loop gives -1.
  const double y_vertex = s.V(0, 1);
  CHECK(gp::mesh_girth(s.V, s.F, Eigen::Vector3d(0, y_vertex, 0), Eigen::Vector3d(0, 1, 0)) >= 0.0);
  CHECK(gp::mesh_girth(s.V, s.F, Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(0, 1, 0)) == -1.0);
  // Two spheres side by side: the slice loop around the chosen centre only.
  gp::Mesh two = s;
  two.V.conservativeResize(2 * s.V.rows(), 3);
  two.V.bottomRows(s.V.rows()) = s.V.rowwise() + Eigen::RowVector3d(1.0, 0, 0);
  two.F.conservativeResize(2 * s.F.rows(), 3);
  two.F.bottomRows(s.F.rows()) = s.F.array() + static_cast<int>(s.V.rows());
  const double g1 = gp::mesh_girth(two.V, two.F, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0));
  CHECK(g1 == Approx(2 * kPi * 0.3).epsilon(2e-3));
}

TEST_CASE("marching tetrahedra gives a closed oriented surface", "[avatar][isosurface]") {
  SECTION("sphere") {
    auto f = [](const Eigen::Vector3d& p) { return p.norm() - 0.5; };
    gp::IsosurfaceOptions o;
    o.cell = 0.05;
    const gp::Mesh m =
        gp::marching_tetrahedra(f, Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), o);
    require_closed_genus(m, 2);
    CHECK(gp::signed_volume(m.V, m.F) == Approx(4.0 / 3.0 * kPi * 0.125).epsilon(0.03));
    CHECK_FALSE(gp::has_self_intersection(m.V, m.F));
  }
  SECTION("torus, with the grid at every phase") {
    for (double shift : {0.0, 0.013, 0.031}) {
      auto f = [](const Eigen::Vector3d& p) {
        const double q = std::hypot(p.x(), p.z()) - 0.4;
        return std::hypot(q, p.y()) - 0.15;
      };
      gp::IsosurfaceOptions o;
      o.cell = 0.04;
      const gp::Mesh m = gp::marching_tetrahedra(f, Eigen::Vector3d::Constant(-0.7 + shift),
                                                 Eigen::Vector3d::Constant(0.7), o);
      require_closed_genus(m, 0);
      CHECK(gp::signed_volume(m.V, m.F) > 0);
    }
  }
  SECTION("a field that is zero on grid points stays manifold") {
    // The plane x = 0.5 passes through grid points exactly.
    auto f = [](const Eigen::Vector3d& p) {
      return std::max({std::abs(p.x()) - 0.5, std::abs(p.y()) - 0.5, std::abs(p.z()) - 0.5});
    };
    gp::IsosurfaceOptions o;
    o.cell = 0.25;
    o.lipschitz = 1e9;  // no culling
    const gp::Mesh m =
        gp::marching_tetrahedra(f, Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), o);
    require_closed_genus(m, 2);
  }
  SECTION("non-finite field values are a numerical error") {
    auto f = [](const Eigen::Vector3d& p) { return p.x() > 0.2 ? std::nan("") : p.norm() - 0.5; };
    gp::IsosurfaceOptions o;
    o.cell = 0.1;
    CHECK_THROWS_AS(
        gp::marching_tetrahedra(f, Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), o),
        gp::NumericalError);
  }
}

TEST_CASE("decimation keeps the surface closed, oriented and close", "[avatar][simplify]") {
  SECTION("sphere") {
    const gp::Mesh s = gp::testing::make_icosphere(5, 1.0);  // 10242 vertices
    const gp::Mesh d = gp::simplify_mesh(s, 500);
    CHECK(d.V.rows() == 500);
    require_closed_genus(d, 2);
    for (Eigen::Index i = 0; i < d.V.rows(); ++i) CHECK(d.V.row(i).norm() == Approx(1.0).epsilon(0.01));
    CHECK(gp::signed_volume(d.V, d.F) == Approx(gp::signed_volume(s.V, s.F)).epsilon(0.01));
    CHECK_FALSE(gp::has_self_intersection(d.V, d.F));
  }
  SECTION("torus keeps its genus") {
    const gp::Mesh t = gp::testing::make_torus(120, 40, 1.0, 0.3);
    const gp::Mesh d = gp::simplify_mesh(t, 600);
    CHECK(d.V.rows() == 600);
    require_closed_genus(d, 0);
  }
  SECTION("a mesh already small enough is returned unchanged") {
    const gp::Mesh s = gp::testing::make_icosphere(1, 1.0);
    const gp::Mesh d = gp::simplify_mesh(s, 1000);
    CHECK(d.V == s.V);
    CHECK(d.F == s.F);
  }
}

TEST_CASE("closed genus-0 check names the defect", "[avatar][checks]") {
  gp::Mesh s = gp::testing::make_icosphere(1, 1.0);
  CHECK_NOTHROW(gp::check_closed_genus0(s.F, "sphere"));
  Eigen::MatrixXi open = s.F.topRows(s.F.rows() - 1);
  CHECK_THROWS_WITH(gp::check_closed_genus0(open, "cut sphere"), Catch::Contains("boundary edge"));
  Eigen::MatrixXi flipped = s.F;
  std::swap(flipped(0, 1), flipped(0, 2));
  CHECK_THROWS_AS(gp::check_closed_genus0(flipped, "flipped"), gp::GeometryError);
  const gp::Mesh t = gp::testing::make_torus(12, 8);
  CHECK_THROWS_WITH(gp::check_closed_genus0(t.F, "torus"), Catch::Contains("Euler characteristic 0"));
}

TEST_CASE("forward kinematics rotates about the joints", "[avatar][skeleton]") {
  gp::Skeleton sk;
  sk.names = gp::avatar_joint_names();
  sk.parents = gp::avatar_joint_parents();
  sk.rest = Eigen::MatrixXd::Random(gp::kJointCount, 3);
  gp::JointRotations r(gp::kJointCount, Eigen::Quaterniond::Identity());
  r[gp::kLShoulder] = gp::rotation_from_degrees(Eigen::Vector3d(0, 0, 90));
  r[gp::kLElbow] = gp::rotation_from_degrees(Eigen::Vector3d(30, 0, 0));
  const auto M = gp::forward_kinematics(sk, r);
  const Eigen::MatrixXd P = gp::posed_joints(sk, M);
  // Joints above the rotated ones stay; the rotated joint itself stays.
  CHECK((P.row(gp::kChest) - sk.rest.row(gp::kChest)).norm() < 1e-12);
  CHECK((P.row(gp::kLShoulder) - sk.rest.row(gp::kLShoulder)).norm() < 1e-12);
  CHECK((P.row(gp::kRElbow) - sk.rest.row(gp::kRElbow)).norm() < 1e-12);
  // Bone lengths are kept.
  for (int j = 1; j < gp::kJointCount; ++j) {
    const int p = sk.parents[j];
    CHECK((P.row(j) - P.row(p)).norm() == Approx((sk.rest.row(j) - sk.rest.row(p)).norm()).epsilon(1e-12));
  }
  // 90 degrees about +z takes the elbow offset (x, y) to (-y, x).
  const Eigen::Vector3d d0 = (sk.rest.row(gp::kLElbow) - sk.rest.row(gp::kLShoulder)).transpose();
  const Eigen::Vector3d d1 = (P.row(gp::kLElbow) - P.row(gp::kLShoulder)).transpose();
  CHECK((d1 - Eigen::Vector3d(-d0.y(), d0.x(), d0.z())).norm() < 1e-12);
  // Angle order: x first, then z.
  const Eigen::Quaterniond q = gp::rotation_from_degrees(Eigen::Vector3d(90, 0, 90));
  CHECK((q * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm() < 1e-12);
  CHECK((q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm() < 1e-12);
}

TEST_CASE("dual-quaternion skinning is exact for rigid motions and keeps tubes round", "[avatar][skinning]") {
  const gp::Mesh s = gp::testing::make_icosphere(3, 0.2);
  SECTION("one bone: the rigid transform itself") {
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(s.V.rows(), 2);
    W.col(1).setOnes();
    std::vector<gp::RigidTransform> bones(2);
    bones[1].q = gp::rotation_from_degrees(Eigen::Vector3d(10, 170, -40));
    bones[1].t = Eigen::Vector3d(0.3, -1, 2);
    const Eigen::MatrixXd P = gp::dual_quaternion_skinning(s.V, W, bones);
    for (Eigen::Index i = 0; i < s.V.rows(); ++i)
      CHECK((P.row(i).transpose() - bones[1].apply(s.V.row(i).transpose())).norm() < 1e-12);
  }
  SECTION("half-half blend of a twist keeps the distance to the axis") {
    // Linear blending of a 180-degree twist collapses points to the axis
    // (candy wrapper); dual quaternions rotate them by 90 degrees instead.
    Eigen::MatrixXd W = Eigen::MatrixXd::Constant(s.V.rows(), 2, 0.5);
    std::vector<gp::RigidTransform> bones(2);
    bones[1].q = Eigen::Quaterniond(Eigen::AngleAxisd(kPi * 0.999, Eigen::Vector3d::UnitY()));
    const Eigen::MatrixXd P = gp::dual_quaternion_skinning(s.V, W, bones);
    for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
      const double r0 = std::hypot(s.V(i, 0), s.V(i, 2)), r1 = std::hypot(P(i, 0), P(i, 2));
      CHECK(r1 == Approx(r0).margin(1e-9));
      CHECK(P(i, 1) == Approx(s.V(i, 1)).margin(1e-12));
    }
  }
}
