// Hard cases for the adaptation and the motion run, at the
// library level: a collapsed simulated triangle inside a stretched mesh (the
// pseudo-inverse path through the whole adapter), a garment starting partly
// inside a generated body, a pose change in a single frame, and a time step
// four times the paper's. Each test states its expectation; figures measured
// on this machine are in the comments.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "adapt/garment_motion.h"
#include "adapt/rest_adapter.h"
#include "collision/body_collider.h"
#include "core/error.h"
#include "garment/garment_file.h"
#include "hard_case_scene.h"
#include "motion_test_helpers.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "testing/test_meshes.h"

using namespace gp;
using namespace gp::adapt;
using gp::testing::max_edge_stretch;
namespace hc = gp::hard_cases;
using hc::Loaded;
using hc::check_same_fit;
using hc::load;
using hc::motion_of;
using hc::run;
using hc::run_options;

namespace {

Eigen::Vector3d face_normal(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  return (b - a).cross(c - a);
}

double face_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  const double longest2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  return (b - a).cross(c - a).norm() / longest2;
}


}  // namespace

TEST_CASE("a collapsed triangle in a stretched patch adapts through the pseudo-inverse to a sound rest shape",
          "[adapt][hard]") {
  // A 0.3 m patch stretched by 1.3 along x (every triangle clipped), with one
  // vertex moved onto the opposite edge of its triangle: that triangle's
  // deformation gradient has a zero singular value. Expectation: its target
  // is the rest triangle stretched by 1.3/1.1 along the surviving direction
  // and left alone along the collapsed one (pseudo-inverse, factor 1), so it
  // is neither degenerate nor flipped; the stitched rest shape is finite,
  // every face keeps its orientation and a quality above 0.2 (measured
  // 0.31), and the collapsed face keeps at least half its rest area (its
  // target grows along the diagonal while its neighbours grow along x, so
  // the stitching compromises: measured 0.76 of the rest area).
  const int n = 8;
  const gp::Mesh grid = gp::testing::make_grid(n, n, 0.3, 0.3);
  Eigen::MatrixXd V_sim = grid.V;
  V_sim.col(0) *= 1.3;
  // Cell (3,3), face (i,j),(i+1,j+1),(i+1,j): (i+1,j) onto the diagonal's midpoint.
  const int collapsed = 2 * (3 * n + 3) + 1;
  const int moved = grid.F(collapsed, 2);
  V_sim.row(moved) = 0.5 * (V_sim.row(grid.F(collapsed, 0)) + V_sim.row(grid.F(collapsed, 1)));

  Eigen::Matrix3d X_rest, X_sim;
  for (int k = 0; k < 3; ++k) {
    X_rest.col(k) = grid.V.row(grid.F(collapsed, k)).transpose();
    X_sim.col(k) = V_sim.row(grid.F(collapsed, k)).transpose();
  }
  const Eigen::Matrix2d Fg = deformation_gradient(X_rest, X_sim);
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(Fg);
  INFO("singular values of the collapsed face " << svd.singularValues().transpose());
  CHECK(svd.singularValues()(1) < 1e-12);
  CHECK(svd.singularValues()(0) > 1.1);
  const Eigen::Matrix2d D_rest = triangle_frame_edges(X_rest);
  const Eigen::Matrix2d T = clipped_target(D_rest, Fg, 0.1, 0.0);
  CHECK(T.allFinite());
  // Area factor s1 / 1.1 along the stretched direction, 1 along the collapsed one.
  CHECK(T.determinant() == Approx(D_rest.determinant() * svd.singularValues()(0) / 1.1).epsilon(1e-9));

  AdaptOptions paper_rule;
  paper_rule.margin = 0.0;
  paper_rule.hysteresis = 0.0;  // clipped to exactly 1 + delta, as the targets above
  RestShapeAdapter adapter(grid.V, grid.F, paper_rule);
  Eigen::MatrixXd V_rest = grid.V;
  const AdaptReport r = adapter.adapt(V_sim, V_rest);
  INFO("clipped " << r.clip.clipped_faces << " of " << grid.F.rows() << ", ARAP iterations " << r.arap.iterations
                  << " residual " << r.arap.residual << ", area " << r.area_before << " -> " << r.area_after);
  CHECK(r.changed);
  CHECK(r.arap.converged);
  REQUIRE(V_rest.allFinite());
  double q_min = 1e300;
  for (int f = 0; f < grid.F.rows(); ++f) {
    q_min = std::min(q_min, face_quality(V_rest, grid.F, f));
    CHECK(face_normal(V_rest, grid.F, f).dot(face_normal(grid.V, grid.F, f)) > 0.0);
  }
  INFO("smallest rest quality after adaptation " << q_min);
  CHECK(q_min > 0.2);
  const double area_ratio = face_normal(V_rest, grid.F, collapsed).norm() / face_normal(grid.V, grid.F, collapsed).norm();
  INFO("collapsed face: rest area after / before " << area_ratio);
  CHECK(T.determinant() >= D_rest.determinant());
  CHECK(area_ratio > 0.5);
  // The patch as a whole grew by about 1.3 / 1.1 along x; the smoothing's
  // further rounds spread the collapsed face's misfit into some more growth
  // (measured 1.22).
  CHECK(r.area_after / r.area_before == Approx(1.3 / 1.1).epsilon(0.04));
}

