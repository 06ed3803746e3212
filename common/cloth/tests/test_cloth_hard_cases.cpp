// Hard cases for the cloth model and its time stepping:
// near-degenerate rest triangles (slivers and needles just above the rejection
// threshold 2A/L^2 >= 1e-6 of triangle_rest), inverted triangles in the initial
// positions, and triangles collapsed to a segment or a point (a deformation
// gradient with a zero singular value). Expectation everywhere: the energies,
// gradients and projected Hessians stay finite, every step ends finite (or,
// where it cannot, throws NumericalError and leaves the state as it was), and
// the cloth ends in a sensible drape, never NaN.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "cloth/cloth_model.h"
#include "cloth/cloth_simulator.h"
#include "core/error.h"
#include "testing/test_meshes.h"

using namespace gp::cloth;
using gp::testing::max_edge_stretch;

namespace {

// The paper's 2.5 ms step, which these tests were written for (the
// simulator's default is the project's 10 ms).
SimulatorOptions paper_step() {
  SimulatorOptions options;
  options.dt = 0.0025;
  return options;
}

// Grid vertex id of make_grid(n, n, ...) at column i, row j.
int grid_id(int n, int i, int j) { return j * (n + 1) + i; }

Eigen::Matrix3d face_positions(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  Eigen::Matrix3d X;
  for (int k = 0; k < 3; ++k) X.col(k) = V.row(F(f, k)).transpose();
  return X;
}

// Shape quality 2A / (longest edge)^2 of face f, the measure triangle_rest
// rejects below 1e-6.
double face_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Matrix3d X = face_positions(V, F, f);
  const Eigen::Vector3d e1 = X.col(1) - X.col(0), e2 = X.col(2) - X.col(0);
  const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
  return e1.cross(e2).norm() / longest2;
}

Eigen::Vector3d face_normal(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Matrix3d X = face_positions(V, F, f);
  return (X.col(1) - X.col(0)).cross(X.col(2) - X.col(0));
}

double min_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double q = 1e300;
  for (int f = 0; f < F.rows(); ++f) q = std::min(q, face_quality(V, F, f));
  return q;
}


// A horizontal square sheet (side `size`, n by n cells, y = 0) whose
// vertex (i+1, j) is moved towards the diagonal (i,j)-(i+1,j+1) of its cell
// until the cap triangle (i,j),(i+1,j+1),(i+1,j) has quality `q` (a sliver
// with an angle near 180 degrees).
void make_sliver(gp::Mesh& m, int n, int i, int j, double q) {
  const Eigen::RowVector3d a = m.V.row(grid_id(n, i, j)), c = m.V.row(grid_id(n, i + 1, j + 1));
  const double L = (c - a).norm();
  const Eigen::RowVector3d mid = 0.5 * (a + c);
  const Eigen::RowVector3d p = m.V.row(grid_id(n, i + 1, j));
  // 2A / L^2 = (L * eps) / L^2: the vertex ends eps = q L from the diagonal.
  m.V.row(grid_id(n, i + 1, j)) = mid + (q * L) * (p - mid).normalized();
}

// Moves vertex (i+1, j) along its edge towards (i, j) until that edge is
// `fraction` of its length: the two faces sharing the edge become needles.
void make_needle(gp::Mesh& m, int n, int i, int j, double fraction) {
  const Eigen::RowVector3d a = m.V.row(grid_id(n, i, j));
  const Eigen::RowVector3d p = m.V.row(grid_id(n, i + 1, j));
  m.V.row(grid_id(n, i + 1, j)) = a + fraction * (p - a);
}

struct SwingResult {
  Eigen::MatrixXd X;
  long rejected = 0;
  long accepted_flips = 0;
  bool all_finite = true;
  double max_speed_seen = 0.0;
};

