#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "garment/surface_path.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pattern/export_report.h"
#include "pattern/flatten.h"
#include "pattern/layout.h"
#include "pattern/make_pattern.h"
#include "pattern/mesh_cut.h"
#include "pattern/rest_diagnostics.h"
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

// A doubly curved patch: the grid bent along x and z.
Mesh bent_grid(int n, double size) {
  Mesh g = testing::make_grid(n, n, size, size);
  for (int v = 0; v < g.V.rows(); ++v) {
    const double x = g.V(v, 0) - 0.5 * size, z = g.V(v, 2) - 0.5 * size;
    g.V(v, 1) = 0.8 * x * x + 0.5 * z * z;
  }
  return g;
}

}  // namespace

TEST_CASE("an open cylinder cut along one seam flattens to its exact rectangle", "[flatten]") {
  const int nu = 24, nv = 10;
  const double radius = 0.12, height = 0.5;
  const Mesh cyl = testing::make_open_cylinder(nu, nv, radius, height);
  std::vector<SeamPath> seams{{"side", cylinder_seam(nu, nv), false, "test", {0, nv * nu}}};
  const Pattern pattern = make_pattern(cyl.V, cyl.F, seams, PatternOptions{});
  REQUIRE(pattern.pieces.size() == 1);
  REQUIRE(pattern.seams.size() == 1);  // no extra cut: a cylinder is developable
  const PatternPiece& p = pattern.pieces.front();
  CHECK(p.flat.stats.flipped_triangles == 0);
  CHECK(p.flat.stats.max_error < 1e-6);
  CHECK(p.stats.max_error < 1e-6);
  CHECK(pattern.meets_limit);
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

TEST_CASE("a hemisphere gets darts and seams and its distortion falls", "[flatten][cutter]") {
  const Mesh cap = testing::make_hemisphere(4, 0.15);
  PatternOptions options;
  // Uncut, the cap is far outside the limit and still has no flipped triangle.
  // (Flattened plainly: the limit weighting takes the uncut cap's
  // compression over its worst 1 % down to 6.9 %.)
  PatternOptions none = options;
  none.darts.max_darts = 0;
  none.panels.max_pieces = 1;
  none.flatten.limit_rounds = 0;
  const Pattern uncut = make_pattern(cap.V, cap.F, {}, none);
  REQUIRE(uncut.pieces.size() == 1);
  CHECK(!uncut.meets_limit);
  CHECK(uncut.pieces[0].flat.stats.flipped_triangles == 0);
  const double before = uncut.pieces[0].stats.worst1_compression;
  CHECK(before > 3.0 * options.limit.compression_worst1);

  const Pattern pattern = make_pattern(cap.V, cap.F, {}, options);
  for (const auto& s : pattern.seams) {
    CHECK(!s.reason.empty());
    CHECK((s.kind == "dart" || s.kind == "panel"));
  }
  CHECK(pattern.seams.size() >= 1);
  CHECK(static_cast<int>(pattern.pieces.size()) <= options.panels.max_pieces);
  double worst = 0.0;
  for (const auto& p : pattern.pieces) {
    CHECK(p.flat.stats.flipped_triangles == 0);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(static_cast<int>(p.dart_seams.size()) <= options.darts.max_darts);
    CHECK(p.stats.area_3d >= options.panels.min_piece_area);
    worst = std::max(worst, p.stats.worst1_compression);
  }
  INFO("compression over the worst 1 % uncut " << before << ", cut " << worst << " in " << pattern.pieces.size() << " pieces");
  CHECK(worst < 0.5 * before);
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
  std::vector<SeamPath> seams{{"middle", shortest_edge_path(cap.V, neighbors, a, b), false, "test", {a, b}}};
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
    CHECK(std::abs(measures[i].left_2d / measures[i].length_3d - 1.0) < 0.05);
    CHECK(std::abs(measures[i].right_2d / measures[i].length_3d - 1.0) < 0.05);
  }
  // Every cut edge has its partner: same edge of the pattern mesh, two different cut vertices.
  for (const CutEdge& e : pattern.cut.edges) {
    CHECK(e.left_face != e.right_face);
    CHECK((e.left_a != e.right_a || e.left_b != e.right_b));
    CHECK(pattern.cut.origin[e.left_a] == e.a);
    CHECK(pattern.cut.origin[e.right_b] == e.b);
  }
}

