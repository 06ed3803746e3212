#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "core/error.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pattern/curve_insertion.h"
#include "pattern/dart_placement.h"
#include "pattern/mesh_cut.h"
#include "pattern/surface_curve.h"
#include "testing/test_meshes.h"
#include "test_helpers.h"

using namespace gp;

namespace {

// The flat grid in the xz-plane as a chart: (x, z).
Eigen::MatrixXd chart_of(const Mesh& grid) {
  Eigen::MatrixXd UV(grid.V.rows(), 2);
  UV.col(0) = grid.V.col(0);
  UV.col(1) = grid.V.col(2);
  return UV;
}

double distance_to_line(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = (b - a).normalized();
  const Eigen::Vector2d q = p - a;
  return std::abs(q.x() * d.y() - q.y() * d.x());
}

}  // namespace

TEST_CASE("a straight line traced across a grid crosses its edges on the line", "[curve]") {
  // make_grid's faces are clockwise seen from +y in the xz-plane; flip them.
  Mesh grid = testing::make_grid(10, 10, 1.0, 1.0);
  grid.F.col(1).swap(grid.F.col(2));
  const Eigen::MatrixXd UV = chart_of(grid);
  // From vertex (1, 1) to a point inside a face near the far corner.
  const int start = 1 * 11 + 1;
  const Eigen::Vector2d a = UV.row(start), b(0.83, 0.71);
  int face = -1;
  Eigen::Vector3d bary;
  for (int f = 0; f < grid.F.rows() && face < 0; ++f) {
    const Eigen::Vector2d p0 = UV.row(grid.F(f, 0)), p1 = UV.row(grid.F(f, 1)), p2 = UV.row(grid.F(f, 2));
    Eigen::Matrix2d M;
    M << p1 - p0, p2 - p0;
    const Eigen::Vector2d w = M.inverse() * (b - p0);
    if (w.minCoeff() >= 0.0 && w.sum() <= 1.0) face = f, bary = Eigen::Vector3d(1.0 - w.sum(), w.x(), w.y());
  }
  REQUIRE(face >= 0);
  Eigen::MatrixXd P(2, 2);
  P.row(0) = a;
  P.row(1) = b;
  TraceOptions o;
  o.min_edge_fraction = 0.0;
  const SurfaceCurve c = trace_polyline(UV, grid.F, CurvePoint::at_vertex(start), CurvePoint::in_face(face, bary), P, {}, o);
  REQUIRE(c.size() > 5);
  CHECK(c.front().is_vertex());
  CHECK(c.back().is_face());
  for (size_t i = 1; i + 1 < c.size(); ++i) {
    CHECK(c[i].is_edge());
    CHECK(distance_to_line(curve_point_position(UV, grid.F, c[i]), a, b) < 1e-12);
  }
  CHECK(curve_length(UV, grid.F, c) == Approx((b - a).norm()).epsilon(1e-12));
  // Leaving the chart gives no curve.
  P.row(1) = Eigen::Vector2d(1.5, 0.5);
  CHECK(trace_polyline(UV, grid.F, CurvePoint::at_vertex(start), CurvePoint::in_face(face, bary), P, {}, o).empty());
}