TEST_CASE("a top starting partly inside the body is pushed out without tearing", "[adapt][hard][body]") {
  // The front of the top (vertices within 12 cm of the chest's front and at
  // most 2.5 cm from the body) is pushed 2.5 cm into the body, so it starts
  // up to 1.5 cm inside (3.5 cm where the design was already closer than its
  // offset). Expectation (run_garment_motion, A-pose, 200 settling steps,
  // simulate-adapt's defaults): the garment ends outside, deepest
  // penetration under 2 mm (measured 0); nothing torn: no edge stretched by
  // half against the design rest shape (measured 1.36; the same top started
  // where it was designed 1.05, with the continuous contact, which a start
  // inside the body leaves off), the stretch against the adapted rest shape
  // is at the limit (p99 <= 1.1) and the rest area grows by no more than
  // 1 % more than the clean start's. The two drapes differ by a few
  // centimetres (free hem and sleeves), which is not asserted.
  const hc::Scene& scene = hc::default_scene();
  const Loaded l = load(scene);
  const Eigen::MatrixXd& V_body = l.poses.V[static_cast<size_t>(l.poses.index_of("apose", "test"))];
  Eigen::MatrixXd V_start = l.mesh.V;
  gp::collision::BodyCollider collider(l.poses.F);
  collider.set_body(V_body);
  int pushed = 0;
  for (int v = 0; v < V_start.rows(); ++v) {
    const Eigen::Vector3d p = V_start.row(v);
    if (std::abs(p.y() - scene.chest_y) > 0.12 || std::abs(p.x()) > 0.12 || p.z() < 0.0) continue;
    const gp::collision::Proximity q = collider.query(p);
    if (q.signed_distance > 0.025) continue;
    V_start.row(v) -= 0.025 * q.outward.transpose();
    ++pushed;
  }
  double deepest_start = 0.0;
  for (int v = 0; v < V_start.rows(); ++v) {
    deepest_start = std::max(deepest_start, -collider.query(V_start.row(v).transpose()).signed_distance);
  }
  INFO("vertices pushed in " << pushed << " of " << V_start.rows() << ", deepest at the start " << deepest_start
                             << " m");
  REQUIRE(pushed >= 10);
  REQUIRE(deepest_start > 0.01);

  const MotionRunOptions options = run_options(200);
  const gp::MotionSpec motion = motion_of(l.poses, {"apose"}, 1);
  const MotionRunResult clean = run(l, motion, l.mesh.V, options);
  const MotionRunResult r = run(l, motion, V_start, options);
  REQUIRE(r.keys.size() == 1);
  const KeyPoseResult& k = r.keys[0];
  const double tear = max_edge_stretch(k.V_draped, l.mesh.V, l.mesh.F);
  const double tear_clean = max_edge_stretch(clean.keys[0].V_draped, l.mesh.V, l.mesh.F);
  INFO("initial min distance " << r.initial_min_distance << " m; deepest at the key pose " << k.deepest_penetration
                               << " m; largest edge stretch vs design " << tear << " (clean start " << tear_clean
                               << "); max stretch vs rest " << k.max_stretch << ", p99 " << k.p99_stretch
                               << "; rest area x" << k.rest_area_growth << " (clean start x"
                               << clean.keys[0].rest_area_growth << "); max distance to the clean start's drape "
                               << (k.V_draped - clean.keys[0].V_draped).rowwise().norm().maxCoeff()
                               << " m; rejected steps " << r.solver.rejected << ", folds " << r.solver.accepted_flips);
  CHECK(r.initial_min_distance < -0.01);
  CHECK(k.V_draped.allFinite());
  CHECK(r.V_rest.allFinite());
  CHECK(k.deepest_penetration < 0.002);
  CHECK(tear < 1.5);
  CHECK(k.p99_stretch <= 1.1);
  CHECK(k.rest_area_growth < clean.keys[0].rest_area_growth + 0.01);
}

