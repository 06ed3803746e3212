#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "mesh/point_triangle.h"

namespace {

using gp::TriangleFeature;
using V3 = Eigen::Vector3d;

// The closest point by dense sampling of the triangle (and its edges, so that
// a degenerate triangle is sampled too): an answer the region test must match.
double sampled_distance(const V3& p, const V3& a, const V3& b, const V3& c) {
  double best = std::numeric_limits<double>::infinity();
  const int n = 400;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      best = std::min(best, (p - (a + u * (b - a) + v * (c - a))).norm());
    }
  return best;
}

void check_consistent(const gp::TriangleClosestPoint& r, const V3& a, const V3& b, const V3& c) {
  CHECK(r.bary.minCoeff() >= 0.0);
  CHECK(r.bary.sum() == Approx(1.0).margin(1e-14));
  const V3 from_bary = r.bary(0) * a + r.bary(1) * b + r.bary(2) * c;
  CHECK((from_bary - r.point).norm() <= 1e-12 * (1.0 + a.norm() + b.norm() + c.norm()));
  if (gp::is_corner(r.feature)) CHECK(r.bary(gp::feature_index(r.feature)) == 1.0);
  if (gp::is_edge(r.feature)) CHECK(r.bary((gp::feature_index(r.feature) + 2) % 3) == 0.0);
}

}  // namespace

TEST_CASE("closest point on a triangle, in each of its seven Voronoi regions", "[mesh]") {
  const V3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  struct Case {
    V3 p;
    TriangleFeature feature;
    V3 closest;
  };
  const Case cases[] = {
      {V3(-1, -1, 0.5), TriangleFeature::corner0, a},
      {V3(3, -0.5, -1), TriangleFeature::corner1, b},
      {V3(-0.5, 3, 2), TriangleFeature::corner2, c},
      {V3(1, -1, 0.3), TriangleFeature::edge0, V3(1, 0, 0)},
      {V3(2, 2, -0.7), TriangleFeature::edge1, V3(1, 1, 0)},
      {V3(-1, 1, 0.1), TriangleFeature::edge2, V3(0, 1, 0)},
      {V3(0.5, 0.5, 3), TriangleFeature::interior, V3(0.5, 0.5, 0)},
  };
  for (const Case& k : cases) {
    const gp::TriangleClosestPoint r = gp::closest_point_on_triangle(k.p, a, b, c);
    CHECK(r.feature == k.feature);
    CHECK((r.point - k.closest).norm() < 1e-15);
    check_consistent(r, a, b, c);
  }
  // Feature indices name the corner or the edge's first corner.
  CHECK(gp::feature_index(TriangleFeature::corner2) == 2);
  CHECK(gp::feature_index(TriangleFeature::edge1) == 1);
  CHECK_FALSE(gp::is_edge(TriangleFeature::interior));
  CHECK_FALSE(gp::is_corner(TriangleFeature::interior));
}

TEST_CASE("closest point on random triangles matches dense sampling, at any scale", "[mesh]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (double scale : {1e-6, 1.0, 1e5}) {
    for (int trial = 0; trial < 40; ++trial) {
      const V3 a = scale * V3(unit(rng), unit(rng), unit(rng));
      const V3 b = scale * V3(unit(rng), unit(rng), unit(rng));
      const V3 c = scale * V3(unit(rng), unit(rng), unit(rng));
      const V3 p = 2.0 * scale * V3(unit(rng), unit(rng), unit(rng));
      const gp::TriangleClosestPoint r = gp::closest_point_on_triangle(p, a, b, c);
      check_consistent(r, a, b, c);
      const double d = (p - r.point).norm();
      // Exact answer: never farther than a sample, and within the sampling
      // resolution (diameter / 400) of the best sample.
      const double diameter = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
      const double sampled = sampled_distance(p, a, b, c);
      CHECK(d <= sampled * (1.0 + 1e-12));
      CHECK(d >= sampled - diameter / 400.0);
    }
  }
}

TEST_CASE("degenerate triangles answer with their closest edge", "[mesh]") {
  const V3 a(0, 0, 0), b(2, 0, 0);
  const V3 p(1, 1, 0);
  // Collinear corners: the edge a-b holds the closest point.
  const auto collinear = gp::closest_point_on_triangle(p, a, b, 0.5 * (a + b));
  CHECK((collinear.point - V3(1, 0, 0)).norm() < 1e-15);
  check_consistent(collinear, a, b, 0.5 * (a + b));
  // Two coincident corners: still a segment.
  const auto pair = gp::closest_point_on_triangle(p, a, b, b);
  CHECK((pair.point - V3(1, 0, 0)).norm() < 1e-15);
  CHECK(gp::is_edge(pair.feature));
  check_consistent(pair, a, b, b);
  // All three coincident: a corner.
  const auto point = gp::closest_point_on_triangle(p, b, b, b);
  CHECK(point.point == b);
  CHECK(gp::is_corner(point.feature));
  // Beyond the segment's end: that end, as a corner.
  const auto beyond = gp::closest_point_on_triangle(V3(3, 1, 0), a, b, 0.5 * (a + b));
  CHECK(beyond.point == b);
  CHECK(gp::is_corner(beyond.feature));
}

TEST_CASE("a NaN query point gives a non-finite answer, not a wrong finite one", "[mesh]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto r = gp::closest_point_on_triangle(V3(nan, 0, 0), V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0));
  CHECK_FALSE(r.point.allFinite());
}
