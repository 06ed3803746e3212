// Continuous collision detection of moving points, triangles and edges: times,
// contact points and sides on cases with known answers, misses, grazing
// contacts, degenerate primitives, and a randomized comparison with dense
// sampling in time.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "collision/ccd.h"

using Eigen::Vector3d;
using gp::collision::edge_edge_ccd;
using gp::collision::point_triangle_ccd;

namespace {

const Vector3d A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);  // normal +z

Vector3d lerp(const Vector3d& a, const Vector3d& b, double t) { return a + t * (b - a); }

double point_triangle_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d w = gp::collision::closest_triangle_weights(p, a, b, c);
  return (w(0) * a + w(1) * b + w(2) * c - p).norm();
}

}  // namespace

TEST_CASE("a point through a still triangle: time, contact point and side", "[collision][ccd]") {
  const auto hit = point_triangle_ccd(Vector3d(0.2, 0.3, 1), Vector3d(0.2, 0.3, -3), A, A, B, B, C, C, 1e-9);
  REQUIRE(hit);
  CHECK(hit->t == Approx(0.25).margin(1e-12));
  CHECK(hit->weights(1) == Approx(0.2).margin(1e-12));
  CHECK(hit->weights(2) == Approx(0.3).margin(1e-12));
  CHECK(hit->side == 1);  // it came from the +z side
  const auto up = point_triangle_ccd(Vector3d(0.2, 0.3, -1), Vector3d(0.2, 0.3, 1), A, A, B, B, C, C, 1e-9);
  REQUIRE(up);
  CHECK(up->side == -1);
}

TEST_CASE("misses: beside the triangle, parallel above it, stopping short", "[collision][ccd]") {
  CHECK_FALSE(point_triangle_ccd(Vector3d(0.8, 0.8, 1), Vector3d(0.8, 0.8, -1), A, A, B, B, C, C, 1e-9));
  CHECK_FALSE(point_triangle_ccd(Vector3d(-1, 0.2, 0.1), Vector3d(2, 0.2, 0.1), A, A, B, B, C, C, 1e-9));
  CHECK_FALSE(point_triangle_ccd(Vector3d(0.2, 0.2, 1), Vector3d(0.2, 0.2, 1e-6), A, A, B, B, C, C, 1e-9));
  // Within the tolerance at the end is a contact.
  CHECK(point_triangle_ccd(Vector3d(0.2, 0.2, 1), Vector3d(0.2, 0.2, 1e-10), A, A, B, B, C, C, 1e-9));
}

TEST_CASE("a moving, turning triangle sweeps over a still point", "[collision][ccd]") {
  // The triangle rises by 2 and tilts: its plane is a different one at every t.
  const Vector3d p(0.25, 0.25, 1.0);
  const Vector3d a1(0, 0, 2), b1(1, 0, 1.5), c1(0, 1, 2.5);
  const auto hit = point_triangle_ccd(p, p, A, a1, B, b1, C, c1, 1e-9);
  REQUIRE(hit);
  // At the hit time the point lies on the triangle.
  CHECK(point_triangle_distance(p, lerp(A, a1, hit->t), lerp(B, b1, hit->t), lerp(C, c1, hit->t)) < 1e-9);
  CHECK(hit->side == 1);  // the point was above the plane before the triangle caught up
}

TEST_CASE("two edges crossing", "[collision][ccd]") {
  // Edge along x at z = 0; an edge along y falls through it.
  const Vector3d a(-1, 0, 0), b(1, 0, 0);
  const auto hit = edge_edge_ccd(a, a, b, b, Vector3d(0.5, -1, 1), Vector3d(0.5, -1, -1), Vector3d(0.5, 1, 1),
                                 Vector3d(0.5, 1, -1), 1e-9);
  REQUIRE(hit);
  CHECK(hit->t == Approx(0.5).margin(1e-12));
  CHECK(hit->s == Approx(0.75).margin(1e-12));
  CHECK(hit->u == Approx(0.5).margin(1e-12));
  // n = (b - a) x (d - c) = x cross y = +z; the second edge came from above.
  CHECK(hit->side == 1);
  // Passing beyond the end of the first edge: no contact.
  CHECK_FALSE(edge_edge_ccd(a, a, b, b, Vector3d(1.5, -1, 1), Vector3d(1.5, -1, -1), Vector3d(1.5, 1, 1),
                            Vector3d(1.5, 1, -1), 1e-9));
  // Parallel edges sliding over each other at a distance: no contact.
  CHECK_FALSE(edge_edge_ccd(a, a, b, b, Vector3d(-3, 0, 0.1), Vector3d(3, 0, 0.1), Vector3d(-2, 0, 0.1),
                            Vector3d(4, 0, 0.1), 1e-9));
}