TEST_CASE("the one-sided energy's gradient matches finite differences", "[flatten][energy]") {
  const Mesh g = bent_grid(6, 0.3);
  const auto loops = boundary_loops(g.F);
  Eigen::MatrixXd UV = lscm_flatten(g.V, g.F, loops.front());
  // A distorted map: stretched along u, squeezed along v, with a twist.
  for (int v = 0; v < UV.rows(); ++v) {
    const double u = UV(v, 0), w = UV(v, 1);
    UV(v, 0) = 1.15 * u + 0.05 * w * w;
    UV(v, 1) = 0.9 * w + 0.02 * u;
  }
  for (double ease_weight : {1.0, 0.25}) {
    FlattenOptions o;
    o.ease_weight = ease_weight;
    Eigen::MatrixXd grad;
    const double e0 = flattening_energy(g.V, g.F, UV, o, &grad);
    CHECK(e0 > 0.0);
    const double h = 1e-7;
    double worst = 0.0, scale = grad.cwiseAbs().maxCoeff();
    for (int v = 0; v < UV.rows(); v += 5)
      for (int c = 0; c < 2; ++c) {
        Eigen::MatrixXd P = UV, M = UV;
        P(v, c) += h;
        M(v, c) -= h;
        const double fd = (flattening_energy(g.V, g.F, P, o, nullptr) - flattening_energy(g.V, g.F, M, o, nullptr)) / (2 * h);
        worst = std::max(worst, std::abs(fd - grad(v, c)));
      }
    INFO("ease weight " << ease_weight << ": gradient scale " << scale << ", worst difference " << worst);
    CHECK(worst < 1e-5 * scale);
  }
}

TEST_CASE("a one-sided flattening trades compression for ease", "[flatten][energy]") {
  const Mesh cap = testing::make_hemisphere(3, 0.15);
  FlattenOptions arap, one_sided;
  arap.ease_weight = 1.0;
  one_sided.ease_weight = 0.1;
  const FlattenResult a = flatten_piece(cap.V, cap.F, arap);
  const FlattenResult b = flatten_piece(cap.V, cap.F, one_sided);
  INFO("compression p99 " << a.stats.p99_compression << " -> " << b.stats.p99_compression << ", ease p95 "
                          << a.stats.p95_stretch << " -> " << b.stats.p95_stretch);
  CHECK(b.stats.p99_compression < 0.95 * a.stats.p99_compression);
  CHECK(b.stats.p95_stretch > 1.1 * a.stats.p95_stretch);
  CHECK(b.stats.flipped_triangles == 0);
}

TEST_CASE("the bulk's ease is the median of the principal stretches, the tail's is not", "[flatten][energy]") {
  // A grid laid flat at its own size and then scaled by 1.02 along x: every
  // triangle is eased by 2 % in one direction and held in the other.
  const Mesh g = testing::make_grid(8, 8, 0.4, 0.4);
  Eigen::MatrixXd UV(g.V.rows(), 2);
  UV.col(0) = 1.02 * g.V.col(0);
  UV.col(1) = g.V.col(2);
  const DistortionStats s = distortion_stats(g.V, g.F, UV);
  CHECK(s.median_ease == Approx(0.02).epsilon(1e-9));
  CHECK(s.median_compression == Approx(0.0).margin(1e-12));
  CHECK(s.worst5_ease == Approx(0.02).epsilon(1e-9));
  // A hemisphere in one piece: ARAP compresses its median triangle by 17.6 %
  // (and eases it by -2.7 %); the one-sided energy shifts the bulk towards
  // ease (14.9 % and 0.09 %), its tail eased far more (41.9 % over the
  // worst 5 %).
  const Mesh cap = testing::make_hemisphere(3, 0.15);
  FlattenOptions arap, one_sided;
  arap.ease_weight = 1.0;
  one_sided.ease_weight = 0.1;
  const DistortionStats a = flatten_piece(cap.V, cap.F, arap).stats;
  const DistortionStats b = flatten_piece(cap.V, cap.F, one_sided).stats;
  INFO("ARAP: median ease " << a.median_ease << ", median compression " << a.median_compression
                            << "; one-sided: " << b.median_ease << ", " << b.median_compression << ", worst 5 % "
                            << b.worst5_ease);
  CHECK(b.median_ease > a.median_ease);
  CHECK(b.median_compression < a.median_compression);
  CHECK(b.median_ease > 0.0);
  CHECK(b.median_ease < 0.5 * b.worst5_ease);
}