// The sheet pinned at two adjacent corners of its x = 0 edge swings down
// under gravity for `steps` steps of dt: a large out-of-plane motion that
// rotates and bends every triangle.
SwingResult swing(const gp::Mesh& m, int n, int steps, double dt) {
  SimulatorOptions options = paper_step();
  options.dt = dt;
  ClothSimulator sim(m.V, m.F, ClothParameters{}, options);
  sim.set_pinned({grid_id(n, 0, 0), grid_id(n, 0, n)});
  SwingResult r;
  for (int s = 0; s < steps; ++s) {
    sim.step();
    r.all_finite = r.all_finite && sim.positions().allFinite() && sim.velocities().allFinite();
    r.max_speed_seen = std::max(r.max_speed_seen, sim.max_speed());
  }
  r.X = sim.positions();
  r.rejected = sim.counters().rejected;
  r.accepted_flips = sim.counters().accepted_flips;
  return r;
}

}  // namespace

namespace {

// The 0.3 m sheet of 12 by 12 cells with a sliver of quality q in cell (3,4)
// and a needle of quality 2.5 q in cell (7,8) (make_needle's fraction is
// twice the needle's quality).
gp::Mesh sheet_with_degenerate_faces(double q) {
  const int n = 12;
  gp::Mesh m = gp::testing::make_grid(n, n, 0.3, 0.3);
  make_sliver(m, n, 3, 4, q);
  make_needle(m, n, 7, 8, 5.0 * q);
  return m;
}

}  // namespace

TEST_CASE("sliver and needle rest triangles down to the threshold swing like well-shaped ones",
          "[cloth][hard]") {
  // Expectation: a sheet with a sliver and a needle of rest quality q
  // (2A/L^2; triangle_rest rejects below 1e-6) at or above the threshold
  // swings down for 0.75 s with every state finite and no rejected step, and
  // stays within 1.5 mm per vertex of the same sheet with q = 1e-3; below
  // it, building the rest state throws a GeometryError naming the face.
  const int n = 12;
  const gp::Mesh regular = gp::testing::make_grid(n, n, 0.3, 0.3);
  const gp::Mesh shaped = sheet_with_degenerate_faces(1e-3);
  const SwingResult reference = swing(shaped, n, 300, 0.0025);
  REQUIRE(reference.all_finite);
  // The sheet swung down: its free edge is far below the pins.
  CHECK(reference.X.col(1).minCoeff() < -0.2);
  for (double q : {1e-5, 2e-6, 1.01e-6, 5e-7, 2e-8}) {
    const bool accepted = q >= 1e-6;
    const gp::Mesh m = sheet_with_degenerate_faces(q);
    int bad_faces = 0;
    for (int f = 0; f < m.F.rows(); ++f) {
      if (face_quality(m.V, m.F, f) < 1e-3) ++bad_faces;
      // No other face was turned over by moving the two vertices.
      CHECK(face_normal(m.V, m.F, f).dot(face_normal(regular.V, regular.F, f)) > 0.0);
    }
    CHECK(min_quality(m.V, m.F) == Approx(q).epsilon(1e-3));
    CHECK(bad_faces == 3);  // the sliver and the needle's two faces
    SwingResult r;
    try {
      r = swing(m, n, 300, 0.0025);
    } catch (const gp::GeometryError& e) {
      INFO("q " << q << ": rejected: " << e.what());
      CHECK_FALSE(accepted);
      CHECK(std::string(e.where()).find("face") != std::string::npos);
      continue;
    }
    CHECK(accepted);
    const double distance = (r.X - reference.X).rowwise().norm().maxCoeff();
    INFO("q " << q << ": smallest rest quality " << min_quality(m.V, m.F) << ", faces under 1e-3: " << bad_faces
              << "; max distance to the well-shaped sheet " << distance << " m; rejected steps " << r.rejected
              << ", accepted folds " << r.accepted_flips << ", largest speed " << r.max_speed_seen << " m/s");
    CHECK(r.all_finite);
    CHECK(r.X.allFinite());
    CHECK(r.rejected == 0);
    CHECK(r.max_speed_seen < 5.0);
    CHECK(max_edge_stretch(r.X, m.V, m.F) < 1.1);
    CHECK(distance < 0.0015);
  }

  // Half the threshold: rejected when the rest state is built.
  gp::Mesh rejected = regular;
  make_sliver(rejected, n, 3, 4, 0.5e-6);
  CHECK_THROWS_AS(ClothSimulator(rejected.V, rejected.F), gp::GeometryError);
  // The bending stencils measure each face against its own longest edge, as
  // triangle_rest does: a needle just above the threshold is accepted by
  // both, one just below is a clean GeometryError.
  gp::Mesh needle = regular;
  make_needle(needle, n, 7, 8, 2.2e-6);
  CHECK(min_quality(needle.V, needle.F) > 1e-6);
  CHECK_NOTHROW(ClothSimulator(needle.V, needle.F));
  make_needle(needle = regular, n, 7, 8, 1.8e-6);
  CHECK(min_quality(needle.V, needle.F) < 1e-6);
  CHECK_THROWS_AS(ClothSimulator(needle.V, needle.F), gp::GeometryError);
}

