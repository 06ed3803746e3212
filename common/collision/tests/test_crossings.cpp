// The crossing detector: exact segment/triangle predicates on hand-made cases
// (through, touching at an edge or a corner, parallel, coplanar, degenerate
// triangles and segments, NaN), and whole meshes: a sheet through a sphere,
// a sheet beside it, a finger through a sheet between its vertices.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "collision/crossings.h"
#include "collision/triangle_tree.h"
#include "core/error.h"
#include "testing/test_meshes.h"

using gp::collision::segment_meets_triangle;
using Eigen::Vector3d;

namespace {

const Vector3d P(0, 0, 0), Q(1, 0, 0), R(0, 1, 0);

// The grid patch of test_meshes (xz-plane, y = 0) centred on the origin,
// side `size`, moved up by `height`; its normals point along +y or -y
// depending on the grid's winding, which the tests do not rely on.
gp::Mesh sheet(int n, double size, double height) {
  gp::Mesh m = gp::testing::make_grid(n, n, size, size);
  for (int v = 0; v < m.V.rows(); ++v) {
    m.V(v, 0) -= 0.5 * size;
    m.V(v, 2) -= 0.5 * size;
    m.V(v, 1) += height;
  }
  return m;
}

}  // namespace

TEST_CASE("segment against triangle: through, beside, touching, parallel", "[collision][crossings]") {
  // Through the interior.
  CHECK(segment_meets_triangle(Vector3d(0.2, 0.2, -1), Vector3d(0.2, 0.2, 1), P, Q, R));
  // Beside it (the plane is crossed outside the triangle).
  CHECK_FALSE(segment_meets_triangle(Vector3d(0.6, 0.6, -1), Vector3d(0.6, 0.6, 1), P, Q, R));
  // Stops short of the plane.
  CHECK_FALSE(segment_meets_triangle(Vector3d(0.2, 0.2, -1), Vector3d(0.2, 0.2, -1e-12), P, Q, R));
  // Ends exactly on the plane inside the triangle: touching counts.
  CHECK(segment_meets_triangle(Vector3d(0.2, 0.2, -1), Vector3d(0.2, 0.2, 0), P, Q, R));
  // Through an edge and through a corner (closed triangle).
  CHECK(segment_meets_triangle(Vector3d(0.5, 0.5, -1), Vector3d(0.5, 0.5, 1), P, Q, R));
  CHECK(segment_meets_triangle(Vector3d(1, 0, -1), Vector3d(1, 0, 1), P, Q, R));
  // Just beyond the edge, by one ulp-scale amount: exact predicates see it.
  const double beyond = 0.5 + 1e-15;
  CHECK_FALSE(segment_meets_triangle(Vector3d(beyond, beyond, -1), Vector3d(beyond, beyond, 1), P, Q, R));
  // Parallel above the plane, and lying in the plane across the triangle.
  CHECK_FALSE(segment_meets_triangle(Vector3d(-1, 0.2, 0.1), Vector3d(2, 0.2, 0.1), P, Q, R));
  CHECK(segment_meets_triangle(Vector3d(-1, 0.2, 0), Vector3d(2, 0.2, 0), P, Q, R));
  CHECK_FALSE(segment_meets_triangle(Vector3d(-1, 2, 0), Vector3d(2, 2, 0), P, Q, R));
  // Tiny and huge scales behave alike.
  for (double s : {1e-6, 1e6}) {
    CHECK(segment_meets_triangle(s * Vector3d(0.2, 0.2, -1), s * Vector3d(0.2, 0.2, 1), s * P, s * Q, s * R));
    CHECK_FALSE(segment_meets_triangle(s * Vector3d(0.6, 0.6, -1), s * Vector3d(0.6, 0.6, 1), s * P, s * Q, s * R));
  }
}

TEST_CASE("degenerate triangles and segments are decided as what they are", "[collision][crossings]") {
  // A triangle collapsed to a segment on the x axis.
  const Vector3d a(0, 0, 0), b(1, 0, 0), c(0.5, 0, 0);
  CHECK(segment_meets_triangle(Vector3d(0.3, 0, -1), Vector3d(0.3, 0, 1), a, b, c));
  CHECK_FALSE(segment_meets_triangle(Vector3d(0.3, 0.1, -1), Vector3d(0.3, 0.1, 1), a, b, c));
  CHECK_FALSE(segment_meets_triangle(Vector3d(1.5, 0, -1), Vector3d(1.5, 0, 1), a, b, c));
  // A triangle collapsed to a point.
  CHECK(segment_meets_triangle(Vector3d(0, 0, -1), Vector3d(0, 0, 1), a, a, a));
  CHECK_FALSE(segment_meets_triangle(Vector3d(1e-9, 0, -1), Vector3d(1e-9, 0, 1), a, a, a));
  // A segment that is a point: on, off the triangle.
  CHECK(segment_meets_triangle(Vector3d(0.2, 0.2, 0), Vector3d(0.2, 0.2, 0), P, Q, R));
  CHECK_FALSE(segment_meets_triangle(Vector3d(0.2, 0.2, 1e-12), Vector3d(0.2, 0.2, 1e-12), P, Q, R));
  // Both degenerate.
  CHECK(segment_meets_triangle(c, c, a, b, c));
  // Non-finite input is refused.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(segment_meets_triangle(Vector3d(nan, 0, 0), Vector3d(0, 0, 1), P, Q, R), gp::UsageError);
}

