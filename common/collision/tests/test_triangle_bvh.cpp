// The body's hierarchy (Embree, refitted per frame) against a brute-force
// search over every triangle: the same triangle and the same squared distance
// for every query, on a moving body, at exact ties, with degenerate triangles;
// rays and balls likewise; non-finite input rejected.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <CGAL/Simple_cartesian.h>
#include <Eigen/Geometry>

#include "collision/body_collider.h"
#include "collision/triangle_bvh.h"
#include "core/error.h"
#include "mesh/point_triangle.h"
#include "testing/test_meshes.h"

using namespace gp::collision;
using Corners = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;

namespace {

Corners corners_of(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Corners C(F.rows(), 9);
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) C.row(f).segment<3>(3 * k) = V.row(F(f, k));
  }
  return C;
}

Eigen::Vector3d corner(const Corners& C, int f, int k) { return C.row(f).segment<3>(3 * k).transpose(); }

// The rule the hierarchy must follow, by exhaustion: the smallest squared
// distance, the lowest index among equal ones.
TriangleBvh::Closest brute_closest(const Corners& C, const Eigen::Vector3d& p) {
  TriangleBvh::Closest best{-1, std::numeric_limits<double>::infinity()};
  for (int f = 0; f < C.rows(); ++f) {
    const double d2 = (p - gp::closest_point_on_triangle(p, corner(C, f, 0), corner(C, f, 1), corner(C, f, 2)).point).squaredNorm();
    if (d2 < best.squared_distance) best = {f, d2};
  }
  return best;
}

// Triangles at exactly the smallest distance from p.
std::vector<int> exactly_closest(const Corners& C, const Eigen::Vector3d& p) {
  const double d2 = brute_closest(C, p).squared_distance;
  std::vector<int> ids;
  for (int f = 0; f < C.rows(); ++f) {
    if ((p - gp::closest_point_on_triangle(p, corner(C, f, 0), corner(C, f, 1), corner(C, f, 2)).point).squaredNorm() == d2) {
      ids.push_back(f);
    }
  }
  return ids;
}

// An arm-like bent tube (the armpit pinch of an A-pose), with two degenerate
// triangles appended: one with two coincident corners (an edge) and one with
// three coincident corners (a point).
gp::Mesh tube_body() {
  gp::Mesh m = gp::testing::make_bent_tube(16, 0.05, 0.25, 0.06, 1.0);
  const Eigen::Index n = m.F.rows();
  m.F.conservativeResize(n + 2, 3);
  m.F.row(n) << m.F(0, 0), m.F(0, 1), m.F(0, 1);
  m.F.row(n + 1) << m.F(7, 2), m.F(7, 2), m.F(7, 2);
  return m;
}

// Frame t of a non-rigid motion of V: a twist about y growing with height, a
// bend towards +x and a translation.
Eigen::MatrixXd moved(const Eigen::MatrixXd& V, double t) {
  Eigen::MatrixXd W(V.rows(), 3);
  for (int v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v);
    const Eigen::Vector3d q = Eigen::AngleAxisd(1.5 * t * p.y(), Eigen::Vector3d::UnitY()) * p;
    W.row(v) = (q + Eigen::Vector3d(0.4 * t * p.y() * p.y() + 0.03 * t, 0.01 * t, -0.02 * t)).transpose();
  }
  return W;
}

}  // namespace

TEST_CASE("the refitted hierarchy finds the brute-force closest triangle on a moving body", "[collision][bvh]") {
  // Expectation: over five frames of a non-rigid motion (the first builds, the
  // rest refit), for random points around the body, points exactly at its
  // vertices (a tie among all faces around the vertex) and at edge midpoints
  // (a tie between the two faces of the edge, up to rounding), with and
  // without hints, the hierarchy answers the brute-force triangle and squared
  // distance exactly.
  const gp::Mesh body = tube_body();
  TriangleBvh refitted(static_cast<int>(body.F.rows()));
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> face(0, static_cast<int>(body.F.rows()) - 1);
  int checked = 0, mismatched = 0, vertex_ties = 0;
  for (int frame = 0; frame < 5; ++frame) {
    const Eigen::MatrixXd V = moved(body.V, 0.25 * frame);
    const Corners C = corners_of(V, body.F);
    refitted.set_corners(C);
    TriangleBvh fresh(static_cast<int>(body.F.rows()));
    fresh.set_corners(C);
    const Eigen::Vector3d lo = V.colwise().minCoeff().transpose(), hi = V.colwise().maxCoeff().transpose();
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Eigen::Vector3d> points;
    for (int k = 0; k < 1500; ++k) {
      const Eigen::Vector3d s(u(rng), u(rng), u(rng));
      points.push_back(lo - Eigen::Vector3d::Constant(0.05) + s.cwiseProduct(hi - lo + Eigen::Vector3d::Constant(0.1)));
    }
    for (int v = 0; v < V.rows(); v += 7) points.push_back(V.row(v).transpose());
    for (int f = 0; f < body.F.rows(); f += 11) points.push_back(0.5 * (corner(C, f, 0) + corner(C, f, 1)));
    for (const Eigen::Vector3d& p : points) {
      const TriangleBvh::Closest expected = brute_closest(C, p);
      for (const TriangleBvh::Closest got : {refitted.closest(p), refitted.closest(p, face(rng)), fresh.closest(p)}) {
        ++checked;
        mismatched += got.triangle != expected.triangle || got.squared_distance != expected.squared_distance;
      }
      vertex_ties += expected.squared_distance == 0.0 && exactly_closest(C, p).size() > 2;
    }
  }
  CHECK(checked == 3 * 5 * (1500 + (tube_body().V.rows() + 6) / 7 + (tube_body().F.rows() + 10) / 11));
  CHECK(mismatched == 0);
  CHECK(vertex_ties > 100);
}

