// Body proximity: signed distances with pseudo-normal signs (sharp cube edges and
// corners), culling, warm starts and skips, the collision response, and a cloth
// draped over a sphere that never sinks into the comfort offset.
#include <catch2/catch.hpp>

#include <cmath>
#include <future>
#include <limits>
#include <random>

#include <CGAL/Simple_cartesian.h>
#include <Eigen/Geometry>

#include "cloth/cloth_simulator.h"
#include "collision/body_collider.h"
#include "core/error.h"
#include "testing/test_meshes.h"
#include "cloth/tests/function_contact.h"

using namespace gp::collision;

namespace {

// Axis-aligned cube [-h, h]^3, outward oriented, 12 triangles.
gp::Mesh make_cube(double h) {
  gp::Mesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1 ? h : -h), (i & 2 ? h : -h), (i & 4 ? h : -h);
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3,  // z = -h
      4, 5, 6, 5, 7, 6,     // z = +h
      0, 1, 4, 1, 5, 4,     // y = -h
      2, 6, 3, 3, 6, 7,     // y = +h
      0, 4, 2, 2, 4, 6,     // x = -h
      1, 3, 5, 3, 7, 5;     // x = +h
  return m;
}

// A sphere of radius 0.3 m with radial bumps of 15 %: a closed surface with
// many near-ties between distant faces.
gp::Mesh lumpy_sphere() {
  gp::Mesh body = gp::testing::make_icosphere(3, 0.3);
  for (int v = 0; v < body.V.rows(); ++v) {
    const Eigen::Vector3d p = body.V.row(v);
    body.V.row(v) *= 1.0 + 0.15 * std::sin(9.0 * p.x()) * std::cos(7.0 * p.y() + 3.0 * p.z());
  }
  return body;
}

double box_signed_distance(const Eigen::Vector3d& p, double h) {
  const Eigen::Vector3d q = p.cwiseAbs() - Eigen::Vector3d::Constant(h);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

}  // namespace

TEST_CASE("signed distance to a cube is exact, with correct signs at edges and corners", "[collision]") {
  const gp::Mesh cube = make_cube(0.5);
  BodyCollider collider(cube.F);
  collider.set_body(cube.V);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int wrong_sign = 0;
  double max_err = 0.0;
  for (int k = 0; k < 20000; ++k) {
    Eigen::Vector3d p(u(rng), u(rng), u(rng));
    // Half of the points near edges and corners, where face normals mislead.
    if (k % 2) p = p.cwiseSign().cwiseProduct(Eigen::Vector3d::Constant(0.5)) + 0.02 * p;
    const double exact = box_signed_distance(p, 0.5);
    const Proximity q = collider.query(p);
    max_err = std::max(max_err, std::abs(q.signed_distance - exact));
    if (std::abs(exact) > 1e-9 && (q.signed_distance > 0) != (exact > 0)) ++wrong_sign;
    CHECK(std::abs(q.outward.norm() - 1.0) < 1e-12);
  }
  CHECK(wrong_sign == 0);
  CHECK(max_err < 1e-12);
}

TEST_CASE("signed distance to a sphere mesh follows the analytic one", "[collision]") {
  const double r = 0.3;
  const gp::Mesh sphere = gp::testing::make_icosphere(4, r);
  BodyCollider collider(sphere.F);
  collider.set_body(sphere.V);
  // Chord error of the level-4 icosphere bounds the difference to the true sphere.
  const double chord = r * (1.0 - std::cos(0.5 * 1.1 * 3.14159265 / 40.0)) * 4.0;
  std::mt19937 rng(2);
  std::normal_distribution<double> n(0.0, 1.0);
  int wrong_sign = 0;
  for (int k = 0; k < 5000; ++k) {
    const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    const double radius = r * (0.5 + 1.0 * (k % 100) / 100.0);
    const Proximity q = collider.query(radius * dir);
    const double exact = radius - r;
    CHECK(std::abs(q.signed_distance - exact) <= chord + 1e-12);
    if (std::abs(exact) > chord && (q.signed_distance > 0) != (exact > 0)) ++wrong_sign;
  }
  CHECK(wrong_sign == 0);
  // Points at the mesh vertices pushed slightly in and out along the normal.
  for (int v = 0; v < sphere.V.rows(); v += 13) {
    const Eigen::Vector3d p = sphere.V.row(v);
    CHECK(collider.query(1.0001 * p).signed_distance > 0.0);
    CHECK(collider.query(0.9999 * p).signed_distance < 0.0);
  }
}