TEST_CASE("slivers that once drifted are rejected; the sharpest accepted ones keep the motion accurate",
          "[cloth][hard]") {
  // Found by this test: with the old threshold 2A/L^2 >= 1e-8 the
  // membrane stiffness of a sliver (~ k / q^2 against a regular face) made
  // the implicit system too ill-conditioned: the fresh-factor fallback was
  // accepted with relative residuals of 1e-5 to 4e-3 and the motion drifted.
  // Measured max vertex distance after 0.75 s against the q = 1e-3 sheet:
  // q 1e-6 0.13 mm, 2e-7 0.95 mm, 1e-7 1.9 mm, 5e-8 5.3 mm, 3e-8 31 mm,
  // 2e-8 338 mm. The threshold is now 1e-6. Expectation: q = 2e-8 is
  // rejected with a GeometryError (or, were it accepted, moves within 5 mm).
  const int n = 12;
  const SwingResult reference = swing(sheet_with_degenerate_faces(1e-3), n, 300, 0.0025);
  const gp::Mesh m = sheet_with_degenerate_faces(2e-8);
  bool rejected = false;
  SwingResult r;
  try {
    r = swing(m, n, 300, 0.0025);
  } catch (const gp::GeometryError&) {
    rejected = true;
  }
  if (!rejected) {
    const double distance = (r.X - reference.X).rowwise().norm().maxCoeff();
    INFO("q 2e-8: max distance to the well-shaped sheet " << distance << " m");
    CHECK(distance < 0.005);
  }
  CHECK(rejected);
}