TEST_CASE("the weighted energy's gradient matches finite differences", "[flatten][energy]") {
  const Mesh g = bent_grid(6, 0.3);
  const auto loops = boundary_loops(g.F);
  Eigen::MatrixXd UV = lscm_flatten(g.V, g.F, loops.front());
  for (int v = 0; v < UV.rows(); ++v) UV.row(v) = Eigen::RowVector2d(1.12 * UV(v, 0), 0.93 * UV(v, 1) + 0.03 * UV(v, 0) * UV(v, 0));
  // Face weights as the limit weighting leaves them: uneven, some far above 1.
  Eigen::VectorXd w(g.F.rows());
  for (int f = 0; f < g.F.rows(); ++f) w[f] = 1.0 + 7.0 * ((f * 37) % 11) / 10.0;
  FlattenOptions o;
  o.ease_weight = 0.1;
  Eigen::MatrixXd grad;
  const double e0 = flattening_energy(g.V, g.F, UV, o, &grad, &w);
  CHECK(e0 > flattening_energy(g.V, g.F, UV, o));  // every weight is at least 1, most above
  const double h = 1e-7, scale = grad.cwiseAbs().maxCoeff();
  double worst = 0.0;
  for (int v = 0; v < UV.rows(); v += 3)
    for (int c = 0; c < 2; ++c) {
      Eigen::MatrixXd P = UV, M = UV;
      P(v, c) += h;
      M(v, c) -= h;
      const double fd = (flattening_energy(g.V, g.F, P, o, nullptr, &w) - flattening_energy(g.V, g.F, M, o, nullptr, &w)) / (2 * h);
      worst = std::max(worst, std::abs(fd - grad(v, c)));
    }
  INFO("gradient scale " << scale << ", worst difference " << worst);
  CHECK(worst < 1e-5 * scale);
}

namespace {

// A cap of a sphere, uncut: the one-sided flattening leaves its worst
// compression at the rim and its worst ease at the pole region. The faces
// of a hemisphere of radius 0.15 m above `fraction` of its height (0.55:
// the upper half, a cap of 45 degrees; plain, 17 / 31 % of compression /
// ease; 0.8: 9.5 / 17 %).
Mesh upper_cap(double fraction = 0.55) {
  const Mesh cap = testing::make_hemisphere(4, 0.15);
  std::vector<Eigen::Vector3i> faces;
  double top = cap.V.col(1).maxCoeff(), bottom = cap.V.col(1).minCoeff();
  if (std::abs(top) < std::abs(bottom)) std::swap(top, bottom);
  for (int f = 0; f < cap.F.rows(); ++f) {
    bool keep = true;
    for (int k = 0; k < 3; ++k) keep = keep && std::abs(cap.V(cap.F(f, k), 1) - bottom) >= fraction * std::abs(top - bottom);
    if (keep) faces.push_back(cap.F.row(f));
  }
  return testing::compact(cap.V, faces);
}

}  // namespace

TEST_CASE("the limit weighting lowers a piece's tails towards the limit", "[flatten][limit]") {
  const Mesh part = upper_cap();
  FlattenOptions plain = PatternOptions::default_flatten();
  plain.limit_rounds = 0;
  const FlattenResult a = flatten_piece(part.V, part.F, plain);
  // Limits a little under what the plain flattening reaches.
  FlattenOptions weighted = plain;
  weighted.limit_rounds = 12;
  weighted.limit_compression = 0.9 * a.stats.worst1_compression;
  weighted.limit_ease = 0.9 * a.stats.worst5_ease;
  const FlattenResult b = flatten_piece(part.V, part.F, weighted);
  auto ratio = [&](const DistortionStats& s) {
    return std::max(s.worst1_compression / weighted.limit_compression, s.worst5_ease / weighted.limit_ease);
  };
  INFO(part.F.rows() << " faces; plain: compression " << a.stats.worst1_compression << ", ease " << a.stats.worst5_ease
                     << "; weighted (" << b.limit_rounds << " rounds): " << b.stats.worst1_compression << ", "
                     << b.stats.worst5_ease << "; mean error " << a.stats.mean_error << " -> " << b.stats.mean_error);
  CHECK(a.stats.worst1_compression > 0.005);
  CHECK(b.limit_rounds > 0);
  CHECK(b.face_weight.size() == part.F.rows());
  CHECK(b.face_weight.maxCoeff() > 1.0);
  CHECK(b.face_weight.minCoeff() == 1.0);
  CHECK(ratio(b.stats) < ratio(a.stats) - 0.05);
  CHECK(b.stats.flipped_triangles == 0);
  // The tails come down at the cost of the rest: the mean distortion rises.
  CHECK(b.stats.mean_error > a.stats.mean_error);
  // Polishing keeps the weights: the piece stays where the weighting left it.
  FlattenResult c = b;
  polish_flattening(part.V, part.F, c, weighted);
  CHECK(ratio(c.stats) < ratio(a.stats) - 0.05);
  // Off: no weights.
  CHECK(a.face_weight.size() == 0);
  CHECK(a.limit_rounds == 0);
}

