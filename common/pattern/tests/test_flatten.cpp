#include <catch2/catch.hpp>

#include <cmath>

#include "mesh/measures.h"
#include "mesh/topology.h"
#include "core/error.h"
#include "pattern/auto_cut.h"
#include "pattern/export_report.h"
#include "pattern/layout.h"
#include "pattern/flatten.h"
#include "pattern/mesh_cut.h"
#include "pattern/rest_diagnostics.h"
#include "pattern/tests/test_helpers.h"
#include "testing/test_meshes.h"
#include "garment/surface_path.h"
#include <limits>

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
  // Without extra cuts allowed the output still has no flipped triangle.
  PatternOptions no_cuts = options;
  no_cuts.max_added_cuts = 0;
  const Pattern uncut = make_pattern(cap.V, cap.F, {}, no_cuts);
  REQUIRE(uncut.pieces.size() == 1);
  CHECK(!uncut.meets_limit);
  CHECK(uncut.cut_cap_reached);
  CHECK(uncut.pieces[0].flat.stats.flipped_triangles == 0);
  const Pattern pattern = make_pattern(cap.V, cap.F, {}, options);
  CHECK(pattern.seams.size() > 1);
  CHECK(pattern.meets_limit);
  CHECK(!pattern.cut_cap_reached);
  CHECK(pattern.stuck_pieces.empty());
  for (const auto& s : pattern.seams) {
    CHECK(!s.reason.empty());
    CHECK((s.kind == "distortion" || s.kind == "overlap"));
  }
  for (const auto& p : pattern.pieces) {
    CHECK(p.flat.stats.flipped_triangles == 0);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(p.flat.stats.p95_error <= options.p95_limit);
    CHECK(p.flat.stats.max_error <= options.max_limit);
  }
}

TEST_CASE("seam partners keep equal lengths after flattening", "[flatten][seams]") {
  const Mesh cap = testing::make_hemisphere(3, 0.2);
  // A user seam across the cap from rim to rim, through the pole region.
  const auto loops = boundary_loops(cap.F);
  REQUIRE(loops.size() == 1);
  int a = loops[0].front(), b = a;
  for (int v : loops[0])
    if ((cap.V.row(v) - cap.V.row(a)).norm() > (cap.V.row(b) - cap.V.row(a)).norm()) b = v;
  const auto neighbors = vertex_neighbors(cap.F, static_cast<int>(cap.V.rows()));
  std::vector<SeamPath> seams{{"middle", shortest_edge_path(cap.V, neighbors, a, b), false, "test"}};
  const Pattern pattern = make_pattern(cap.V, cap.F, seams, PatternOptions{});
  CHECK(pattern.pieces.size() >= 2);
  const Layout layout = layout_pattern(pattern, LayoutOptions{});
  const auto measures = measure_seams(pattern, layout, SeamTolerance{});
  REQUIRE(measures.size() == pattern.seams.size());
  for (size_t i = 0; i < measures.size(); ++i) {
    INFO("seam " << pattern.seams[i].name);
    CHECK(measures[i].length_3d > 0.0);
    CHECK(measures[i].ok);
    CHECK(measures[i].mismatch <= std::max(0.002, 0.005 * measures[i].length_3d));
    // Both sides are within the distortion limit of the 3D length.
    CHECK(std::abs(measures[i].left_2d / measures[i].length_3d - 1.0) < 0.05);
    CHECK(std::abs(measures[i].right_2d / measures[i].length_3d - 1.0) < 0.05);
  }
  // Every cut edge has its partner: same 3D edge, two different cut vertices.
  for (const CutEdge& e : pattern.cut.edges) {
    CHECK(e.left_face != e.right_face);
    CHECK((e.left_a != e.right_a || e.left_b != e.right_b));
    CHECK(pattern.cut.origin[e.left_a] == e.a);
    CHECK(pattern.cut.origin[e.right_b] == e.b);
  }
}