TEST_CASE("a pose change in one frame stops with NumericalError", "[adapt][hard][body]") {
  // A-pose to arms-up in a single frame: the arms sweep through the sleeves
  // within one 2.5 ms step (body speeds of ~100 m/s). The step cannot be
  // taken safely: the run throws NumericalError and returns nothing, rather
  // than a torn or penetrating drape. Measured: "cloth step failed after 4
  // halvings of the time step: vertex speed above 20 m/s". (The test used to
  // accept a finished run as well, so it could not fail; a solver that does
  // finish this jump untorn should change it to the finished outcome.)
  const hc::Scene& scene = hc::default_scene();
  const Loaded l = load(scene);
  const gp::MotionSpec motion = motion_of(l.poses, {"apose", "armsup"}, 1);
  const MotionRunOptions options = run_options(100);
  try {
    run(l, motion, l.mesh.V, options);
    FAIL("the run finished the one-frame jump");
  } catch (const gp::NumericalError& e) {
    const std::string message = e.what();
    INFO("stopped: " << message);
    CHECK(message.find("cloth step failed after 4 halvings of the time step") != std::string::npos);
    CHECK(message.find("vertex speed above 20") != std::string::npos);
  }
}

TEST_CASE("four times the default time step gives nearly the same fit", "[adapt][hard][body]") {
  // A-pose to T-pose in 10 frames, then settling, at the default dt (240
  // settling steps) and at 4 dt (60 steps: the same simulated time); the
  // default is 10 ms, so 4 dt is 40 ms.
  // Expectation: both complete; at every key pose the drapes agree within
  // 7 cm at any vertex and 1.5 cm on average, the rest-area growth within
  // 1.5 % and the 99th-percentile stretch within 0.01. Measured with the
  // continuous contact, which keeps the sleeves on arms that sweep 15 cm a
  // step at 4 dt: T-pose 5.6 cm and 1.1 cm, growth 1.0410 against 1.0300,
  // p99 1.0988 against 1.0982 (the free hem and sleeve ends settle
  // differently; before it, 3.2 cm and 4.0 mm, growth 1.0505 against 1.0443,
  // measured when the default step was the paper's 2.5 ms).
  const hc::Scene& scene = hc::default_scene();
  const Loaded l = load(scene);
  const gp::MotionSpec motion = motion_of(l.poses, {"apose", "tpose"}, 10);
  MotionRunOptions small = run_options(240);
  MotionRunOptions large = run_options(60);
  large.solver.dt = 4.0 * small.solver.dt;
  large.settle.fixed_point_steps = small.settle.fixed_point_steps / 4;
  const MotionRunResult a = run(l, motion, l.mesh.V, small);
  const MotionRunResult b = run(l, motion, l.mesh.V, large);
  REQUIRE(a.keys.size() == 2);
  check_same_fit(a, b, 0.07, 0.015, 0.015);
}