TEST_CASE("the limit weighting compresses no triangle beyond the budget", "[flatten][limit]") {
  // The weighting pushes the cloth of its eased triangles into the
  // compression of the triangles around them; the sewn garment must stretch
  // those out. With the cutter's budget no triangle the plain flattening
  // left within it ends beyond it. A smaller cap (460 faces), which the
  // weighting brings within the limit.
  const Mesh part = upper_cap(0.8);
  const Eigen::VectorXd area = face_areas(part.V, part.F);
  FlattenOptions plain = PatternOptions::default_flatten();
  plain.limit_rounds = 0;
  const FlattenResult a = flatten_piece(part.V, part.F, plain);
  // The weighting as the cutter runs it (export-rest --limit-rounds 20),
  // with the test cap's budget: half its fit's delta of 0.04
  // (PanelOptions::weighting_budget_share, common/export/tests/test_sewn_fit.cpp).
  FlattenOptions weighted = PatternOptions::default_flatten();
  weighted.limit_rounds = 20;
  weighted.limit_compression = 0.03;
  weighted.limit_ease = 0.1;
  weighted.compression_budget = PanelOptions{}.weighting_budget_share * 0.04;  // half the test cap's delta of 0.04 (common/export/tests/test_sewn_fit.cpp)
  FlattenOptions unbudgeted = weighted;
  unbudgeted.compression_budget = 0.0;
  const FlattenResult b = flatten_piece(part.V, part.F, weighted);
  const FlattenResult u = flatten_piece(part.V, part.F, unbudgeted);
  const Eigen::MatrixXd Sa = flattening_stretches(part.V, part.F, a.UV);
  // The area (fraction) of the triangles within the budget in the plain
  // flattening that `r` compresses beyond it, and the worst such compression.
  auto beyond = [&](const FlattenResult& r, double budget) {
    const Eigen::MatrixXd S = flattening_stretches(part.V, part.F, r.UV);
    double moved = 0.0, total = 0.0, worst = 0.0;
    for (int f = 0; f < part.F.rows(); ++f) {
      total += area[f];
      if (1.0 - Sa(f, 1) > budget || 1.0 - S(f, 1) <= budget) continue;
      moved += area[f];
      worst = std::max(worst, 1.0 - S(f, 1));
    }
    return std::make_pair(moved / total, worst);
  };
  auto ratio = [&](const DistortionStats& s) {
    return std::max(s.worst1_compression / weighted.limit_compression, s.worst5_ease / weighted.limit_ease);
  };
  const auto [b_moved, b_worst] = beyond(b, weighted.compression_budget);
  const auto [u_moved, u_worst] = beyond(u, weighted.compression_budget);
  INFO(part.F.rows() << " faces; plain: " << a.stats.worst1_compression << " / " << a.stats.worst5_ease
                     << ", max compression " << a.stats.max_compression << "; budgeted (" << b.limit_rounds
                     << " rounds): " << b.stats.worst1_compression << " / " << b.stats.worst5_ease << ", max "
                     << b.stats.max_compression << ", moved beyond the budget " << b_moved << " (worst " << b_worst
                     << "); unbudgeted (" << u.limit_rounds << " rounds): " << u.stats.worst1_compression << " / "
                     << u.stats.worst5_ease << ", moved " << u_moved << " (worst " << u_worst << ")");
  REQUIRE(weighted.compression_budget == Approx(0.02));
  // The plain flattening is far over the limit (9.5 / 17.0 %).
  CHECK(a.stats.worst1_compression == Approx(0.0946).margin(0.003));
  CHECK(a.stats.worst5_ease == Approx(0.1697).margin(0.005));
  // With the budget: within the limit, and no triangle the plain flattening
  // left within the budget is compressed beyond it (a tenth of a percent
  // of rounding allowed, kCeilingTolerance).
  CHECK(b.limit_rounds > 0);
  CHECK(ratio(b.stats) <= 1.0);
  CHECK(b_worst <= weighted.compression_budget + 1e-3);
  CHECK(b_moved == 0.0);
  CHECK(b.stats.worst1_compression < weighted.compression_budget + 1e-3);
  CHECK(b.stats.flipped_triangles == 0);
  // Without it the same rounds meet the limit too, but by compressing
  // 18 % of the piece beyond the budget, up to 2.8 %.
  CHECK(ratio(u.stats) <= 1.0);
  CHECK(u_moved > 0.1);
  CHECK(u_worst > 0.025);
  // The cutter's default: on, with its budget (pattern README, "The limit weighting").
  CHECK(PatternOptions{}.flatten.limit_rounds == 20);
  CHECK(PatternOptions{}.panels.weighting_budget_share == 0.5);
}