TEST_CASE("tree queries find the closest of all triangles, with and without hints", "[collision]") {
  // A lumpy closed surface (a sphere with radial bumps): many near-ties between
  // distant faces, where a traversal that prunes wrongly would show.
  const gp::Mesh body = lumpy_sphere();
  BodyCollider collider(body.F);
  collider.set_body(body.V);
  using K = CGAL::Simple_cartesian<double>;
  auto brute_force = [&body](const Eigen::Vector3d& p) {
    double best = std::numeric_limits<double>::infinity();
    for (int f = 0; f < body.F.rows(); ++f) {
      auto corner = [&](int k) {
        return K::Point_3(body.V(body.F(f, k), 0), body.V(body.F(f, k), 1), body.V(body.F(f, k), 2));
      };
      best = std::min(best, CGAL::squared_distance(K::Point_3(p.x(), p.y(), p.z()),
                                                   K::Triangle_3(corner(0), corner(1), corner(2))));
    }
    return std::sqrt(best);
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::uniform_int_distribution<int> face(0, static_cast<int>(body.F.rows()) - 1);
  double worst = 0.0;
  for (int k = 0; k < 1500; ++k) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const double exact = brute_force(p);
    // No hint, and a hint at a random (usually far) face.
    worst = std::max(worst, std::abs(std::abs(collider.query(p).signed_distance) - exact));
    worst = std::max(worst, std::abs(std::abs(collider.query(p, face(rng)).signed_distance) - exact));
  }
  CHECK(worst <= 1e-14);
}

TEST_CASE("a frame prepared on another thread during queries answers as set_body does", "[collision]") {
  // The lumpy sphere, then the same sphere moved by 4 cm and turned by 0.3 rad
  // about z (with a body velocity). One collider prepares the moved frame on a
  // second thread while it answers 2,000 queries on the first frame; another
  // is set to the moved frame directly. Expectation: the first frame's answers
  // are undisturbed (equal to a third collider's), and after set_body(frame)
  // every answer (distance, closest point, face, contacts with the body's
  // normal speed) equals the direct collider's to the bit.
  const gp::Mesh body = lumpy_sphere();
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::MatrixXd V_moved = (body.V * turn.transpose()).rowwise() + Eigen::RowVector3d(0.04, 0.0, 0.0);
  const Eigen::MatrixXd velocity = (V_moved - body.V) / 0.01;
  BodyCollider pipelined(body.F), direct(body.F), reference(body.F);
  pipelined.set_body(body.V);
  reference.set_body(body.V);
  direct.set_body(V_moved, &velocity);

  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<Eigen::Vector3d> points(2000);
  for (auto& p : points) p = Eigen::Vector3d(u(rng), u(rng), u(rng));
  std::future<BodyFrame> next =
      std::async(std::launch::async, [&] { return pipelined.prepare(V_moved, &velocity); });
  int same_during = 0;
  for (const Eigen::Vector3d& p : points) {
    const Proximity a = pipelined.query(p), b = reference.query(p);
    same_during += a.face == b.face && a.signed_distance == b.signed_distance && a.closest == b.closest;
  }
  CHECK(same_during == static_cast<int>(points.size()));
  pipelined.set_body(next.get());
  int same_after = 0;
  Eigen::MatrixXd X(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t k = 0; k < points.size(); ++k) {
    const Proximity a = pipelined.query(points[k]), b = direct.query(points[k]);
    same_after += a.face == b.face && a.signed_distance == b.signed_distance && a.closest == b.closest;
    X.row(static_cast<Eigen::Index>(k)) = points[k].transpose();
  }
  CHECK(same_after == static_cast<int>(points.size()));
  const std::vector<Contact> ca = pipelined.contacts(X, 0.05, 0.01), cb = direct.contacts(X, 0.05, 0.01);
  REQUIRE(ca.size() == cb.size());
  CHECK(!ca.empty());
  bool same_contacts = true;
  for (size_t k = 0; k < ca.size(); ++k) {
    same_contacts = same_contacts && ca[k].vertex == cb[k].vertex && ca[k].outward == cb[k].outward &&
                    ca[k].body_normal_speed == cb[k].body_normal_speed;
  }
  CHECK(same_contacts);
}