TEST_CASE("degenerate and sliver primitives", "[collision][ccd]") {
  // A triangle collapsed to a segment has no plane (the cubic vanishes): a
  // point passing through the segment exactly is a measure-zero event that
  // the neighbouring primitives' tests see; the detection must stay finite.
  const Vector3d m(0.5, 0, 0);
  const auto collapsed = point_triangle_ccd(Vector3d(0.3, 0.1, 1), Vector3d(0.3, 0.1, -1), A, A, B, B, m, m, 1e-9);
  CHECK_FALSE(collapsed);
  // A sliver 1e-6 m high is still a triangle: crossed inside, missed beside.
  const Vector3d sliver(0.5, 1e-6, 0);
  const auto through = point_triangle_ccd(Vector3d(0.5, 5e-7, 1), Vector3d(0.5, 5e-7, -1), A, A, B, B, sliver,
                                          sliver, 1e-10);
  REQUIRE(through);
  CHECK(through->t == Approx(0.5).margin(1e-9));
  CHECK_FALSE(point_triangle_ccd(Vector3d(0.5, 2e-6, 1), Vector3d(0.5, 2e-6, -1), A, A, B, B, sliver, sliver, 1e-10));
  // A zero-length edge (a point) falling onto an edge: no plane either; a
  // result, if any, lies in the step.
  const auto point_edge = edge_edge_ccd(Vector3d(-1, 0, 0), Vector3d(-1, 0, 0), Vector3d(1, 0, 0), Vector3d(1, 0, 0),
                                        Vector3d(0.2, 0, 1), Vector3d(0.2, 0, -1), Vector3d(0.2, 0, 1),
                                        Vector3d(0.2, 0, -1), 1e-9);
  if (point_edge) CHECK((point_edge->t >= 0.0 && point_edge->t <= 1.0));
}

TEST_CASE("randomized: every passage through a triangle's interior is found", "[collision][ccd]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto rand3 = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  int crossings = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vector3d p0 = rand3(), p1 = rand3(), a0 = rand3(), b0 = rand3(), c0 = rand3();
    const Vector3d a1 = a0 + 0.3 * rand3(), b1 = b0 + 0.3 * rand3(), c1 = c0 + 0.3 * rand3();
    auto plane = [&](double t) {
      const Vector3d a = lerp(a0, a1, t), b = lerp(b0, b1, t), c = lerp(c0, c1, t);
      return (b - a).cross(c - a).dot(lerp(p0, p1, t) - a);
    };
    // Sign changes of the plane distance on a fine sampling, refined by
    // bisection; a crossing when the point is then inside the triangle with
    // a margin (barycentric coordinates above 1e-6).
    bool crossed = false;
    const int n = 1000;
    for (int i = 0; i < n && !crossed; ++i) {
      double lo = static_cast<double>(i) / n, hi = static_cast<double>(i + 1) / n;
      if ((plane(lo) < 0.0) == (plane(hi) < 0.0)) continue;
      for (int it = 0; it < 80; ++it) {
        const double mid = 0.5 * (lo + hi);
        if ((plane(mid) < 0.0) == (plane(lo) < 0.0)) lo = mid;
        else hi = mid;
      }
      const double t = 0.5 * (lo + hi);
      const Vector3d w =
          gp::collision::closest_triangle_weights(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t), lerp(c0, c1, t));
      crossed = w.minCoeff() > 1e-6;
    }
    const auto hit = point_triangle_ccd(p0, p1, a0, a1, b0, b1, c0, c1, 1e-9);
    if (crossed) {
      ++crossings;
      CHECK(hit);
    }
    if (hit) {
      const double t = hit->t;
      CHECK(point_triangle_distance(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t), lerp(c0, c1, t)) <= 1e-9);
    }
  }
  CHECK(crossings > 50);
}