TEST_CASE("Anderson-accelerated iterations reach plain local/global's minimum", "[flatten]") {
  const Mesh g = bent_grid(14, 0.4);
  const auto loops = boundary_loops(g.F);
  const Eigen::MatrixXd start = lscm_flatten(g.V, g.F, loops.front());
  FlattenOptions o;
  o.tolerance = 1e-12;
  o.max_iterations = 20000;
  Eigen::MatrixXd fast = start;
  const ArapRun a = arap_flatten(g.V, g.F, fast, o, false);
  // Plain local/global from the same start: the same energy.
  FlattenOptions plain = o;
  plain.anderson_window = 0;
  Eigen::MatrixXd slow = start;
  const ArapRun b = arap_flatten(g.V, g.F, slow, plain, false);
  INFO("accelerated " << a.iterations << " iterations, energy " << a.energy << "; plain " << b.iterations << ", "
                      << b.energy);
  CHECK(a.energy == Approx(b.energy).epsilon(1e-6));
  CHECK(a.iterations < b.iterations);
}

TEST_CASE("no flipped triangles with a nearly degenerate triangle", "[flatten][hard]") {
  // A curved patch in which one vertex is moved almost onto the opposite
  // edge of a triangle.
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

TEST_CASE("a closed or multiply bounded piece gets topological cuts first", "[cutter]") {
  const Mesh cyl = testing::make_open_cylinder(24, 8, 0.1, 0.3);
  const Pattern pattern = make_pattern(cyl.V, cyl.F, {}, PatternOptions{});
  REQUIRE(!pattern.seams.empty());
  CHECK(pattern.seams.front().kind == "topology");
  CHECK(pattern.seams.front().reason.find("2 boundary loops") != std::string::npos);
  CHECK(pattern.meets_limit);
  const Mesh sphere = testing::make_icosphere(2, 0.1);
  const Pattern closed = make_pattern(sphere.V, sphere.F, {}, PatternOptions{});
  CHECK(closed.seams.front().kind == "topology");
  for (const auto& p : closed.pieces) CHECK(p.flat.stats.flipped_triangles == 0);
}

TEST_CASE("a tube's topological cut keeps off its front and back", "[cutter]") {
  // A cylinder along y: its front faces +z. The cut joining its two loops
  // runs down a side (|x| large), not the front or the back.
  const Mesh cyl = testing::make_open_cylinder(32, 10, 0.1, 0.4);
  const Pattern pattern = make_pattern(cyl.V, cyl.F, {}, PatternOptions{});
  REQUIRE(pattern.seams.front().kind == "topology");
  const auto& path = pattern.seams.front().vertex_ids;
  double nz = 0.0;
  for (int v : path) nz = std::max(nz, std::abs(pattern.mesh.V(v, 2)) / 0.1);
  CHECK(nz < 0.5);
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

TEST_CASE("cone points count inside a piece only a margin away from its seams and boundary", "[diagnostics]") {
  // The tent of the test above: the lifted centre is a cone, 15 cm from the
  // grid's border. Uncut, it lies inside the one piece with a 1 cm margin,
  // and not with a 20 cm one; cut along the middle row through the centre,
  // it is on a seam, where pieces meet. The flat design has no cone.
  const Mesh grid = testing::make_grid(6, 6, 0.3, 0.3);
  const double cone = 2.0 * M_PI * 0.05;
  const int centre = 3 * 7 + 3;
  Mesh tent = grid;
  tent.V(centre, 1) += 0.1;
  const RestShapeDiagnostics lifted = diagnose_rest_shape(grid.V, tent.V, grid.F, cone);
  REQUIRE(lifted.cone_points >= 1);
  const InnerCones uncut = cone_points_inside_pieces(grid.V, tent.V, grid.F, cone, tent.V, grid.F, 0.01);
  CHECK(uncut.rest == lifted.cone_points);
  CHECK(uncut.design == 0);
  CHECK(cone_points_inside_pieces(grid.V, tent.V, grid.F, cone, tent.V, grid.F, 0.2).rest == 0);
  CutPath middle;
  for (int i = 0; i < 7; ++i) middle.vertex_ids.push_back(3 * 7 + i);
  const CutMesh cut = cut_mesh(tent.V, grid.F, {middle});
  const InnerCones on_seam = cone_points_inside_pieces(grid.V, tent.V, grid.F, cone, cut.V, cut.F, 0.01);
  CHECK(on_seam.rest < uncut.rest);
  CHECK_THROWS_AS(cone_points_inside_pieces(grid.V, tent.V.topRows(10), grid.F, cone, tent.V, grid.F, 0.01),
                  GeometryError);
}

TEST_CASE("a tuck flattens injectively without squeezed triangles", "[flatten][hard]") {
  // A flat grid (5 cm edges) with one inner vertex pushed 8 cm across its
  // neighbour: its faces turn over, as in a rest shape's tuck. The piece has
  // more cloth around that vertex than a flat sheet holds, so plain
  // iterations fold it and the flip-free ones must squeeze something.
  Mesh tuck = testing::make_grid(6, 6, 0.3, 0.3);
  tuck.V(3 * 7 + 3, 0) += 0.08;
  const FlattenResult r = flatten_piece(tuck.V, tuck.F);
  CHECK(r.stats.flipped_triangles == 0);
  CHECK(r.initialization.find("injective") != std::string::npos);
  const Eigen::MatrixXd S = flattening_stretches(tuck.V, tuck.F, r.UV);
  // Flip-free ARAP steps squeezed a triangle of this piece to s2 = 1e-16
  // (max s1 1.30); the barrier keeps every triangle open (s2 0.47, s1 2.03).
  CHECK(S.col(1).minCoeff() > 0.1);
  CHECK(S.col(0).maxCoeff() < 10.0);
  // Every flat triangle is a usable rest triangle for the cloth model
  // (quality 2A / longest edge^2 well above its 1e-6 bound).
  double worst = 1.0;
  for (int f = 0; f < tuck.F.rows(); ++f) {
    const Eigen::Vector2d a = r.UV.row(tuck.F(f, 0)), b = r.UV.row(tuck.F(f, 1)), c = r.UV.row(tuck.F(f, 2));
    const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    const double longest2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    worst = std::min(worst, area2 / longest2);
  }
  CHECK(worst > 1e-3);
}

TEST_CASE("injective iterations lower the symmetric Dirichlet energy without flips", "[flatten]") {
  const Mesh g = bent_grid(10, 0.4);
  const auto loops = boundary_loops(g.F);
  REQUIRE(loops.size() == 1);
  Eigen::MatrixXd UV = tutte_flatten(g.V, g.F, loops.front());
  FlattenOptions o;
  const double before = symmetric_dirichlet_energy(g.V, g.F, UV, o);
  const ArapRun run = injective_flatten(g.V, g.F, UV, o);
  CHECK(run.iterations > 0);
  CHECK(symmetric_dirichlet_energy(g.V, g.F, UV, o) < 0.1 * before);
  const DistortionStats st = distortion_stats(g.V, g.F, UV);
  CHECK(st.flipped_triangles == 0);
  // From Tutte's circle to about the plain flattening's distortion.
  const FlattenResult plain = flatten_piece(g.V, g.F, o);
  CHECK(st.p95_error < plain.stats.p95_error + 0.02);
  // A flipped start is refused; a flipped UV has infinite energy.
  Eigen::MatrixXd mirrored = UV;
  mirrored.col(0) *= -1.0;
  CHECK(std::isinf(symmetric_dirichlet_energy(g.V, g.F, mirrored, o)));
  CHECK_THROWS_AS(injective_flatten(g.V, g.F, mirrored, o), GeometryError);
}