TEST_CASE("the triangle tree answers segment queries like the predicate, degenerate faces included",
          "[collision][crossings]") {
  gp::Mesh m = sheet(6, 1.0, 0.0);
  // Collapse one triangle onto its first edge (its third corner moved onto
  // the first, exactly).
  const int f_degenerate = 7;
  m.V.row(m.F(f_degenerate, 2)) = m.V.row(m.F(f_degenerate, 0));
  const gp::collision::TriangleTree tree(m.V, m.F);
  CHECK(tree.size() == m.F.rows());
  for (int i = 0; i < 50; ++i) {
    const Vector3d a(-0.6 + 0.023 * i, -0.3, -0.5 + 0.019 * i), b(0.4 - 0.017 * i, 0.2, 0.45 - 0.021 * i);
    std::vector<int> brute;
    for (int f = 0; f < m.F.rows(); ++f) {
      if (segment_meets_triangle(a, b, m.V.row(m.F(f, 0)), m.V.row(m.F(f, 1)), m.V.row(m.F(f, 2)))) brute.push_back(f);
    }
    CHECK(tree.segment_faces(a, b) == brute);
  }
  // A point query at a corner of the collapsed face finds it.
  const Vector3d on = m.V.row(m.F(f_degenerate, 1)).transpose();
  const std::vector<int> hits = tree.segment_faces(on, on);
  CHECK(std::find(hits.begin(), hits.end(), f_degenerate) != hits.end());
}

TEST_CASE("a sheet through a sphere crosses it; beside it, it does not", "[collision][crossings]") {
  const gp::Mesh body = gp::testing::make_icosphere(3, 0.3);
  SECTION("through the middle") {
    const gp::Mesh cloth = sheet(12, 1.0, 0.05);
    const gp::collision::CrossingReport r = gp::collision::find_crossings(body.V, body.F, cloth.V, cloth.F);
    CHECK(r.body_edge_crossings > 0);
    CHECK(r.cloth_edge_crossings > 0);
    CHECK_FALSE(r.intersection_free());
    // Cloth vertices within the sphere's circle at y = 0.05 lie inside, the
    // deepest at the centre: 0.3 - 0.05 = 0.25 m from the surface (the
    // icosphere's faces lie up to 1.6 % inside its circumsphere).
    CHECK(r.cloth_vertices_inside > 0);
    CHECK(r.deepest_cloth_vertex == Approx(0.25).margin(0.01));
    CHECK(r.body_vertices_behind > 0);
    CHECK(r.body_edge_examples.size() == 10);
    for (const auto& e : r.body_edge_examples) CHECK(e.a < e.b);
  }
  SECTION("above it, 1 mm clear of the top") {
    const gp::Mesh cloth = sheet(12, 1.0, 0.301);
    const gp::collision::CrossingReport r = gp::collision::find_crossings(body.V, body.F, cloth.V, cloth.F);
    CHECK(r.intersection_free());
    CHECK(r.deepest_cloth_vertex == 0.0);
    CHECK(r.body_faces_tested > 0);
  }
  SECTION("touching the top vertex counts") {
    int top = 0;
    body.V.col(1).maxCoeff(&top);
    const gp::Mesh cloth = sheet(12, 1.0, body.V(top, 1));
    const gp::collision::CrossingReport r = gp::collision::find_crossings(body.V, body.F, cloth.V, cloth.F);
    CHECK(r.body_edge_crossings > 0);
    CHECK(r.cloth_vertices_inside == 0);
  }
}

TEST_CASE("a finger through a sheet between its vertices is seen from the body side", "[collision][crossings]") {
  // A thin closed "finger" (a sphere squeezed to 5 mm radius across, 6 cm
  // long along y) poking 1 cm through a coarse sheet: no cloth vertex is
  // inside, yet body edges cross cloth triangles and the finger's tip is
  // behind the cloth by 1 cm.
  gp::Mesh finger = gp::testing::make_icosphere(3, 1.0);
  for (int v = 0; v < finger.V.rows(); ++v) {
    finger.V(v, 0) *= 0.005;
    finger.V(v, 2) *= 0.005;
    finger.V(v, 1) = 0.03 * finger.V(v, 1) - 0.02;  // y in [-0.05, 0.01]
  }
  // 6.7 cm triangles, the finger 1.2 cm or more from every cloth edge.
  gp::Mesh cloth = sheet(3, 0.2, 0.0);
  cloth.V.col(0).array() += 0.2 / 12.0;
  const gp::collision::CrossingReport r = gp::collision::find_crossings(finger.V, finger.F, cloth.V, cloth.F);
  CHECK(r.cloth_vertices_inside == 0);
  CHECK(r.body_edge_crossings > 0);
  CHECK(r.cloth_edge_crossings == 0);
  CHECK(r.body_vertices_behind > 0);
  CHECK(r.deepest_body_vertex == Approx(0.01).margin(1e-3));
  // Moved 2 cm down, it is clear.
  gp::Mesh lowered = finger;
  lowered.V.col(1).array() -= 0.02;
  CHECK(gp::collision::find_crossings(lowered.V, lowered.F, cloth.V, cloth.F).intersection_free());
}

TEST_CASE("non-finite coordinates are refused with the vertex named", "[collision][crossings]") {
  const gp::Mesh body = gp::testing::make_icosphere(1, 0.3);
  gp::Mesh cloth = sheet(3, 1.0, 0.5);
  cloth.V(5, 2) = std::numeric_limits<double>::quiet_NaN();
  try {
    gp::collision::find_crossings(body.V, body.F, cloth.V, cloth.F);
    FAIL("no error");
  } catch (const gp::GeometryError& e) {
    CHECK(e.where() == "cloth vertex 5");
  }
  gp::Mesh bad_body = body;
  bad_body.V(0, 0) = std::numeric_limits<double>::infinity();
  const gp::Mesh clean_cloth = sheet(3, 1.0, 0.5);
  CHECK_THROWS_AS(gp::collision::find_crossings(bad_body.V, bad_body.F, clean_cloth.V, clean_cloth.F),
                  gp::GeometryError);
}