TEST_CASE("curves inserted into a mesh become edge paths that cut it in two", "[curve]") {
  const Mesh cyl = testing::make_open_cylinder(24, 10, 0.1, 0.4);
  // A seam along a wavy edge path up the cylinder, smoothed through the triangles.
  std::vector<int> path;
  for (int j = 0; j <= 10; ++j) path.push_back(j * 24 + (j % 2));
  bool smoothed = false;
  const SurfaceCurve c = smooth_edge_path(cyl.V, cyl.F, path, {path.front(), path.back()}, false, EdgePathSmoothing{},
                                          &smoothed);
  REQUIRE(smoothed);
  CHECK(c.front().is_vertex());
  CHECK(c.back().is_vertex());
  // Smoother and no longer than the zigzag.
  double zigzag = 0.0;
  for (size_t i = 0; i + 1 < path.size(); ++i) zigzag += (cyl.V.row(path[i + 1]) - cyl.V.row(path[i])).norm();
  CHECK(curve_length(cyl.V, cyl.F, c) < zigzag);
  const RefinedMesh r = insert_curves(cyl.V, cyl.F, {c});
  // The same surface: same area, the input's vertices first and unchanged.
  CHECK(face_areas(r.V, r.F).sum() == Approx(face_areas(cyl.V, cyl.F).sum()).epsilon(1e-12));
  CHECK((r.V.topRows(cyl.V.rows()) - cyl.V).cwiseAbs().maxCoeff() == 0.0);
  CHECK(r.parent_face.size() == static_cast<size_t>(r.F.rows()));
  // The refined mesh is a manifold with the cylinder's topology.
  CHECK(euler_characteristic(r.F) == 0);
  CHECK(boundary_loops(r.F).size() == 2);
  // Cut along the curve's path: one disk.
  REQUIRE(r.paths.size() == 1);
  const CutMesh cut = cut_mesh(r.V, r.F, {{0, r.paths[0], false}});
  CHECK(boundary_loops(cut.F).size() == 1);
  CHECK(euler_characteristic(cut.F) == 1);
  // Every new vertex lies where its origin says.
  for (int v = static_cast<int>(cyl.V.rows()); v < r.V.rows(); ++v) {
    const SurfacePoint& s = r.origin[static_cast<size_t>(v)];
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) x += s.bary[k] * cyl.V.row(cyl.F(s.face, k)).transpose();
    CHECK((x - r.V.row(v).transpose()).norm() < 1e-12);
  }
}

TEST_CASE("two curves crossing inside a face are refused", "[curve][errors]") {
  Mesh grid = testing::make_grid(2, 2, 1.0, 1.0);
  grid.F.col(1).swap(grid.F.col(2));
  // Face 0's corners, and two chords across it that cross.
  const int f = 0;
  const int a = grid.F(f, 0), b = grid.F(f, 1), c = grid.F(f, 2);
  const SurfaceCurve one{CurvePoint::on_edge(a, b, 0.5), CurvePoint::at_vertex(c)};
  const SurfaceCurve two{CurvePoint::on_edge(b, c, 0.5), CurvePoint::at_vertex(a)};
  CHECK_THROWS_AS(insert_curves(grid.V, grid.F, {one, two}), GeometryError);
}