TEST_CASE("set_body rejects an empty frame and one prepared by another collider", "[collision]") {
  const gp::Mesh body = lumpy_sphere();
  BodyCollider a(body.F), b(body.F);
  CHECK_THROWS_AS(a.set_body(BodyFrame{}), gp::UsageError);
  CHECK_THROWS_AS(a.set_body(b.prepare(body.V)), gp::UsageError);
  Eigen::MatrixXd bad = body.V;
  bad(3, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(a.prepare(bad), gp::GeometryError);
  a.set_body(a.prepare(body.V));
  CHECK(a.query(Eigen::Vector3d(0.0, 0.0, 0.0)).signed_distance < 0.0);
}

TEST_CASE("contacts and resolve on two threads answer as on one", "[collision]") {
  // 3,000 points in a shell around the lumpy sphere (inside it, within the
  // offset and beyond), moved a little between five rounds of contacts()
  // then resolve() on a moving body (warm starts, skips, gap rays, crease
  // sides). Expectation: one thread and two give the same contacts, the same
  // projected positions and velocities and the same counts, to the bit.
  const gp::Mesh body = lumpy_sphere();
  BodyCollider one(body.F), two(body.F);
  two.set_threads(2);
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> radius(0.2, 0.42);
  Eigen::MatrixXd X(3000, 3), Vel = Eigen::MatrixXd::Zero(3000, 3);
  for (int i = 0; i < X.rows(); ++i) {
    const Eigen::Vector3d d(g(rng), g(rng), g(rng));
    X.row(i) = (radius(rng) * d.normalized()).transpose();
  }
  Eigen::MatrixXd X1 = X, X2 = X, V1 = Vel, V2 = Vel;
  bool same = true;
  size_t contacts_seen = 0;
  for (int round = 0; round < 5; ++round) {
    const Eigen::MatrixXd V_body = body.V * (1.0 + 0.01 * round);
    const Eigen::MatrixXd body_velocity = body.V * (0.01 / 0.01);
    one.set_body(V_body, &body_velocity);
    two.set_body(V_body, &body_velocity);
    const std::vector<Contact> c1 = one.contacts(X1, 0.02, 0.005), c2 = two.contacts(X2, 0.02, 0.005);
    same = same && c1.size() == c2.size();
    for (size_t k = 0; same && k < c1.size(); ++k) {
      same = c1[k].vertex == c2[k].vertex && c1[k].signed_distance == c2[k].signed_distance &&
             c1[k].outward == c2[k].outward && c1[k].offset == c2[k].offset &&
             c1[k].body_normal_speed == c2[k].body_normal_speed;
    }
    contacts_seen += c1.size();
    one.resolve(X1, V1, 0.02);
    two.resolve(X2, V2, 0.02);
    same = same && X1 == X2 && V1 == V2;
    for (int i = 0; i < X1.rows(); ++i) {
      const Eigen::RowVector3d step(0.002 * g(rng), 0.002 * g(rng), 0.002 * g(rng));
      X1.row(i) += step;
      X2.row(i) += step;
    }
  }
  CHECK(same);
  CHECK(contacts_seen > 1000);
  const CollisionStats& s1 = one.stats();
  const CollisionStats& s2 = two.stats();
  CHECK(s1.queries == s2.queries);
  CHECK(s1.skipped == s2.skipped);
  CHECK(s1.reused == s2.reused);
  CHECK(s1.projected == s2.projected);
  CHECK(s1.gap_rays == s2.gap_rays);
  CHECK(s1.creases == s2.creases);
  CHECK(s1.deepest_penetration == s2.deepest_penetration);
  CHECK(s1.projected > 100);
  CHECK_THROWS_AS(one.set_threads(0), gp::UsageError);
}

TEST_CASE("culling keeps the faces the garment can reach", "[collision]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(4, 0.3);
  // A small patch of points hovering 2 cm above the north pole.
  Eigen::MatrixXd garment(9, 3);
  for (int i = 0; i < 9; ++i) garment.row(i) << 0.03 * (i % 3 - 1), 0.32, 0.03 * (i / 3 - 1);
  const std::vector<int> faces = reachable_body_faces(sphere.V, sphere.F, garment, 0.05);
  CHECK(faces.size() > 4);
  CHECK(faces.size() < static_cast<size_t>(sphere.F.rows()) / 10);
  CHECK(std::is_sorted(faces.begin(), faces.end()));
  for (int f : faces) {
    const double y = (sphere.V.row(sphere.F(f, 0)) + sphere.V.row(sphere.F(f, 1)) + sphere.V.row(sphere.F(f, 2))).y() / 3.0;
    CHECK(y > 0.2);
  }
  // Queries against the culled set agree with the full body near the garment.
  BodyCollider culled(sphere.F, faces), full(sphere.F);
  culled.set_body(sphere.V);
  full.set_body(sphere.V);
  for (int i = 0; i < 9; ++i) {
    const Proximity a = culled.query(garment.row(i).transpose()), b = full.query(garment.row(i).transpose());
    CHECK(a.signed_distance == Approx(b.signed_distance).margin(1e-14));
    CHECK((a.closest - b.closest).norm() < 1e-14);
  }
  CHECK_THROWS_AS(BodyCollider(sphere.F, {-1}), gp::UsageError);
  CHECK_THROWS_AS(reachable_body_faces(sphere.V, sphere.F, garment, -1.0), gp::UsageError);
}

TEST_CASE("culling keeps exactly the faces meeting some garment vertex's cube", "[collision]") {
  using K = CGAL::Simple_cartesian<double>;
  const gp::Mesh sphere = gp::testing::make_icosphere(3, 0.3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.45, 0.45);
  Eigen::MatrixXd garment(60, 3);
  for (int i = 0; i < garment.rows(); ++i) garment.row(i) << u(rng), u(rng), u(rng);
  for (double reach : {0.0, 0.01, 0.05, 0.2, 2.0}) {
    std::vector<int> expected;
    for (int f = 0; f < sphere.F.rows(); ++f) {
      auto corner = [&](int k) {
        return K::Point_3(sphere.V(sphere.F(f, k), 0), sphere.V(sphere.F(f, k), 1), sphere.V(sphere.F(f, k), 2));
      };
      const K::Triangle_3 t(corner(0), corner(1), corner(2));
      for (int i = 0; i < garment.rows(); ++i) {
        const Eigen::RowVector3d p = garment.row(i);
        if (CGAL::do_intersect(t, CGAL::Bbox_3(p.x() - reach, p.y() - reach, p.z() - reach, p.x() + reach,
                                               p.y() + reach, p.z() + reach))) {
          expected.push_back(f);
          break;
        }
      }
    }
    INFO("reach " << reach);
    CHECK(reachable_body_faces(sphere.V, sphere.F, garment, reach) == expected);
  }
}

TEST_CASE("resolve projects to the offset, removes inward velocity, and skips far vertices", "[collision]") {
  const gp::Mesh cube = make_cube(0.5);
  BodyCollider collider(cube.F);
  collider.set_body(cube.V);
  Eigen::MatrixXd X(3, 3), Vel(3, 3);
  X << 0.1, 0.45, 0.0,   // inside, 5 cm under the top face
      0.0, 0.505, 0.2,   // outside but within the 1 cm offset
      0.0, 2.0, 0.0;     // far away
  Vel << 0.3, -1.0, 0.0, 0.0, 0.5, 0.0, 0.0, -1.0, 0.0;
  collider.resolve(X, Vel, 0.01);
  CHECK(X.row(0).isApprox(Eigen::RowVector3d(0.1, 0.51, 0.0), 1e-12));
  CHECK(X.row(1).isApprox(Eigen::RowVector3d(0.0, 0.51, 0.2), 1e-12));
  CHECK(X.row(2) == Eigen::RowVector3d(0.0, 2.0, 0.0));
  CHECK(Vel.row(0).isApprox(Eigen::RowVector3d(0.3, 0.0, 0.0), 1e-12));  // tangential kept
  CHECK(Vel.row(1).isApprox(Eigen::RowVector3d(0.0, 0.5, 0.0), 1e-12));  // separating kept
  CHECK(Vel.row(2) == Eigen::RowVector3d(0.0, -1.0, 0.0));
  CHECK(collider.stats().projected == 2);
  CHECK(collider.stats().deepest_penetration == Approx(0.05).epsilon(1e-12));
  // Second call: the far vertex is skipped by the motion bound; the near ones re-queried.
  collider.resolve(X, Vel, 0.01);
  CHECK(collider.stats().skipped == 1);
  CHECK(collider.stats().queries == 5);
  // A body moving fast enough invalidates the bound: a 1.6 m jump makes it query again.
  Eigen::MatrixXd moved = cube.V;
  moved.col(1).array() += 1.6;
  Eigen::MatrixXd body_velocity = Eigen::MatrixXd::Zero(8, 3);
  body_velocity.col(1).setConstant(2.0);
  collider.set_body(moved, &body_velocity);
  Eigen::MatrixXd X2 = X, V2 = Vel;
  collider.resolve(X2, V2, 0.01);
  CHECK(collider.stats().skipped == 1);
  // The far vertex is now inside the moved cube (y from 1.1 to 2.1): pushed out
  // through the top and given the body's upward speed.
  CHECK(X2(2, 1) == Approx(2.11).epsilon(1e-12));
  CHECK(V2(2, 1) == Approx(2.0).epsilon(1e-12));
  CHECK_THROWS_AS(collider.set_body(Eigen::MatrixXd::Zero(3, 3)), gp::UsageError);
}

TEST_CASE("a cloth falling on a sphere stays outside the comfort offset", "[collision][simulator]") {
  const double r = 0.2, offset = 0.01;
  const gp::Mesh sphere = gp::testing::make_icosphere(4, r);
  gp::Mesh cloth = gp::testing::make_grid(30, 30, 0.6, 0.6);
  cloth.V.rowwise() += Eigen::RowVector3d(-0.3, r + 0.05, -0.3);
  BodyCollider collider(sphere.F, reachable_body_faces(sphere.V, sphere.F, cloth.V, 0.5));
  collider.set_body(sphere.V);
  gp::cloth::SimulatorOptions paper_step;  // the paper's 2.5 ms, which this test was written for
  paper_step.dt = 0.0025;
  gp::cloth::ClothSimulator sim(cloth.V, cloth.F, gp::cloth::ClothParameters{}, paper_step);
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [&](Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) { collider.resolve(X, Vel, offset); };
  BodyCollider checker(sphere.F);
  checker.set_body(sphere.V);
  double worst = 1e9;
  std::vector<int> hints(cloth.V.rows(), -1);
  for (int s = 0; s < 400; ++s) {
    sim.step();
    for (int v = 0; v < sim.positions().rows(); ++v) {
      const Proximity q = checker.query(sim.positions().row(v).transpose(), hints[v]);
      hints[v] = q.face;
      worst = std::min(worst, q.signed_distance);
    }
  }
  INFO("closest approach " << worst << " m, queries " << collider.stats().queries << ", skipped "
                           << collider.stats().skipped);
  CHECK(worst >= offset - 0.002);
  // The cloth drapes: the centre rests on top of the sphere, the corners hang low.
  const int centre = 15 * 31 + 15;
  CHECK(sim.positions()(centre, 1) == Approx(r + offset).margin(0.003));
  CHECK(sim.positions()(0, 1) < 0.05);
  CHECK(sim.positions().allFinite());
}

TEST_CASE("contacts lists vertices within offset plus band with normals and body normal speed", "[collision]") {
  const gp::Mesh cube = make_cube(0.5);
  BodyCollider collider(cube.F);
  // The body moves up at 0.3 m/s.
  Eigen::MatrixXd body_velocity = Eigen::MatrixXd::Zero(cube.V.rows(), 3);
  body_velocity.col(1).setConstant(0.3);
  collider.set_body(cube.V, &body_velocity);
  Eigen::MatrixXd X(5, 3);
  X << 0.0, 0.51, 0.0,     // 1 cm above the top face: in contact (offset 0.01, band 0.001)
      0.0, 0.5105, 0.1,    // in the band
      0.0, 0.52, 0.2,      // beyond offset + band: not listed
      0.0, 0.45, 0.0,      // 5 cm inside, below the top face
      0.505, 0.0, 0.0;     // 5 mm from the +x face
  const std::vector<Contact> c = collider.contacts(X, 0.01, 0.001);
  REQUIRE(c.size() == 4);
  CHECK(c[0].vertex == 0);
  CHECK(c[1].vertex == 1);
  CHECK(c[2].vertex == 3);
  CHECK(c[3].vertex == 4);
  CHECK(c[0].signed_distance == Approx(0.01).margin(1e-12));
  CHECK(c[1].signed_distance == Approx(0.0105).margin(1e-12));
  CHECK(c[2].signed_distance == Approx(-0.05).margin(1e-12));
  CHECK(c[0].outward.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  CHECK(c[2].outward.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  CHECK(c[3].outward.isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  CHECK(c[0].body_normal_speed == Approx(0.3));
  CHECK(c[3].body_normal_speed == Approx(0.0).margin(1e-12));
  CHECK_THROWS_AS(collider.contacts(X, -0.01, 0.0), gp::UsageError);
}

TEST_CASE("on a body standing still, a vertex's candidate faces give the tree's answers", "[collision]") {
  // The lumpy sphere again, and cloth points 2 mm to 5 cm outside or 1 cm
  // inside it that move by less than the candidates' slack (2 mm) most rounds
  // and jump by 5 mm every fourth, so that both paths and the re-collection
  // are taken; every answer is compared with a fresh tree query. The body
  // stands still: its frame is set again at the same positions (a key pose).
  const gp::Mesh body = lumpy_sphere();
  BodyCollider collider(body.F);
  collider.set_body(body.V);
  collider.set_body(body.V);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(body.V.rows()) - 1);
  const int n = 300;
  Eigen::MatrixXd X(n, 3);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = body.V.row(vertex(rng));
    const double lift = i % 10 == 0 ? -0.01 : 0.002 + 0.024 * (1.0 + u(rng));
    X.row(i) = (p + lift * p.normalized()).transpose();
  }
  auto random_step = [&](double length) {
    Eigen::Vector3d d(u(rng), u(rng), u(rng));
    while (!(d.norm() > 1e-3)) d = Eigen::Vector3d(u(rng), u(rng), u(rng));
    return Eigen::Vector3d(length * std::abs(u(rng)) * d.normalized());
  };
  double worst_distance = 0.0, worst_direction = 0.0;
  long compared = 0;
  for (int round = 0; round < 24; ++round) {
    for (int i = 0; i < n; ++i) X.row(i) += random_step(round % 4 == 3 ? 5e-3 : 1.9e-3).transpose();
    // Offset 0.05 m and a band of 1 m: every point is a contact.
    for (const Contact& c : collider.contacts(X, 0.05, 1.0)) {
      const Proximity tree = collider.query(X.row(c.vertex).transpose());
      worst_distance = std::max(worst_distance, std::abs(c.signed_distance - tree.signed_distance));
      worst_direction = std::max(worst_direction, 1.0 - c.outward.dot(tree.outward));
      ++compared;
    }
  }
  CHECK(compared >= 24 * n);
  CHECK(worst_distance <= 1e-15);
  CHECK(worst_direction <= 1e-12);
  // Most answers came from the candidates. A moving body's frames are
  // answered by the tree alone.
  CHECK(collider.stats().local > 12 * n);
  const long local_before = collider.stats().local;
  for (int frame = 1; frame <= 3; ++frame) {
    collider.set_body(body.V * (1.0 + 1e-4 * frame));
    for (int round = 0; round < 4; ++round) {
      for (int i = 0; i < n; ++i) X.row(i) += random_step(1e-3).transpose();
      collider.contacts(X, 0.05, 1.0);
    }
  }
  CHECK(collider.stats().local == local_before);
}

TEST_CASE("a vertex that has not moved on an unchanged body reuses its last answer", "[collision]") {
  const gp::Mesh cube = make_cube(0.5);
  BodyCollider collider(cube.F);
  collider.set_body(cube.V);
  Eigen::MatrixXd X(3, 3);
  X << 0.0, 0.505, 0.0,  // in contact
      0.3, 0.0, 0.508,   // in contact
      0.0, 2.0, 0.0;     // far: skipped by the motion bound, never reused
  const std::vector<Contact> first = collider.contacts(X, 0.01, 0.001);
  REQUIRE(first.size() == 2);
  CHECK(collider.stats().queries == 3);
  const std::vector<Contact> second = collider.contacts(X, 0.01, 0.001);
  CHECK(collider.stats().queries == 3);
  CHECK(collider.stats().reused == 2);
  CHECK(collider.stats().skipped == 1);
  REQUIRE(second.size() == 2);
  for (size_t k = 0; k < 2; ++k) {
    CHECK(second[k].vertex == first[k].vertex);
    CHECK(second[k].signed_distance == first[k].signed_distance);
    CHECK(second[k].outward == first[k].outward);
  }
  // A moved vertex is queried again, and so is every vertex on a new body frame
  // (even at the same body positions).
  X(1, 2) = 0.507;
  collider.contacts(X, 0.01, 0.001);
  CHECK(collider.stats().queries == 4);
  CHECK(collider.stats().reused == 3);
  collider.set_body(cube.V);
  const std::vector<Contact> third = collider.contacts(X, 0.01, 0.001);
  CHECK(collider.stats().queries == 6);
  CHECK(collider.stats().reused == 3);
  REQUIRE(third.size() == 2);
  CHECK(third[1].signed_distance == Approx(0.007).margin(1e-12));
  // resolve() reuses both answers and projects both vertices to the offset;
  // having moved, they are queried again by the next contacts().
  Eigen::MatrixXd Vel = Eigen::MatrixXd::Zero(3, 3);
  collider.resolve(X, Vel, 0.01);
  CHECK(collider.stats().queries == 6);
  CHECK(collider.stats().reused == 5);
  CHECK(X(0, 1) == Approx(0.51).margin(1e-12));
  CHECK(X(1, 2) == Approx(0.51).margin(1e-12));
  collider.contacts(X, 0.01, 0.001);
  CHECK(collider.stats().queries == 8);
}

namespace {

// A closed L-shaped prism along z (a floor block and a wall block): its inner
// corner along the z axis is a concave crease, floor y = 0 (normal +y) meeting
// wall x = 0 (normal +x).
gp::Mesh make_l_prism() {
  const double p[6][2] = {{-0.2, -0.2}, {0.3, -0.2}, {0.3, 0.0}, {0.0, 0.0}, {0.0, 0.3}, {-0.2, 0.3}};
  gp::Mesh m;
  m.V.resize(12, 3);
  for (int i = 0; i < 6; ++i) {
    m.V.row(i) << p[i][0], p[i][1], -0.2;
    m.V.row(6 + i) << p[i][0], p[i][1], 0.2;
  }
  std::vector<Eigen::Vector3i> F;
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    F.push_back({i, j, 6 + j});
    F.push_back({i, 6 + j, 6 + i});
  }
  for (int k = 1; k < 5; ++k) {  // caps: a fan from corner 0 (each triangle inside the L)
    F.push_back({6, 6 + k, 6 + k + 1});
    F.push_back({0, k + 1, k});
  }
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t f = 0; f < F.size(); ++f) m.F.row(static_cast<Eigen::Index>(f)) = F[f].transpose();
  return m;
}

// A strip pressed by gravity into the L's crease, with contacts as velocity
// constraints as simulate-adapt sets them; after 200 steps: the largest net
// speed of its middle column over the last 40 [m/s] and that column's smallest
// distance to either side [m].
struct CreaseStrip {
  double speed = 0.0;
  double distance = 0.0;
  long creases = 0;
  long constraints = 0;
};

CreaseStrip press_strip_into_crease() {
  const gp::Mesh body = make_l_prism();
  const double offset = 0.01;
  BodyCollider collider(body.F);
  collider.set_body(body.V);
  // Three columns along z, folded like the crease, 2 mm off the offset
  // surface: the middle one above the crease line (x = y = offset), where
  // gravity presses it.
  gp::Mesh strip = gp::testing::make_grid(2, 12, 0.02, 0.24);
  for (int v = 0; v < strip.V.rows(); ++v) {
    const int column = static_cast<int>(std::lround(strip.V(v, 0) / 0.01));
    const double z = strip.V(v, 2) - 0.12;
    const Eigen::Vector3d place[3] = {{offset + 0.002, offset + 0.012, z}, {offset + 0.002, offset + 0.002, z},
                                      {offset + 0.012, offset + 0.002, z}};
    strip.V.row(v) = place[column].transpose();
  }
  gp::cloth::ClothParameters params;
  params.gravity = 9.81 * Eigen::Vector3d(-1.0, -1.0, 0.0).normalized();
  gp::cloth::SimulatorOptions options;
  options.dt = 0.01;
  gp::cloth::ClothSimulator sim(strip.V, strip.F, params, options);
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [&](Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) { collider.resolve(X, Vel, offset); };
  step_body.on_constraints = [&](const Eigen::MatrixXd& X, double h, std::vector<gp::cloth::VelocityConstraint>& out) {
    for (const Contact& c : collider.contacts(X, offset, 5e-4)) {
      gp::cloth::VelocityConstraint k;
      k.vertex = c.vertex;
      k.normal = c.outward;
      k.normal_velocity = std::min(std::max(offset - c.signed_distance, 0.0) / h, 0.5);
      k.touching = c.signed_distance <= offset + 1e-6;
      out.push_back(k);
    }
  };
  Eigen::MatrixXd before;
  for (int s = 0; s < 200; ++s) {
    if (s == 160) before = sim.positions();
    sim.step();
  }
  CreaseStrip r;
  r.distance = 1.0;
  for (int v = 1; v < strip.V.rows(); v += 3) {  // the middle column
    r.speed = std::max(r.speed, (sim.positions().row(v) - before.row(v)).norm() / 0.4);
    r.distance = std::min(r.distance, std::min(sim.positions()(v, 0), sim.positions()(v, 1)));
  }
  r.creases = collider.stats().creases;
  r.constraints = sim.counters().constraints;
  return r;
}

}  // namespace

