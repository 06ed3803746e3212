#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "core/error.h"
#include "geometry/self_intersections.h"
#include "interp/frame_measures.h"
#include "interp/pose_interpolator.h"
#include "interp_fixtures.h"
#include "io/mesh_io.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

using interp_test::deg;
using interp_test::height;
using interp_test::lengths;
using interp_test::make_pose_set;
using interp_test::rot;

namespace {

gp::InterpolationOptions with_method(gp::InterpolationMethod method) {
  gp::InterpolationOptions o;
  o.method = method;
  return o;
}

// Largest |V_x - V_y| over vertices.
double max_distance(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
  return (X - Y).rowwise().norm().maxCoeff();
}

// Shape checks of a body motion a -> b (in-between bodies must keep the
// body's shape): per frame, edge lengths against the two key poses and the
// volume against the key volumes; self-intersections at a few frames compared
// with the key poses. Returns the worst figures for the caller to assert.
struct BodyMotionFigures {
  double key_error = 0.0;            // max vertex error at t = 0 and 1, relative to height
  double ratio_range_excess = 0.0;   // frame edge ratios outside the keys' ratio range
  double edge_excess_p99 = 0.0;      // 99th percentile of per-edge excursion beyond the keys
  double edge_excess_mean = 0.0;
  double volume_excess = 0.0;
  long long key_self_intersections = 0;
  long long frame_self_intersections = 0;
  double linear_edge_deviation_max = 0.0;  // linear baseline vs nonlinear
};

BodyMotionFigures body_motion_figures(const gp::PoseSet& set, int a, int b, int steps) {
  BodyMotionFigures fig;
  gp::PoseInterpolator nonlinear(set), linear(set, with_method(gp::InterpolationMethod::linear));
  gp::MotionMeasurer measurer(set.V, set.F, a);
  const double h = height(set.V[a]);
  fig.key_error = std::max(max_distance(nonlinear.frame(a, b, 0.0), set.V[a]),
                           max_distance(nonlinear.frame(a, b, 1.0), set.V[b])) / h;
  const gp::FrameMeasures key_b = measurer.measure(set.V[b], a, b);
  // Edge ratios (length / length in pose a) of pose b span [lo, hi]; pose a is 1.
  const double ratio_lo = std::min(1.0, key_b.edge_ratio_min), ratio_hi = std::max(1.0, key_b.edge_ratio_max);
  const Eigen::VectorXd l_a = measurer.key_edge_lengths(a), l_b = measurer.key_edge_lengths(b);
  const Eigen::MatrixXi E = gp::unique_edges(set.F);
  std::vector<double> all_excess;
  Eigen::MatrixXd V, V_lin;
  for (int k = 1; k < steps; ++k) {
    const double t = static_cast<double>(k) / steps;
    nonlinear.frame(a, b, t, V);
    const gp::FrameMeasures m = measurer.measure(V, a, b);
    fig.ratio_range_excess = std::max({fig.ratio_range_excess, ratio_lo - m.edge_ratio_min,
                                       m.edge_ratio_max - ratio_hi});
    fig.volume_excess = std::max(fig.volume_excess, m.volume_excess);
    const Eigen::VectorXd l = gp::edge_lengths(V, E);
    for (Eigen::Index e = 0; e < l.size(); ++e) {
      const double lo = std::min(l_a(e), l_b(e)), hi = std::max(l_a(e), l_b(e));
      all_excess.push_back(std::max({0.0, l(e) / hi - 1.0, 1.0 - l(e) / lo}));
    }
    linear.frame(a, b, t, V_lin);
    fig.linear_edge_deviation_max =
        std::max(fig.linear_edge_deviation_max, measurer.compare(V_lin, V).edge_deviation_max);
  }
  std::sort(all_excess.begin(), all_excess.end());
  fig.edge_excess_p99 = all_excess[all_excess.size() * 99 / 100];
  double sum = 0.0;
  for (double x : all_excess) sum += x;
  fig.edge_excess_mean = sum / all_excess.size();
  fig.key_self_intersections = std::max(gp::self_intersections(set.V[a], set.F).pair_count,
                                        gp::self_intersections(set.V[b], set.F).pair_count);
  for (double t : {0.25, 0.5, 0.75})
    fig.frame_self_intersections = std::max(fig.frame_self_intersections,
                                            gp::self_intersections(nonlinear.frame(a, b, t), set.F).pair_count);
  return fig;
}

}  // namespace

