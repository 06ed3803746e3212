#include <catch2/catch.hpp>

#include <cmath>

#include "pattern/flatten.h"
#include "pattern/seam_allowance.h"

using namespace gp;

namespace {

double distance_to_outline(const Polygon2& poly, const Eigen::Vector2d& q) {
  double best = 1e300;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
    const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - q).norm());
  }
  return best;
}

}  // namespace

TEST_CASE("seam allowance is a mitred polygon offset", "[seam_allowance]") {
  const Polygon2 square{{0, 0}, {0.1, 0}, {0.1, 0.1}, {0, 0.1}};
  const auto out = offset_polygon(square, 0.01, 1e-4, "square");
  REQUIRE(out.size() == 1);
  CHECK(polygon_area(out[0]) == Approx(0.12 * 0.12).epsilon(1e-9));
  CHECK(polygon_perimeter(out[0]) == Approx(4 * 0.12).epsilon(1e-9));
  // Clockwise input gives the same counter-clockwise offset.
  const Polygon2 cw(square.rbegin(), square.rend());
  CHECK(polygon_area(offset_polygon(cw, 0.01, 1e-4, "cw")[0]) == Approx(0.12 * 0.12).epsilon(1e-9));
}

TEST_CASE("acute corners are bevelled and touching dart sides are handled", "[seam_allowance]") {
  // A 5 degree spike: its mitre would reach 0.01 / sin(2.5 deg) = 23 cm out.
  const double a = 5.0 * M_PI / 180.0;
  const Polygon2 spike{{0, 0}, {0.3, 0}, {0.3 * std::cos(a), 0.3 * std::sin(a)}};
  const auto out = offset_polygon(spike, 0.01, 1e-4, "spike");
  REQUIRE(!out.empty());
  for (const auto& q : out[0]) CHECK(distance_to_outline(spike, q) <= 0.02 * (1 + 1e-6));
  // A closed dart: the outline goes in along a slit and back on the same line.
  const Polygon2 dart{{0, 0}, {0.2, 0}, {0.2, 0.2}, {0.1, 0.2}, {0.1, 0.1}, {0.1, 0.2}, {0, 0.2}};
  Eigen::MatrixXd P(static_cast<int>(dart.size()), 2);
  for (size_t i = 0; i < dart.size(); ++i) P.row(static_cast<int>(i)) = dart[i].transpose();
  CHECK(polygon_self_intersects(P));
  const auto cut = offset_polygon(dart, 0.01, 1e-4, "dart");
  REQUIRE(!cut.empty());
  CHECK(polygon_area(cut[0]) == Approx(0.22 * 0.22).epsilon(1e-6));
}

TEST_CASE("the bevel of a run of sharp corners stays within twice the allowance", "[seam_allowance]") {
  // A spike whose tip is two sharp corners 2 mm apart (a dart mouth bridged
  // next to a narrow point): their mitres are two far offset vertices in a
  // row, which moving each part of the way to its neighbours left far out.
  for (double deg : {2.0, 5.0, 10.0}) {
    const double a = deg * M_PI / 180.0;
    const Polygon2 spike{{0, 0}, {0.3, 0}, {0.3, 0.002}, {0.3 * std::cos(a), 0.3 * std::sin(a)}};
    const auto out = offset_polygon(spike, 0.01, 1e-5, "spike");
    REQUIRE(!out.empty());
    double farthest = 0.0;
    for (const auto& q : out[0]) {
      const double d = distance_to_outline(spike, q);
      farthest = std::max(farthest, d);
      CHECK(d <= 0.02 * (1 + 1e-6));
    }
    CHECK(farthest >= 0.0199);  // bevelled at the limit, not short of it
  }
}

TEST_CASE("Douglas-Peucker keeps corners and drops collinear points", "[seam_allowance]") {
  Polygon2 poly;
  for (int i = 0; i < 10; ++i) poly.emplace_back(0.01 * i, 0.0);
  for (int i = 0; i < 10; ++i) poly.emplace_back(0.1, 0.01 * i);
  for (int i = 0; i < 10; ++i) poly.emplace_back(0.1 - 0.01 * i, 0.1);
  for (int i = 0; i < 10; ++i) poly.emplace_back(0.0, 0.1 - 0.01 * i);
  const Polygon2 s = simplify_polygon(poly, 1e-6);
  CHECK(s.size() == 4);
  CHECK(polygon_area(s) == Approx(0.01).epsilon(1e-12));
}