TEST_CASE("inverted triangles in the initial positions unfold or are counted as folds, never NaN",
          "[cloth][hard]") {
  // A sheet hanging at rest from its top row (vertical plane z = 0); the
  // initial positions turn triangles over: (a) one vertex mirrored through
  // the opposite edge of its triangle in the sheet's plane (that triangle
  // and its neighbours overlap), (b) a 3 by 3 vertex patch pushed 2 cm out of
  // the plane with its centre thrown 4 cm sideways and 3 cm back through it,
  // (c) one vertex thrown 5 cm through the sheet and 3 cm sideways.
  // Expectation: every step finite, no NumericalError; after 1 s no face is
  // turned against the sheet's normal (or the turn-overs were counted as
  // accepted folds), no edge stretched by 10 %, the sheet has nearly
  // stopped (under 0.2 m/s) and hangs within 5 cm of the sheet that started
  // at rest (measured 0.003 mm, 7.6 mm and 27 mm: the out-of-plane ripple
  // of (b) and (c) has almost no bending stiffness to flatten it).
  const int n = 10;
  const double size = 0.25;
  // Grid (x, 0, z) to the vertical sheet (x, -z, 0): a rotation, so the
  // grid's normal +y becomes +z.
  auto vertical = [](const Eigen::MatrixXd& V) {
    Eigen::MatrixXd W(V.rows(), 3);
    W.col(0) = V.col(0);
    W.col(1) = -V.col(2);
    W.col(2) = V.col(1);
    return W;
  };
  const gp::Mesh grid = gp::testing::make_grid(n, n, size, size);
  const Eigen::MatrixXd V_rest = vertical(grid.V);
  const Eigen::MatrixXi& F = grid.F;
  struct Start {
    const char* name;
    Eigen::MatrixXd X;
  };
  std::vector<Start> starts;
  {
    Eigen::MatrixXd X = grid.V;
    // Face (i,j),(i+1,j+1),(i+1,j) of cell (4,4): mirror (i+1,j) through the diagonal.
    const Eigen::RowVector3d a = X.row(grid_id(n, 4, 4)), c = X.row(grid_id(n, 5, 5));
    const Eigen::RowVector3d p = X.row(grid_id(n, 5, 4));
    const Eigen::RowVector3d e = (c - a).normalized();
    const Eigen::RowVector3d foot = a + (p - a).dot(e) * e;
    X.row(grid_id(n, 5, 4)) = 2.0 * foot - p;
    starts.push_back({"vertex mirrored in the plane", vertical(X)});
  }
  {
    Eigen::MatrixXd X = grid.V;
    for (int j = 4; j <= 6; ++j)
      for (int i = 4; i <= 6; ++i) X(grid_id(n, i, j), 1) = -0.02;
    X(grid_id(n, 5, 5), 1) = 0.03;
    X(grid_id(n, 5, 5), 0) += 0.04;
    starts.push_back({"patch folded back", vertical(X)});
  }
  {
    Eigen::MatrixXd X = grid.V;
    X(grid_id(n, 5, 5), 1) = -0.05;
    X(grid_id(n, 5, 5), 0) += 0.03;
    starts.push_back({"vertex thrown through the sheet", vertical(X)});
  }
  std::vector<int> pins;
  for (int i = 0; i <= n; ++i) pins.push_back(grid_id(n, i, 0));
  const int steps = 400;
  Eigen::MatrixXd X_reference;
  {
    ClothSimulator sim(V_rest, F, ClothParameters{}, paper_step());
    sim.set_pinned(pins);
    for (int s = 0; s < steps; ++s) sim.step();
    X_reference = sim.positions();
  }
  for (const Start& start : starts) {
    SECTION(start.name) {
      int inverted_at_start = 0;
      for (int f = 0; f < F.rows(); ++f) {
        if (face_normal(start.X, F, f).dot(Eigen::Vector3d::UnitZ()) < 0.0) ++inverted_at_start;
      }
      ClothSimulator sim(V_rest, F, ClothParameters{}, paper_step());
      sim.set_positions(start.X);
      sim.set_pinned(pins);
      bool finite = true;
      for (int s = 0; s < steps; ++s) {
        sim.step();
        finite = finite && sim.positions().allFinite() && sim.velocities().allFinite();
      }
      const Eigen::MatrixXd& X = sim.positions();
      int turned = 0;
      for (int f = 0; f < F.rows(); ++f) {
        if (face_normal(X, F, f).dot(Eigen::Vector3d::UnitZ()) < 0.0) ++turned;
      }
      const double distance = (X - X_reference).rowwise().norm().maxCoeff();
      INFO(start.name << ": faces inverted at the start " << inverted_at_start << ", turned at the end " << turned
                      << ", rejected steps " << sim.counters().rejected << ", accepted folds "
                      << sim.counters().accepted_flips << ", max speed " << sim.max_speed() << " m/s, edge stretch "
                      << max_edge_stretch(X, V_rest, F) << ", max distance to the sheet started at rest " << distance
                      << " m");
      CHECK(inverted_at_start >= 1);
      CHECK(finite);
      CHECK((turned == 0 || sim.counters().accepted_flips > 0));
      CHECK(max_edge_stretch(X, V_rest, F) < 1.1);
      CHECK(sim.max_speed() < 0.2);
      CHECK(distance < 0.05);
    }
  }
}