TEST_CASE("exact ties between distant triangles go to the lowest index, whatever the hint", "[collision][bvh]") {
  // Two parallel grids 0.5 m apart (y = 0, and y = 0.5 facing down), 0.125 m
  // cells, and queries on the mid-plane y = 0.25 above grid vertices and edge
  // midpoints: every coordinate is a dyadic fraction, so the closest points
  // and distances are exact and equal on both grids (4 to 12 triangles at
  // exactly 0.25 m). Expectation: the lowest index among them, from every hint
  // and after refits that move the grids and back.
  const gp::Mesh grid = gp::testing::make_grid(8, 8, 1.0, 1.0);
  const Eigen::Index nf = grid.F.rows(), nv = grid.V.rows();
  Eigen::MatrixXd V(2 * nv, 3);
  Eigen::MatrixXi F(2 * nf, 3);
  // The upper grid first, so that its faces have the lower ids.
  V.topRows(nv) = grid.V;
  V.topRows(nv).col(1).setConstant(0.5);
  V.bottomRows(nv) = grid.V;
  V.bottomRows(nv).col(1).setZero();
  F.topRows(nf) = grid.F.rowwise().reverse();
  F.bottomRows(nf) = grid.F.array() + static_cast<int>(nv);
  const Corners C = corners_of(V, F);
  TriangleBvh bvh(static_cast<int>(F.rows()));
  bvh.set_corners(corners_of(Eigen::MatrixXd(V.array() + 0.3), F));
  bvh.set_corners(C);
  int ties = 0, wrong = 0;
  for (int i = 0; i <= 16; ++i) {
    for (int j = 0; j <= 16; ++j) {
      if (i % 2 && j % 2) continue;  // cell centres lie on a diagonal edge: not dyadic after projection
      const Eigen::Vector3d p(0.0625 * i, 0.25, 0.0625 * j);
      const std::vector<int> tied = exactly_closest(C, p);
      REQUIRE(tied.size() >= 2);
      REQUIRE(tied.front() < nf);
      REQUIRE(tied.back() >= nf);
      ++ties;
      for (int hint : {-1, tied.front(), tied.back(), static_cast<int>(F.rows()) - 1}) {
        const TriangleBvh::Closest got = bvh.closest(p, hint);
        wrong += got.triangle != tied.front() || got.squared_distance != 0.0625;
      }
    }
  }
  CHECK(ties == 17 * 17 - 64);
  CHECK(wrong == 0);

  // The collider over the same two grids answers the lowest body face id, on
  // the upper grid, with the distance of either.
  BodyCollider collider(F);
  collider.set_body(V);
  const Proximity q = collider.query(Eigen::Vector3d(0.5, 0.25, 0.5));
  CHECK(q.face < nf);
  CHECK(std::abs(q.signed_distance) == 0.25);
}