TEST_CASE("a rigid rotation by 170 degrees stays rigid; the linear blend collapses it", "[interp]") {
  const gp::Mesh body = interp_test::make_scarecrow(60, 16);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1.0, 0.2).normalized();
  const Eigen::Vector3d pivot(0.4, -0.2, 0.1);
  Eigen::MatrixXd V_rot = body.V;
  for (Eigen::Index v = 0; v < V_rot.rows(); ++v)
    V_rot.row(v) = (pivot + rot(axis, deg(170)) * (body.V.row(v).transpose() - pivot)).transpose();
  const gp::PoseSet set = make_pose_set(body.F, {body.V, V_rot}, {"rest", "turned"});
  gp::PoseInterpolator nonlinear(set), linear(set, with_method(gp::InterpolationMethod::linear));
  const Eigen::VectorXd l0 = lengths(body.V, body.F);
  const double h = height(body.V);

  CHECK(max_distance(nonlinear.frame(0, 1, 0.0), body.V) < 1e-6 * h);
  CHECK(max_distance(nonlinear.frame(0, 1, 1.0), V_rot) < 1e-6 * h);
  double nonlinear_worst = 0.0, linear_min_ratio = 1.0;
  for (int k = 1; k < 20; ++k) {
    const double t = k / 20.0;
    const Eigen::MatrixXd V = nonlinear.frame(0, 1, t);
    nonlinear_worst = std::max(nonlinear_worst, ((lengths(V, body.F).array() / l0.array()) - 1.0).abs().maxCoeff());
    // The frame is the rest shape turned by t * 170 degrees (not the short way).
    const Eigen::Vector3d span = (V.row(V.rows() - 1) - V.row(0)).transpose();
    const Eigen::Vector3d span_rest = (body.V.row(V.rows() - 1) - body.V.row(0)).transpose();
    CHECK((span - rot(axis, deg(170) * t) * span_rest).norm() < 1e-6 * h);
    const Eigen::MatrixXd V_lin = linear.frame(0, 1, t);
    linear_min_ratio = std::min(linear_min_ratio, (lengths(V_lin, body.F).array() / l0.array()).minCoeff());
  }
  CHECK(nonlinear_worst < 1e-3);
  CHECK(nonlinear_worst < 1e-9);  // in fact exact up to round-off
  // The linear blend shrinks the mesh to cos(85 deg) = 9 % of its size half-way.
  CHECK(linear_min_ratio < 0.15);
}