TEST_CASE("curve points that coincide are merged into one vertex", "[curve]") {
  Mesh grid = testing::make_grid(2, 2, 1.0, 1.0);
  grid.F.col(1).swap(grid.F.col(2));
  const int f = 0;
  const int a = grid.F(f, 0), b = grid.F(f, 1), c = grid.F(f, 2);
  const int n = static_cast<int>(grid.V.rows());
  const double area = face_areas(grid.V, grid.F).sum();
  // A dart-like junction: the second curve ends at the first one's point
  // inside face 0 (two registrations of the same barycentric point), and a
  // third runs from an edge point that coincides with a corner (t = 0).
  const Eigen::Vector3d tip(0.4, 0.3, 0.3);
  const SurfaceCurve one{CurvePoint::on_edge(a, b, 0.5), CurvePoint::in_face(f, tip), CurvePoint::on_edge(b, c, 0.5)};
  const SurfaceCurve two{CurvePoint::at_vertex(c), CurvePoint::in_face(f, tip)};
  const SurfaceCurve three{CurvePoint::on_edge(a, c, 0.0), CurvePoint::in_face(f, tip)};
  const RefinedMesh r = insert_curves(grid.V, grid.F, {one, two, three});
  // The tip is one vertex, shared by the three paths; the corner point is the corner.
  REQUIRE(r.paths.size() == 3);
  CHECK(r.paths[0].size() == 3);
  const int tip_id = r.paths[0][1];
  CHECK(r.paths[1] == std::vector<int>{c, tip_id});
  CHECK(r.paths[2] == std::vector<int>{a, tip_id});
  // New vertices: the two edge midpoints and the tip, no more; every one used by a face.
  CHECK(r.V.rows() == n + 3);
  CHECK(static_cast<int>(r.origin.size()) == r.V.rows());
  std::vector<int> used(static_cast<size_t>(r.V.rows()), 0);
  for (int g = 0; g < r.F.rows(); ++g)
    for (int k = 0; k < 3; ++k) used[static_cast<size_t>(r.F(g, k))] = 1;
  for (int v = 0; v < r.V.rows(); ++v) CHECK(used[static_cast<size_t>(v)] == 1);
  // The refinement covers the mesh exactly once, and stays a manifold disk.
  CHECK(face_areas(r.V, r.F).sum() == Approx(area).epsilon(1e-12));
  CHECK(boundary_loops(r.F).size() == 1);
  CHECK(euler_characteristic(r.F) == 1);
  for (int g = 0; g < r.F.rows(); ++g) {
    const Eigen::Vector3d p0 = r.V.row(r.F(g, 0)), p1 = r.V.row(r.F(g, 1)), p2 = r.V.row(r.F(g, 2));
    CHECK((p1 - p0).cross(p2 - p0).norm() > 1e-6);
  }
  // Every vertex lies where its origin says.
  for (int v = n; v < r.V.rows(); ++v) {
    const SurfacePoint& s = r.origin[static_cast<size_t>(v)];
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) x += s.bary[k] * grid.V.row(grid.F(s.face, k)).transpose();
    CHECK((x - r.V.row(v).transpose()).norm() < 1e-12);
  }
}

