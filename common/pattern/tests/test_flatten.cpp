#include <catch2/catch.hpp>

#include <cmath>

#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pattern/auto_cut.h"
#include "pattern/flatten.h"
#include "pattern/mesh_cut.h"
#include "pattern/tests/test_helpers.h"
#include "testing/test_meshes.h"

using namespace gp;

namespace {

// The seam of the test cylinder: the vertical line of vertices at angle 0.
std::vector<int> cylinder_seam(int nu, int nv) {
  std::vector<int> ids;
  for (int j = 0; j <= nv; ++j) ids.push_back(j * nu);
  return ids;
}

double polygon_perimeter(const Eigen::MatrixXd& UV, const std::vector<int>& loop) {
  double s = 0.0;
  for (size_t k = 0; k < loop.size(); ++k) s += (UV.row(loop[k]) - UV.row(loop[(k + 1) % loop.size()])).norm();
  return s;
}

}  // namespace

TEST_CASE("an open cylinder cut along one seam flattens to its exact rectangle", "[flatten]") {
  const int nu = 24, nv = 10;
  const double radius = 0.12, height = 0.5;
  const Mesh cyl = testing::make_open_cylinder(nu, nv, radius, height);
  std::vector<SeamPath> seams{{"side", cylinder_seam(nu, nv), false, "test"}};
  const Pattern pattern = make_pattern(cyl.V, cyl.F, seams, PatternOptions{});
  REQUIRE(pattern.pieces.size() == 1);
  REQUIRE(pattern.seams.size() == 1);  // no extra cut: a cylinder is developable
  const PatternPiece& p = pattern.pieces.front();
  CHECK(p.flat.stats.flipped_triangles == 0);
  CHECK(p.flat.stats.max_error < 1e-6);
  // The polygonal cylinder's developed width is nu chords of the circle.
  const double width = nu * 2.0 * radius * std::sin(M_PI / nu);
  CHECK(polygon_perimeter(p.flat.UV, p.boundary) == Approx(2.0 * (width + height)).epsilon(1e-6));
  // Rectangle: the flat bounding box in the frame of the seam edge.
  const Eigen::Vector2d axis = (p.flat.UV.row(p.boundary[0]) - p.flat.UV.row(p.boundary[1])).normalized();
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (int v = 0; v < p.flat.UV.rows(); ++v) {
    const Eigen::Vector2d x = p.flat.UV.row(v);
    const Eigen::Vector2d q(x.dot(Eigen::Vector2d(-axis.y(), axis.x())), x.dot(axis));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector2d size = hi - lo;
  CHECK(std::max(size.x(), size.y()) == Approx(std::max(width, height)).epsilon(1e-6));
  CHECK(std::min(size.x(), size.y()) == Approx(std::min(width, height)).epsilon(1e-6));
  CHECK(p.flat.stats.area_2d == Approx(p.flat.stats.area_3d).epsilon(1e-6));
}

TEST_CASE("a hemisphere needs extra cuts and meets the default limit after them", "[flatten][auto_cut]") {
  const Mesh cap = testing::make_hemisphere(4, 0.15);
  PatternOptions options;
  // Without extra cuts the cap is far outside the limit.
  const FlattenResult whole = flatten_piece(cap.V, cap.F);
  CHECK(whole.stats.flipped_triangles == 0);
  CHECK(whole.stats.max_error > options.max_limit);
  const Pattern pattern = make_pattern(cap.V, cap.F, {}, options);
  CHECK(pattern.seams.size() > 1);
  CHECK(pattern.meets_limit);
  for (const auto& s : pattern.seams) {
    CHECK(!s.reason.empty());
    CHECK(s.kind == "distortion");
  }
  for (const auto& p : pattern.pieces) {
    CHECK(p.flat.stats.flipped_triangles == 0);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(p.flat.stats.p95_error <= options.p95_limit);
    CHECK(p.flat.stats.max_error <= options.max_limit);
  }
}