TEST_CASE("a chain twisted by 270 degrees over its links keeps its edge lengths; the linear blend shrinks it",
          "[interp]") {
  const int links = 10;
  const gp::Mesh chain = interp_test::make_bead_chain(links);
  const Eigen::MatrixXd V_twist = interp_test::twist_chain(chain.V, links, 270.0);
  const gp::PoseSet set = make_pose_set(chain.F, {chain.V, V_twist}, {"straight", "twisted"});
  gp::PoseInterpolator nonlinear(set), linear(set, with_method(gp::InterpolationMethod::linear));
  CHECK(nonlinear.transition_info(0, 1).max_rotation_deg == Approx(270.0).margin(1e-6));
  const Eigen::VectorXd l0 = lengths(chain.V, chain.F);
  const double h = height(chain.V);
  CHECK(max_distance(nonlinear.frame(0, 1, 0.0), chain.V) < 1e-6 * h);
  CHECK(max_distance(nonlinear.frame(0, 1, 1.0), V_twist) < 1e-6 * h);

  double nonlinear_worst = 0.0, linear_min_ratio = 1.0;
  for (int k = 1; k < 12; ++k) {
    const double t = k / 12.0;
    const Eigen::MatrixXd V = nonlinear.frame(0, 1, t);
    nonlinear_worst = std::max(nonlinear_worst, ((lengths(V, chain.F).array() / l0.array()) - 1.0).abs().maxCoeff());
    // Every link turns by its share of t * 270 degrees, the top one the long way.
    CHECK(max_distance(V, interp_test::twist_chain(chain.V, links, 270.0 * t)) < 1e-6 * h);
    linear_min_ratio =
        std::min(linear_min_ratio, (lengths(linear.frame(0, 1, t), chain.F).array() / l0.array()).minCoeff());
  }
  CHECK(nonlinear_worst < 1e-3);
  // The linear blend cuts across: the top link shrinks to |cos(135 deg)| = 71 %.
  CHECK(linear_min_ratio < 0.75);
}

TEST_CASE("a continuously twisted tube turns the long way; its shear costs edge accuracy", "[interp]") {
  // A smooth 270 degree twist of an open tube is a rotation plus a shear of
  // every triangle. Interpolating the rotation log of each triangle does not
  // commute with that shear (exp(t log(R_twist R_shear)) differs from
  // R_twist^t R_shear^t), so lengths deviate in proportion to the shear
  // gamma = radius * twist rate, most at the free end. The branch must still be
  // the long way round everywhere.
  auto run = [](double radius, double& excess, double& turned) {
    const gp::Mesh tube = gp::testing::make_open_cylinder(12, 90, radius, 2.0);
    const Eigen::MatrixXd V_twist = interp_test::twist_tube(tube.V, 270.0, 2.0);
    const gp::PoseSet set = make_pose_set(tube.F, {tube.V, V_twist}, {"straight", "twisted"});
    gp::PoseInterpolator nonlinear(set);
    gp::MotionMeasurer measurer(set.V, set.F, 0);
    excess = 0.0;
    for (int k = 1; k < 12; ++k)
      excess = std::max(excess, measurer.measure(nonlinear.frame(0, 1, k / 12.0), 0, 1).edge_excess_max);
    const Eigen::MatrixXd V_half = nonlinear.frame(0, 1, 0.5);
    const Eigen::Index top = tube.V.rows() - 12;  // first vertex of the top ring
    turned = std::atan2(V_half(top, 0), V_half(top, 2)) - std::atan2(tube.V(top, 0), tube.V(top, 2));
    while (turned < 0) turned += 2 * interp_test::kPi;
  };
  double excess_thick = 0, turned_thick = 0, excess_thin = 0, turned_thin = 0;
  run(0.05, excess_thick, turned_thick);  // gamma = 0.12
  run(0.01, excess_thin, turned_thin);    // gamma = 0.024
  CHECK(turned_thick == Approx(deg(135)).margin(deg(2)));
  CHECK(turned_thin == Approx(deg(135)).margin(deg(1)));
  CHECK(excess_thick < 0.08);
  CHECK(excess_thin < 0.012);
  CHECK(excess_thin < 0.25 * excess_thick);  // shrinks with the shear
}

TEST_CASE("a generated body raising its arms by 130 degrees keeps its shape", "[interp][body]") {
  const gp::Mesh rest = interp_test::make_scarecrow();
  const gp::PoseSet set = make_pose_set(
      rest.F, {interp_test::pose_scarecrow(rest.V, -55.0), interp_test::pose_scarecrow(rest.V, 75.0)},
      {"down", "up"});
  const BodyMotionFigures fig = body_motion_figures(set, 0, 1, 20);
  CHECK(fig.key_error < 1e-6);
  CHECK(fig.ratio_range_excess < 0.01);
  CHECK(fig.edge_excess_p99 < 0.02);
  CHECK(fig.edge_excess_mean < 0.002);
  CHECK(fig.volume_excess < 0.02);
  CHECK(fig.frame_self_intersections <= fig.key_self_intersections);
  // The linear baseline differs visibly from the nonlinear method.
  CHECK(fig.linear_edge_deviation_max > 0.1);
}