TEST_CASE("settling with a hundredth of the damping reaches the same fit", "[adapt][body]") {
  // A-pose to T-pose in 10 frames, then settling (cap 1,500) with the
  // material's damping and with settle_damping 0.01. The body stands still
  // while settling, so the static equilibrium the cloth relaxes to does not
  // depend on the damping, only the way there does.
  // Expectation: both settle, with the same stretch figures (check_same_fit,
  // a vertex of the free hem may settle 10-15 cm elsewhere). The rest
  // growth is not unique: the cloth slides along the body into another
  // equilibrium, and the adaptation grows what that one stretches. Measured
  // with the continuous contact and adaptation from adapt_speed on: T-pose
  // mean distance 1.8 cm, growth 1.0408 against 1.0847, p99 1.094 against
  // 1.097 (before the contact: 7.4 mm, 1.0442 against 1.0432). With the
  // adaptation's margin (limit 1.08): 1.9 cm, growth 1.051 against 1.094, p99
  // 1.070 against 1.080; the light damping settles after 992 steps, beyond
  // the earlier cap of 400. With the compression at a tenth of the stretch
  // stiffness (cloth/README.md, "Compression"): 1.8 cm, growth 1.037 against
  // 1.108, p99 1.078 against 1.079.
  const hc::Scene& scene = hc::default_scene();
  const Loaded l = load(scene);
  const gp::MotionSpec motion = motion_of(l.poses, {"apose", "tpose"}, 10);
  const MotionRunOptions damped = run_options(1500);
  MotionRunOptions light = damped;
  light.settle.damping = 0.01;
  const MotionRunResult a = run(l, motion, l.mesh.V, damped);
  const MotionRunResult b = run(l, motion, l.mesh.V, light);
  REQUIRE(a.keys.size() == 2);
  for (const auto* r : {&a, &b})
    for (const KeyPoseResult& k : r->keys) CHECK(k.settled);
  // Measured: 14.0 cm at most at the T-pose, mean 1.8 cm.
  check_same_fit(a, b, 0.15, 0.025, 0.08);
}

TEST_CASE("targets are held within the face growth cap where the cloth is stretched far beyond any fit",
          "[adapt][hard]") {
  // Every face stretched 10-fold along x (cloth held by the body, a skirt
  // caught on a hand): without a bound the rest would grow 10 / 1.1 in one
  // adaptation and again at every next one. With the cap of 4 the patch
  // grows to at most 4 times its design area, every face counted as capped,
  // and the rest stays finite and unflipped.
  const gp::Mesh grid = gp::testing::make_grid(8, 8, 0.2, 0.2);
  Eigen::MatrixXd V_sim = grid.V;
  V_sim.col(0) *= 10.0;
  AdaptOptions options;
  options.margin = 0.0;
  options.hysteresis = 0.0;
  options.arap.tolerance = 1e-10;
  options.max_face_growth = 4.0;
  RestShapeAdapter adapter(grid.V, grid.F, options);
  Eigen::MatrixXd V_rest = grid.V;
  const AdaptReport r = adapter.adapt(V_sim, V_rest);
  REQUIRE(V_rest.allFinite());
  INFO("area " << r.area_before << " -> " << r.area_after << ", capped " << r.capped_faces);
  CHECK(r.capped_faces == grid.F.rows());
  CHECK(r.area_after / r.area_before == Approx(4.0).epsilon(1e-3));
  for (int f = 0; f < grid.F.rows(); ++f) {
    CHECK(face_normal(V_rest, grid.F, f).dot(face_normal(grid.V, grid.F, f)) > 0.0);
  }
  // A second adaptation against the same positions grows nothing more.
  const AdaptReport again = adapter.adapt(V_sim, V_rest);
  CHECK(again.area_after / r.area_before == Approx(4.0).epsilon(1e-3));
  options.max_face_growth = 1.0;
  CHECK_THROWS_AS(RestShapeAdapter(grid.V, grid.F, options), gp::UsageError);
}