TEST_CASE("no flipped triangles with a nearly degenerate triangle", "[flatten][hard]") {
  // A curved patch (a quarter of a cylinder bent along z too) in which one
  // vertex is moved almost onto the opposite edge of a triangle.
  Mesh grid = testing::make_grid(12, 12, 0.3, 0.3);
  for (int v = 0; v < grid.V.rows(); ++v) {
    const double x = grid.V(v, 0), z = grid.V(v, 2);
    grid.V(v, 1) = 0.8 * (x - 0.15) * (x - 0.15) + 0.5 * (z - 0.15) * (z - 0.15);
  }
  // Vertex (6, 6) slid to 1e-7 of the midpoint of its neighbours (5, 6)-(6, 7)
  // diagonal: the triangles beside it become slivers.
  const int c = 6 * 13 + 6, l = 6 * 13 + 5, u = 7 * 13 + 6;
  grid.V.row(c) = 0.5 * (grid.V.row(l) + grid.V.row(u)) + Eigen::RowVector3d(1e-7, 0.0, -1e-7);
  const FlattenResult r = flatten_piece(grid.V, grid.F);
  CHECK(r.stats.flipped_triangles == 0);
  CHECK(!r.boundary_overlaps);
  CHECK(r.UV.allFinite());
  CHECK(r.stats.p95_error < 0.05);
  // The same at 1000 and 1/1000 the size: distortion is scale-free.
  for (double scale : {1e-3, 1e3}) {
    const FlattenResult s = flatten_piece(grid.V * scale, grid.F);
    CHECK(s.stats.flipped_triangles == 0);
    CHECK(s.stats.p95_error == Approx(r.stats.p95_error).margin(1e-4));
  }
  // An exactly degenerate (zero-area) triangle is still flattened without flips.
  Mesh flat = testing::make_grid(6, 6, 0.2, 0.2);
  flat.V.row(3 * 7 + 3) = 0.5 * (flat.V.row(3 * 7 + 2) + flat.V.row(4 * 7 + 3));
  const FlattenResult d = flatten_piece(flat.V, flat.F);
  CHECK(d.stats.flipped_triangles == 0);
}