TEST_CASE("rays and balls match a brute-force search", "[collision][bvh]") {
  // The moved tube: rays from random points in random directions, and balls
  // of random radii, against every triangle. CGAL's ray/triangle intersection
  // decides the hits in both; degenerate triangles are never hit.
  using K = CGAL::Simple_cartesian<double>;
  const gp::Mesh body = tube_body();
  const Eigen::MatrixXd V = moved(body.V, 0.6);
  const Corners C = corners_of(V, body.F);
  TriangleBvh bvh(static_cast<int>(body.F.rows()));
  bvh.set_corners(corners_of(body.V, body.F));
  bvh.set_corners(C);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.4, 0.4), r(0.0, 0.08);
  int hits = 0, wrong_rays = 0, wrong_balls = 0;
  for (int k = 0; k < 600; ++k) {
    const Eigen::Vector3d o(u(rng), u(rng), u(rng));
    const Eigen::Vector3d d = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const int skip = k % 3 == 0 ? k % static_cast<int>(body.F.rows()) : -1;
    const K::Ray_3 ray(K::Point_3(o.x(), o.y(), o.z()), K::Vector_3(d.x(), d.y(), d.z()));
    int axis = 0;
    for (int a = 1; a < 3; ++a) axis = std::abs(d[a]) > std::abs(d[axis]) ? a : axis;
    TriangleBvh::Hit expected;
    expected.t = std::numeric_limits<double>::infinity();
    for (int f = 0; f < C.rows(); ++f) {
      if (f == skip || (corner(C, f, 1) - corner(C, f, 0)).cross(corner(C, f, 2) - corner(C, f, 0)).isZero(0.0)) continue;
      auto pt = [&](int c) { return K::Point_3(C(f, 3 * c), C(f, 3 * c + 1), C(f, 3 * c + 2)); };
      const auto x = CGAL::intersection(ray, K::Triangle_3(pt(0), pt(1), pt(2)));
      if (!x) continue;
      // CGAL's parameter (its AABB tree's ray traversal): along the ray's
      // own vector, its second point minus its source.
      auto param = [&](const K::Point_3& y) { return (y[axis] - o[axis]) / ray.to_vector()[axis]; };
      double t;
      if (const K::Point_3* y = boost::get<K::Point_3>(&*x)) {
        t = param(*y);
      } else {
        const K::Segment_3& s = boost::get<K::Segment_3>(*x);
        t = std::min(param(s.source()), param(s.target()));
      }
      if (t < expected.t) expected = {f, t};
    }
    const TriangleBvh::Hit got = bvh.first_hit(o, d, skip);
    hits += got.triangle >= 0;
    wrong_rays += got.triangle != expected.triangle || (got.triangle >= 0 && got.t != expected.t);

    const double radius = r(rng);
    std::vector<int> inside;
    for (int f = 0; f < C.rows(); ++f) {
      const Eigen::Vector3d c = gp::closest_point_on_triangle(o, corner(C, f, 0), corner(C, f, 1), corner(C, f, 2)).point;
      if ((o - c).squaredNorm() <= radius * radius) inside.push_back(f);
    }
    wrong_balls += bvh.within(o, radius) != inside;
  }
  CHECK(hits > 30);
  CHECK(wrong_rays == 0);
  CHECK(wrong_balls == 0);
}

TEST_CASE("non-finite input is rejected with a clear error, and skipped by the collision response", "[collision][bvh]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const gp::Mesh body = gp::testing::make_icosphere(2, 0.3);
  TriangleBvh bvh(static_cast<int>(body.F.rows()));
  CHECK_THROWS_AS(bvh.closest(Eigen::Vector3d::Zero()), gp::UsageError);  // before set_corners
  Corners C = corners_of(body.V, body.F);
  bvh.set_corners(C);
  CHECK_THROWS_AS(bvh.closest(Eigen::Vector3d(nan, 0, 0)), gp::NumericalError);
  CHECK_THROWS_AS(bvh.closest(Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 0)), gp::NumericalError);
  CHECK_THROWS_AS(bvh.first_hit(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d::UnitX()), gp::NumericalError);
  CHECK_THROWS_AS(bvh.first_hit(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), gp::NumericalError);
  CHECK_THROWS_AS(bvh.within(Eigen::Vector3d::Zero(), nan), gp::NumericalError);
  C(4, 2) = nan;
  CHECK_THROWS_AS(bvh.set_corners(C), gp::GeometryError);
  CHECK_THROWS_AS(bvh.set_corners(C.topRows(3)), gp::UsageError);
  CHECK_THROWS_AS(TriangleBvh(0), gp::UsageError);

  BodyCollider collider(body.F);
  collider.set_body(body.V);
  CHECK_THROWS_AS(collider.query(Eigen::Vector3d(0, nan, 0)), gp::NumericalError);
  // A cloth vertex at NaN (a diverged solve) is left alone; the others are
  // pushed out to the offset as usual.
  Eigen::MatrixXd X(2, 3), Vel = Eigen::MatrixXd::Zero(2, 3);
  X << nan, 0.0, 0.0, 0.0, 0.0, 0.29;
  collider.resolve(X, Vel, 0.01);
  CHECK(std::isnan(X(0, 0)));
  CHECK(std::abs(collider.query(X.row(1).transpose()).signed_distance - 0.01) < 1e-9);
  const std::vector<Contact> contacts = collider.contacts(X, 0.01, 0.005);
  REQUIRE(contacts.size() == 1);
  CHECK(contacts[0].vertex == 1);
}