TEST_CASE("shared avatar from A-pose to arms up keeps its shape", "[interp][body][shared]") {
  const auto dir = gp::testing::shared_avatars_dir();
  if (dir.empty()) {
    WARN("skipped: ../shared/avatars not found");
    return;
  }
  const gp::PoseSet set = gp::load_pose_files({dir / "slim_apose.ply", dir / "slim_armsup.ply"});
  const BodyMotionFigures fig = body_motion_figures(set, 0, 1, 12);
  CHECK(fig.key_error < 1e-6);
  CHECK(fig.ratio_range_excess < 0.01);
  CHECK(fig.edge_excess_p99 < 0.05);
  CHECK(fig.edge_excess_mean < 0.002);
  CHECK(fig.volume_excess < 0.02);
  CHECK(fig.frame_self_intersections <= fig.key_self_intersections);
  CHECK(fig.linear_edge_deviation_max > 0.3);
}

TEST_CASE("the anchor centroid follows the straight line between the key poses", "[interp]") {
  const gp::Mesh rest = interp_test::make_scarecrow(60, 16);
  Eigen::MatrixXd V_up = interp_test::pose_scarecrow(rest.V, 60.0);
  V_up.rowwise() += Eigen::RowVector3d(0.3, -0.1, 0.5);
  const gp::PoseSet set = make_pose_set(rest.F, {rest.V, V_up}, {"rest", "up"});
  gp::InterpolationOptions options;
  options.anchor.vertex_ids = {5, 40, 41, 42, 300};
  gp::PoseInterpolator interp(set, options);
  CHECK(interp.anchor_vertex_ids() == std::vector<int>{5, 40, 41, 42, 300});
  const Eigen::MatrixXd V = interp.frame(0, 1, 0.3);
  Eigen::RowVector3d got = Eigen::RowVector3d::Zero(), want = Eigen::RowVector3d::Zero();
  for (int id : options.anchor.vertex_ids) {
    got += V.row(id) / 5.0;
    want += (0.7 * rest.V.row(id) + 0.3 * V_up.row(id)) / 5.0;
  }
  CHECK((got - want).norm() < 1e-12);

  // Automatic anchor: the requested fraction of vertices.
  gp::InterpolationOptions automatic;
  automatic.anchor.fraction = 0.1;
  gp::PoseInterpolator interp_auto(set, automatic);
  CHECK(interp_auto.anchor_vertex_ids().size() ==
        static_cast<size_t>(std::ceil(0.1 * static_cast<double>(rest.V.rows()))));
}

TEST_CASE("frames are deterministic and scale with the input", "[interp]") {
  const gp::Mesh rest = interp_test::make_scarecrow(60, 16);
  const gp::PoseSet set = make_pose_set(
      rest.F, {interp_test::pose_scarecrow(rest.V, -40.0), interp_test::pose_scarecrow(rest.V, 80.0)},
      {"down", "up"});
  gp::PoseInterpolator first(set), second(set);
  const Eigen::MatrixXd V = first.frame(0, 1, 0.37);
  CHECK(V == second.frame(0, 1, 0.37));
  CHECK(V == first.frame(0, 1, 0.37));  // cached transition, same result
  // Reverse direction passes through the same shape.
  CHECK(max_distance(first.frame(1, 0, 0.63), V) < 1e-3 * height(rest.V));
  for (double scale : {1e-3, 1e3}) {
    const gp::PoseSet scaled = make_pose_set(rest.F, {scale * set.V[0], scale * set.V[1]}, {"down", "up"});
    gp::PoseInterpolator s(scaled);
    CHECK(max_distance(s.frame(0, 1, 0.37), scale * V) < 1e-9 * scale);
  }
}