TEST_CASE("flattening rejects what is not a finite disk", "[flatten][errors]") {
  const Mesh cyl = testing::make_open_cylinder(12, 4, 0.1, 0.3);
  CHECK_THROWS_AS(flatten_piece(cyl.V, cyl.F), GeometryError);  // two boundary loops
  Mesh grid = testing::make_grid(4, 4);
  grid.V(5, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(flatten_piece(grid.V, grid.F), GeometryError);
  const Mesh torus = testing::make_torus(16, 8);
  CHECK_THROWS_AS(make_pattern(torus.V, torus.F, {}, PatternOptions{}), GeometryError);
}

TEST_CASE("a closed or multiply bounded piece gets topological cuts first", "[auto_cut]") {
  const Mesh cyl = testing::make_open_cylinder(24, 8, 0.1, 0.3);
  const Pattern pattern = make_pattern(cyl.V, cyl.F, {}, PatternOptions{});
  REQUIRE(!pattern.seams.empty());
  CHECK(pattern.seams.front().kind == "topology");
  CHECK(pattern.seams.front().reason.find("2 boundary loops") != std::string::npos);
  CHECK(pattern.meets_limit);
  const Mesh sphere = testing::make_icosphere(2, 0.1);
  PatternOptions loose;
  loose.p95_limit = 0.2;
  loose.max_limit = 0.5;
  const Pattern closed = make_pattern(sphere.V, sphere.F, {}, loose);
  CHECK(closed.seams.front().kind == "topology");
  for (const auto& p : closed.pieces) CHECK(p.flat.stats.flipped_triangles == 0);
}

TEST_CASE("scraps merge back across added cuts when the merged piece meets the limit", "[auto_cut][merge]") {
  // A tight limit on a sphere's cap: greedy cuts leave small pieces.
  const Mesh cap = testing::make_hemisphere(3, 0.15);
  PatternOptions options;
  options.p95_limit = 0.01;
  options.max_limit = 0.03;
  options.merge_area = 0.0;
  const Pattern greedy = make_pattern(cap.V, cap.F, {}, options);
  options.merge_area = 1.0;  // every added cut is a candidate
  const Pattern merged = make_pattern(cap.V, cap.F, {}, options);
  auto smallest = [](const Pattern& p) {
    double a = 1e9;
    for (const auto& q : p.pieces) a = std::min(a, q.flat.stats.area_3d);
    return a;
  };
  INFO("greedy: " << greedy.pieces.size() << " pieces, " << greedy.seams.size() << " seams, smallest "
                  << smallest(greedy) << " m^2; merged: " << merged.pieces.size() << " pieces, "
                  << merged.seams.size() << " seams, smallest " << smallest(merged) << " m^2");
  REQUIRE(greedy.meets_limit);
  CHECK(greedy.merged_cuts.empty());
  CHECK(merged.meets_limit);
  CHECK(merged.seams_within_tolerance);
  CHECK(!merged.merged_cuts.empty());
  CHECK(merged.pieces.size() < greedy.pieces.size());
  CHECK(merged.seams.size() + merged.merged_cuts.size() == greedy.seams.size());
  CHECK(smallest(merged) >= smallest(greedy));
  for (const auto& name : merged.merged_cuts)
    for (const auto& s : merged.seams) CHECK(s.name != name);
  for (const auto& p : merged.pieces) {
    CHECK(p.meets_limit);
    CHECK(p.flat.stats.flipped_triangles == 0);
    CHECK(!p.flat.boundary_overlaps);
  }
}

TEST_CASE("merging scraps leaves every failing piece as it was", "[auto_cut][merge]") {
  // Cut caps that stop short of a tight limit: pieces still fail when the
  // scraps are merged. A merge may only keep a failing piece unchanged (same
  // faces, same flattening); it must never make a piece fail.
  const Mesh cap = testing::make_hemisphere(3, 0.15);
  PatternOptions options;
  options.p95_limit = 0.01;
  options.max_limit = 0.03;
  for (int max_cuts : {10, 24, 32}) {
    options.max_added_cuts = max_cuts;
    options.merge_area = 0.0;
    const Pattern greedy = make_pattern(cap.V, cap.F, {}, options);
    options.merge_area = 1.0;
    const Pattern merged = make_pattern(cap.V, cap.F, {}, options);
    INFO("cap " << max_cuts << ": " << greedy.pieces.size() << " pieces, " << merged.merged_cuts.size() << " merged");
    CHECK(!merged.meets_limit);
    CHECK(merged.cut_cap_reached);
    for (const auto& p : merged.pieces) {
      if (p.meets_limit) continue;
      const auto same = std::find_if(greedy.pieces.begin(), greedy.pieces.end(),
                                     [&](const PatternPiece& q) { return q.face_ids == p.face_ids; });
      REQUIRE(same != greedy.pieces.end());
      CHECK(!same->meets_limit);
      CHECK(same->flat.stats.p95_error == Approx(p.flat.stats.p95_error).epsilon(1e-12));
      CHECK(same->flat.stats.max_error == Approx(p.flat.stats.max_error).epsilon(1e-12));
    }
  }
}

TEST_CASE("rest-shape diagnostics find growth, tucks and cone points", "[diagnostics]") {
  const Mesh grid = testing::make_grid(6, 6, 0.3, 0.3);  // flat, 7 x 7 vertices, 5 cm edges
  const double cone = 2.0 * M_PI * 0.05;
  const RestShapeDiagnostics same = diagnose_rest_shape(grid.V, grid.V, grid.F, cone);
  CHECK(same.area_growth == Approx(1.0));
  CHECK(same.growth_max == Approx(1.0));
  CHECK(same.turned_faces == 0);
  CHECK(same.cone_points == 0);
  CHECK(same.abs_defect_sum == Approx(0.0).margin(1e-9));
  // Grown 1.5 times along x: no cone, growth 1.5 everywhere.
  Mesh wide = grid;
  wide.V.col(0) *= 1.5;
  const RestShapeDiagnostics grown = diagnose_rest_shape(grid.V, wide.V, grid.F, cone);
  CHECK(grown.area_growth == Approx(1.5));
  CHECK(grown.growth_p95 == Approx(1.5));
  CHECK(grown.cone_points == 0);
  // An inner vertex lifted 10 cm: a tent, a cone point with a large defect.
  const int centre = 3 * 7 + 3;
  REQUIRE(grid.V(centre, 0) == Approx(0.15));
  Mesh tent = grid;
  tent.V(centre, 1) += 0.1;
  const RestShapeDiagnostics lifted = diagnose_rest_shape(grid.V, tent.V, grid.F, cone);
  CHECK(lifted.cone_points >= 1);
  CHECK(lifted.max_abs_defect > cone);
  CHECK(lifted.growth_max > 1.5);
  // The same vertex pushed across its neighbour (8 cm along x): faces turn over.
  Mesh tuck = grid;
  tuck.V(centre, 0) += 0.08;
  const RestShapeDiagnostics turned = diagnose_rest_shape(grid.V, tuck.V, grid.F, cone);
  CHECK(turned.turned_faces >= 1);
  CHECK(turned.turned_area_fraction > 0.0);
  CHECK_THROWS_AS(diagnose_rest_shape(grid.V, grid.V.topRows(10), grid.F, cone), GeometryError);
}