TEST_CASE("cloth pressed into a crease is held by both sides and comes to rest", "[collision][simulator]") {
  const CreaseStrip r = press_strip_into_crease();
  INFO("net speed of the crease line " << r.speed << " m/s, " << r.creases << " crease contacts, "
                                       << r.constraints << " constraints");
  CHECK(r.creases > 0);
  CHECK(r.speed < 1e-3);
  // The middle column sits in the crease at the offset from both sides.
  CHECK(r.distance == Approx(0.01).margin(5e-4));
}

TEST_CASE("in a pinch narrower than twice the offset, vertices go to the middle of the gap", "[collision]") {
  // Two unit cubes 2 cm apart (an arm against the torso): faces at x = -0.01
  // and x = +0.01. With a 1.5 cm offset the two offset shells overlap.
  const gp::Mesh cube = make_cube(0.5);
  gp::Mesh body;
  body.V.resize(16, 3);
  body.V << cube.V.rowwise() - Eigen::RowVector3d(0.51, 0.0, 0.0),
      cube.V.rowwise() + Eigen::RowVector3d(0.51, 0.0, 0.0);
  body.F.resize(24, 3);
  body.F << cube.F, cube.F.array() + 8;
  BodyCollider collider(body.F);
  collider.set_body(body.V);

  const Proximity q = collider.query(Eigen::Vector3d(0.004, 0.1, 0.0));
  CHECK(q.signed_distance == Approx(0.006).margin(1e-12));
  CHECK(q.outward.isApprox(-Eigen::Vector3d::UnitX(), 1e-12));
  CHECK(collider.gap(q) == Approx(0.02).margin(1e-9));
  // Facing open space, the ray leaves the body.
  CHECK(std::isinf(collider.gap(collider.query(Eigen::Vector3d(0.0, 0.6, 0.0)))));

  Eigen::MatrixXd X(3, 3), Vel = Eigen::MatrixXd::Zero(3, 3);
  X << 0.004, 0.1, 0.0,   // in the gap, 6 mm from the right cube
      -0.008, -0.2, 0.1,  // in the gap, 2 mm from the left cube
      0.7, 0.505, 0.0;    // above the right cube's top: open space, the full offset
  collider.resolve(X, Vel, 0.015);
  // Both gap vertices end in the middle (1 cm from either face), not 1.5 cm
  // from one face and so 5 mm from the other.
  CHECK(X(0, 0) == Approx(0.0).margin(1e-9));
  CHECK(X(1, 0) == Approx(0.0).margin(1e-9));
  CHECK(X(2, 1) == Approx(0.515).margin(1e-12));
  CHECK(collider.stats().pinched == 2);
  // A second call finds them at the middle already: nothing moves.
  const Eigen::MatrixXd X_again = X;
  collider.resolve(X, Vel, 0.015);
  CHECK(X.isApprox(X_again, 1e-12));

  // Contacts report the offset they used.
  const std::vector<Contact> c = collider.contacts(X, 0.015, 0.001);
  REQUIRE(c.size() == 3);
  CHECK(c[0].offset == Approx(0.01).margin(1e-9));
  CHECK(c[1].offset == Approx(0.01).margin(1e-9));
  CHECK(c[2].offset == 0.015);
}