TEST_CASE("a triangle collapsed to a segment or a point has finite energy, gradient and PSD Hessian",
          "[cloth][hard]") {
  // Deformation gradients with a zero singular value: the current triangle is
  // a segment (three collinear corners, in a generic direction, along the
  // rest u axis, along the rest v axis) or a point, and near-collapses down
  // to 1e-13 m. Expectation: all terms finite; the projected Hessians and
  // the system block are positive semi-definite (smallest eigenvalue above
  // -1e-9 of the largest); the energy is the analytic value for the
  // collapsed cases.
  Eigen::Matrix3d X_rest;
  X_rest.col(0) << 0.0, 0.0, 0.0;
  X_rest.col(1) << 0.02, 0.0, 0.0;
  X_rest.col(2) << 0.0, 0.03, 0.0;  // u axis = +y (material direction), v axis = +x
  const TriangleRest rest = triangle_rest(X_rest);
  const double k_stretch = 800.0, k_shear = 200.0;
  struct Collapse {
    const char* name;
    Eigen::Matrix3d X;
    double expected_stretch;  // analytic stretch energy, < 0 when not checked
  };
  std::vector<Collapse> cases;
  Eigen::Matrix3d X;
  X.col(0) << 0.1, 0.2, 0.3;
  X.col(1) = X.col(0);
  X.col(2) = X.col(0);
  // Both w vanish: stretch energy k A / 2 (1 + 1).
  cases.push_back({"point", X, k_stretch * rest.area});
  X.col(0) << 0.0, 0.0, 0.0;
  X.col(1) << 0.04, 0.0, 0.0;
  X.col(2) << 0.0, 0.0, 0.0;
  // x2 on x0: the u edge (along +y at rest) vanishes, w_u = 0; w_v stretched x2.
  cases.push_back({"segment, w_u = 0", X, 0.5 * k_stretch * rest.area * (1.0 + 1.0)});
  X.col(0) << 0.0, 0.0, 0.0;
  X.col(1) << 0.0, 0.0, 0.0;
  X.col(2) << 0.0, 0.045, 0.0;
  cases.push_back({"segment, w_v = 0", X, 0.5 * k_stretch * rest.area * (0.25 + 1.0)});
  X.col(0) << 0.0, 0.0, 0.0;
  X.col(1) << 0.01, 0.02, -0.01;
  X.col(2) << 0.03, 0.06, -0.03;
  cases.push_back({"segment, generic direction", X, -1.0});
  X.col(0) << 0.0, 0.0, 0.0;
  X.col(1) << 0.02, 0.0, 0.0;
  X.col(2) << 1e-13, 0.0, 0.0;
  cases.push_back({"near-collapse, 1e-13 m", X, -1.0});
  X.col(2) << 1e-10, 1e-13, 1e-13;
  cases.push_back({"near-collapse, 1e-10 m", X, -1.0});

  auto psd_ok = [](const Matrix9d& H) {
    const Eigen::SelfAdjointEigenSolver<Matrix9d> es(0.5 * (H + H.transpose()));
    const double largest = std::max(es.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
    return es.eigenvalues().minCoeff() >= -1e-9 * largest;
  };
  for (const Collapse& c : cases) {
    INFO(c.name);
    const double e_stretch = stretch_energy(c.X, rest, k_stretch);
    const double e_shear = shear_energy(c.X, rest, k_shear);
    CHECK(std::isfinite(e_stretch));
    CHECK(std::isfinite(e_shear));
    if (c.expected_stretch >= 0.0) CHECK(e_stretch == Approx(c.expected_stretch).epsilon(1e-12));
    CHECK(stretch_gradient(c.X, rest, k_stretch).allFinite());
    CHECK(shear_gradient(c.X, rest, k_shear).allFinite());
    const Matrix9d Hs = stretch_hessian(c.X, rest, k_stretch, true);
    const Matrix9d Hh = shear_hessian(c.X, rest, k_shear, true);
    CHECK(Hs.allFinite());
    CHECK(Hh.allFinite());
    CHECK(psd_ok(Hs));
    CHECK(psd_ok(Hh));
    CHECK(stretch_hessian(c.X, rest, k_stretch, false).allFinite());
    CHECK(shear_hessian(c.X, rest, k_shear, false).allFinite());
    CHECK(stretch_damping(c.X, rest, 100.0).allFinite());
    CHECK(shear_damping(c.X, rest, 1.0).allFinite());
    Vector9d g;
    Matrix9d K;
    // The symmetric stretch term (compression ratio 1), as the expected energies assume.
    const double e = membrane_system_block(c.X, rest, MembraneCoefficients{k_stretch, k_shear, 100.0, 1.0, 1.0},
                                           0.0025, g, K);
    CHECK(std::isfinite(e));
    CHECK(e == Approx(e_stretch + e_shear).epsilon(1e-12));
    CHECK(g.allFinite());
    CHECK(K.allFinite());
    CHECK(psd_ok(K));
  }
}

TEST_CASE("a step from a state with collapsed triangles is finite and the triangles recover", "[cloth][hard]") {
  // A horizontal sheet at rest, then: one vertex placed on the opposite edge
  // of its triangle (segment), and one cell's three corners of another
  // triangle gathered on one point (point; its neighbours become segments).
  // Expectation: model energies and gradient finite; every step finite with
  // no NumericalError; after 0.5 s the collapsed triangles have regained at
  // least half of their rest area and none is turned over.
  const int n = 10;
  const double size = 0.25;
  const gp::Mesh m = gp::testing::make_grid(n, n, size, size);
  ClothParameters params;
  const ClothRestState rest = build_rest_state(m.V, m.F, params);
  Eigen::MatrixXd X = m.V;
  // Segment: face (2,2),(3,3),(3,2) with (3,2) moved onto the diagonal's midpoint.
  const int seg_face = 2 * (2 * n + 2) + 1;
  REQUIRE(m.F(seg_face, 2) == grid_id(n, 3, 2));
  X.row(grid_id(n, 3, 2)) = 0.5 * (m.V.row(grid_id(n, 2, 2)) + m.V.row(grid_id(n, 3, 3)));
  // Point: face (6,6),(6,7),(7,7) gathered on its centroid.
  const int point_face = 2 * (6 * n + 6);
  REQUIRE(m.F(point_face, 0) == grid_id(n, 6, 6));
  const Eigen::RowVector3d centroid =
      (m.V.row(grid_id(n, 6, 6)) + m.V.row(grid_id(n, 6, 7)) + m.V.row(grid_id(n, 7, 7))) / 3.0;
  for (int v : {grid_id(n, 6, 6), grid_id(n, 6, 7), grid_id(n, 7, 7)}) X.row(v) = centroid;
  REQUIRE(face_normal(X, m.F, seg_face).norm() < 1e-15);
  REQUIRE(face_normal(X, m.F, point_face).norm() == 0.0);

  const ClothEnergies e = cloth_energies(X, m.F, rest, params);
  INFO("energies at the collapsed state: stretch " << e.stretch << " shear " << e.shear << " bend " << e.bend);
  CHECK(std::isfinite(e.total()));
  CHECK(e.stretch > 0.0);
  CHECK(cloth_gradient(X, m.F, rest, params).allFinite());

  ClothSimulator sim(m.V, m.F, params, paper_step());
  std::vector<int> pins;
  for (int j = 0; j <= n; ++j) pins.push_back(grid_id(n, 0, j));
  sim.set_positions(X);
  sim.set_pinned(pins);
  sim.step();
  CHECK(sim.positions().allFinite());
  CHECK(sim.velocities().allFinite());
  bool finite = true;
  for (int s = 1; s < 200; ++s) {
    sim.step();
    finite = finite && sim.positions().allFinite();
  }
  CHECK(finite);
  const Eigen::MatrixXd& Y = sim.positions();
  for (int f : {seg_face, point_face}) {
    const double area_ratio = face_normal(Y, m.F, f).norm() / face_normal(m.V, m.F, f).norm();
    // Orientation against the neighbouring faces of the same cell row.
    const Eigen::Vector3d n_local = face_normal(Y, m.F, f + 2) + face_normal(Y, m.F, f - 2);
    INFO("face " << f << ": area / rest area " << area_ratio << ", rejected steps " << sim.counters().rejected
                 << ", accepted folds " << sim.counters().accepted_flips);
    CHECK(area_ratio > 0.5);
    CHECK(face_normal(Y, m.F, f).dot(n_local) > 0.0);
  }
  CHECK(max_edge_stretch(Y, m.V, m.F) < 1.1);
}

namespace {

// The 12 by 12 sheet of 0.3 m hanging in the xy plane from its two top
// corners, with the four corners of cell (5, 5) drawn towards the cell's
// centre until the cell is `length` wide and `width` high: a cluster of tiny
// slivers (quality 2A/L^2 about width / length) like the one a remeshed design
// can leave, whose vertex masses are far below the others' and whose bending
// stencils are far stiffer than their membrane.
gp::Mesh hanging_sheet_with_tiny_cell(double length, double width) {
  const int n = 12;
  const double cell = 0.3 / n;
  gp::Mesh m = gp::testing::make_grid(n, n, 0.3, 0.3);
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  const int corners[4] = {grid_id(n, 5, 5), grid_id(n, 6, 5), grid_id(n, 5, 6), grid_id(n, 6, 6)};
  for (int v : corners) centre += 0.25 * m.V.row(v);
  for (int v : corners) {
    const Eigen::RowVector3d d = m.V.row(v) - centre;
    m.V.row(v) = centre + Eigen::RowVector3d(d(0) * length / cell, 0.0, d(2) * width / cell);
  }
  for (int v = 0; v < m.V.rows(); ++v) m.V.row(v) = Eigen::RowVector3d(m.V(v, 0), -m.V(v, 2), 0.0);
  return m;
}

}  // namespace

TEST_CASE("a cluster of tiny rest triangles makes the solver factor the whole matrix", "[cloth][hard]") {
  const int n = 12;
  // A cell 1 mm by 1 um (quality about 1e-3; the benchmark's dress had a
  // cluster 0.1 mm across at 2e-3). Measured: 50 CG iterations per
  // factorization with the membrane pattern kept, 2.9 by default.
  const gp::Mesh m = hanging_sheet_with_tiny_cell(1e-3, 1e-6);
  const int steps = 40;
  double iterations_per_factor[2] = {0, 0};
  Eigen::MatrixXd X[2];
  long fallbacks[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    SimulatorOptions options = paper_step();
    options.dt = 0.01;
    if (k == 0) options.membrane_max_iterations = 1000000;  // the membrane pattern kept whatever it costs
    ClothSimulator sim(m.V, m.F, ClothParameters{}, options);
    sim.set_pinned({grid_id(n, 0, 0), grid_id(n, n, 0)});
    for (int s = 0; s < steps; ++s) sim.step();
    REQUIRE(sim.positions().allFinite());
    iterations_per_factor[k] =
        static_cast<double>(sim.counters().cg_iterations) / static_cast<double>(sim.counters().factorizations);
    fallbacks[k] = sim.counters().membrane_fallbacks;
    X[k] = sim.positions();
  }
  INFO("CG iterations per factorization: membrane pattern kept " << iterations_per_factor[0] << ", default "
                                                                 << iterations_per_factor[1]);
  CHECK(iterations_per_factor[0] > 30.0);
  CHECK(iterations_per_factor[1] < 6.0);
  CHECK(fallbacks[0] == 0);
  CHECK(fallbacks[1] == 1);
  // Both solve the same system to the CG tolerance.
  CHECK((X[0] - X[1]).cwiseAbs().maxCoeff() < 1e-4);
}