TEST_CASE("a staircase within the tolerance is straightened whatever its wavelength", "[curve][smoothing]") {
  // An edge path's staircase along the x axis: steps of 1 cm, repeating every
  // 30 cm (longer than the 12 cm wavelength), sampled every 5 mm.
  const int n = 201;
  Eigen::MatrixXd P(n, 2);
  for (int i = 0; i < n; ++i) {
    const double x = 0.005 * i;
    P.row(i) = Eigen::Vector2d(x, std::fmod(x, 0.3) < 0.15 ? 0.0 : 0.01);
  }
  P(n - 1, 1) = 0.0;
  auto worst_y = [](const Eigen::MatrixXd& X) {
    double w = 0.0;
    for (int i = 0; i < X.rows(); ++i) w = std::max(w, std::abs(X(i, 1) - 0.005));
    return w;
  };
  auto distance = [&](const Eigen::MatrixXd& X) {
    double worst = 0.0;
    for (int r = 0; r < X.rows(); ++r) {
      double d = std::numeric_limits<double>::infinity();
      for (int i = 0; i + 1 < P.rows(); ++i) {
        const Eigen::Vector2d a = P.row(i), ab = P.row(i + 1) - P.row(i), q = X.row(r);
        const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        d = std::min(d, (a + t * ab - q).norm());
      }
      worst = std::max(worst, d);
    }
    return worst;
  };
  // The smoothing spline alone keeps the steps (a 30 cm wave passes it).
  const Eigen::MatrixXd spline = smooth_polyline_2d(P, {}, 0.005, 0.12);
  // Trusted only to 8 mm, the path is a nearly straight line through the
  // steps' middle, however long their period.
  const Eigen::MatrixXd within = smooth_polyline_2d(P, {}, 0.005, 0.12, nullptr, 0.008);
  INFO("spline leaves the path by " << distance(spline) << " m, the tolerant curve by " << distance(within));
  CHECK(distance(within) < 0.008 * 1.1);
  // Away from the pinned ends (at y = 0), it stays within 2.5 mm of y = 5 mm.
  CHECK(worst_y(within.middleRows(40, n - 80)) < 0.0025);
  CHECK(worst_y(spline.middleRows(40, n - 80)) > 0.004);
  // A real bend, ten times the tolerance, is followed within 1.5 times it.
  Eigen::MatrixXd B(n, 2);
  for (int i = 0; i < n; ++i) B.row(i) = Eigen::Vector2d(0.005 * i, 0.08 * std::sin(M_PI * 0.005 * i));
  P = B;
  const Eigen::MatrixXd bend = smooth_polyline_2d(B, {}, 0.005, 0.12, nullptr, 0.008);
  CHECK(distance(bend) < 0.008 * 1.5);
  // Nothing moves with no tolerance on an exact straight line.
  Eigen::MatrixXd L(n, 2);
  for (int i = 0; i < n; ++i) L.row(i) = Eigen::Vector2d(0.005 * i, 0.0);
  CHECK(smooth_polyline_2d(L, {}, 0.005, 0.12, nullptr, 0.008).col(1).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("two darts' chart lines cross or not", "[curve][darts]") {
  auto line = [](double x0, double y0, double x1, double y1) {
    Eigen::MatrixXd P(2, 2);
    P << x0, y0, x1, y1;
    return P;
  };
  CHECK(polylines_cross(line(0, 0, 1, 1), line(0, 1, 1, 0)));
  CHECK(polylines_cross(line(0, 0, 1, 0), line(0.5, 0, 0.5, 1)));  // a tip on the other's leg
  CHECK_FALSE(polylines_cross(line(0, 0, 1, 0), line(0, 0.1, 1, 0.1)));
  CHECK_FALSE(polylines_cross(line(0, 0, 1, 0), line(2, 0, 3, 0)));  // collinear, apart
  CHECK_FALSE(polylines_cross(line(0, 0, 1, 0), line(1, 0, 1, 1)));  // a shared end
  Eigen::MatrixXd bent(3, 2);
  bent << 0, -1, 0.5, 0.5, 1, -1;
  CHECK(polylines_cross(bent, line(0, 0, 1, 0)));
}

TEST_CASE("dart tips are two kernel radii apart even where mean shift climbs back to a taken mode", "[curve][darts]") {
  // A spherical cap, wider than the kernel: its angle defect is spread
  // evenly, so the mean shift from any start well inside climbs to the one
  // mode near the top. Two darts to the same tip would coincide: a slit
  // between them with no area, which no flattening survives.
  const Mesh sphere = testing::make_icosphere(4, 0.1);
  std::vector<Eigen::Vector3i> faces;
  for (int f = 0; f < sphere.F.rows(); ++f) {
    const double y = (sphere.V(sphere.F(f, 0), 1) + sphere.V(sphere.F(f, 1), 1) + sphere.V(sphere.F(f, 2), 1)) / 3.0;
    if (y > -0.05) faces.emplace_back(sphere.F(f, 0), sphere.F(f, 1), sphere.F(f, 2));
  }
  const Mesh cap = testing::compact(sphere.V, faces);
  PatternOptions options;
  options.darts.max_darts = 0;
  options.panels.max_pieces = 1;
  const Pattern pattern = make_pattern(cap.V, cap.F, {}, options);
  REQUIRE(pattern.pieces.size() == 1);
  for (const int count : {2, 4}) {
    const std::vector<DartTip> tips = dart_tips(pattern, 0, options, count);
    REQUIRE(!tips.empty());
    for (const DartTip& t : tips) UNSCOPED_INFO("tip at " << t.point.transpose() << ", " << t.curvature << " rad");
    CHECK(static_cast<int>(tips.size()) <= count);
    for (size_t i = 0; i < tips.size(); ++i)
      for (size_t j = i + 1; j < tips.size(); ++j) {
        INFO("tips " << i << " and " << j << " of " << tips.size() << " (asked for " << count << ")");
        CHECK((tips[i].point - tips[j].point).norm() >= 2.0 * options.darts.kernel_radius);
      }
  }
}