TEST_CASE("the linear method blends positions", "[interp]") {
  const gp::Mesh rest = interp_test::make_scarecrow(30, 8);
  const Eigen::MatrixXd V_up = interp_test::pose_scarecrow(rest.V, 90.0);
  const gp::PoseSet set = make_pose_set(rest.F, {rest.V, V_up}, {"rest", "up"});
  gp::PoseInterpolator linear(set, with_method(gp::InterpolationMethod::linear));
  CHECK(linear.factorization_seconds() == 0.0);
  CHECK(max_distance(linear.frame(0, 1, 0.25), 0.75 * rest.V + 0.25 * V_up) < 1e-15);
  CHECK(gp::parse_interpolation_method("linear") == gp::InterpolationMethod::linear);
  CHECK_THROWS_AS(gp::parse_interpolation_method("cubic"), gp::UsageError);
}

TEST_CASE("bad pose sets and arguments are reported with their category", "[interp]") {
  const gp::Mesh rest = interp_test::make_scarecrow(30, 8);
  const Eigen::MatrixXd V_up = interp_test::pose_scarecrow(rest.V, 90.0);
  {
    Eigen::MatrixXd V_nan = V_up;
    V_nan(17, 1) = std::numeric_limits<double>::quiet_NaN();
    try {
      gp::PoseInterpolator interp(make_pose_set(rest.F, {rest.V, V_nan}, {"rest", "nan"}));
      FAIL("no error for a NaN coordinate");
    } catch (const gp::GeometryError& e) {
      CHECK(e.where().find("vertex 17") != std::string::npos);
      CHECK(e.where().find("nan") != std::string::npos);
    }
  }
  CHECK_THROWS_AS(gp::PoseInterpolator(make_pose_set(rest.F, {rest.V, V_up.topRows(10)}, {"a", "b"})),
                  gp::GeometryError);
  CHECK_THROWS_AS(gp::PoseInterpolator(gp::PoseSet{}), gp::GeometryError);
  gp::InterpolationOptions bad_anchor;
  bad_anchor.anchor.vertex_ids = {static_cast<int>(rest.V.rows())};
  CHECK_THROWS_AS(gp::PoseInterpolator(make_pose_set(rest.F, {rest.V, V_up}, {"a", "b"}), bad_anchor),
                  gp::SpecError);
  gp::InterpolationOptions bad_fraction;
  bad_fraction.anchor.fraction = 0.0;
  CHECK_THROWS_AS(gp::PoseInterpolator(make_pose_set(rest.F, {rest.V, V_up}, {"a", "b"}), bad_fraction),
                  gp::SpecError);

  gp::PoseInterpolator interp(make_pose_set(rest.F, {rest.V, V_up}, {"a", "b"}));
  CHECK_THROWS_AS(interp.frame(0, 2, 0.5), gp::UsageError);
  CHECK_THROWS_AS(interp.frame(0, 1, 1.5), gp::UsageError);
  CHECK_THROWS_AS(interp.frame(0, 1, std::numeric_limits<double>::quiet_NaN()), gp::UsageError);
  // A triangle collapsed in the target pose borrows its neighbour's rotation.
  Eigen::MatrixXd V_flat = V_up;
  V_flat.row(rest.F(40, 2)) = 0.5 * (V_flat.row(rest.F(40, 0)) + V_flat.row(rest.F(40, 1)));
  gp::PoseInterpolator degenerate(make_pose_set(rest.F, {rest.V, V_flat}, {"a", "flat"}));
  CHECK(degenerate.transition_info(0, 1).degenerate_faces >= 1);
  CHECK(degenerate.frame(0, 1, 0.5).allFinite());
  CHECK(max_distance(degenerate.frame(0, 1, 1.0), V_flat) < 1e-6 * height(rest.V));
}
