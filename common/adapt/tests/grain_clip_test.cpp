// The clip against a fabric's per-direction limits (stretch_clip.h,
// GrainClip): the paper's rule when the limits are equal, each direction
// against its own limit otherwise, with the warp turned against the mesh.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include <Eigen/Dense>

#include "adapt/rest_adapter.h"
#include "adapt/stretch_clip.h"
#include "cloth/cloth_energy.h"
#include "core/error.h"
#include "mesh/measures.h"
#include "testing/test_meshes.h"

using namespace gp::adapt;

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix2d rotation(double a) {
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}

// A grid in the xy-plane (the body's vertical +y lies in it: the warp).
gp::Mesh upright_grid(int n, double size) {
  gp::Mesh m = gp::testing::make_grid(n, n, size, size);
  m.V.col(1).swap(m.V.col(2));
  m.F.col(1).swap(m.F.col(2));  // keep the orientation
  return m;
}

}  // namespace

TEST_CASE("a stretch along one material direction clips as the paper's rule with that direction's limit", "[adapt][fabric]") {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int rep = 0; rep < 200; ++rep) {
    Eigen::Matrix2d D;
    D << 0.02, 0.01 * u(rng), 0.0, 0.015 + 0.005 * u(rng);
    const Eigen::Matrix2d R = rotation(kPi * u(rng));
    const int axis = rep % 2;  // warp or weft
    const Eigen::Vector2d d = R.col(axis);
    const double s = 1.0 + 0.3 * (u(rng) + 1.0);
    // The stretch along d, then any rotation (the simulated triangle's frame).
    const Eigen::Matrix2d G = rotation(u(rng)) * (Eigen::Matrix2d::Identity() + (s - 1.0) * d * d.transpose());
    const double L = 1.05 + 0.1 * (u(rng) + 1.0), h = 0.01;
    const double other = 1.5;  // the other direction's limit: far above
    const Eigen::Matrix2d a = clipped_target(D, G, L - 1.0, h);
    const Eigen::Matrix2d b =
        axis == 0 ? clipped_target_grain(D, G, R, L, other, h) : clipped_target_grain(D, G, R, other, L, h);
    CHECK((a - b).norm() <= 1e-12 * D.norm());
  }
}

TEST_CASE("a shear (the bias) is left to the fabric, a principal stretch is not", "[adapt][fabric]") {
  Eigen::Matrix2d D;
  D << 0.02, 0.0, 0.0, 0.02;
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
  // A pure shear of 20 degrees: warp and weft keep their lengths, the principal stretch is 1.19.
  const double g = std::tan(20.0 * kPi / 180.0);
  Eigen::Matrix2d G;
  G << 1.0, g, 0.0, 1.0;
  G.col(1).normalize();
  CHECK(G.col(0).norm() == Approx(1.0));
  CHECK(G.col(1).norm() == Approx(1.0));
  CHECK(Eigen::JacobiSVD<Eigen::Matrix2d>(G).singularValues()(0) > 1.15);
  CHECK(clipped_target_grain(D, G, R, 1.10, 1.10, 0.0) == D);
  CHECK((clipped_target(D, G, 0.10, 0.0) - D).norm() > 1e-4);
}

TEST_CASE("each material direction is clipped at its own limit", "[adapt][fabric]") {
  // A rest triangle, its warp at 30 degrees to the rest frame's x axis.
  Eigen::Matrix2d D;
  D << 0.02, 0.008, 0.0, 0.017;
  const double phi = kPi / 6.0;
  const Eigen::Matrix2d R = rotation(phi);
  const Eigen::Vector2d warp = R.col(0), weft = R.col(1);
  // Stretch by s along one material direction (in the rest frame).
  auto stretch_along = [](const Eigen::Vector2d& d, double s) {
    return Eigen::Matrix2d(Eigen::Matrix2d::Identity() + (s - 1.0) * d * d.transpose());
  };
  const double limit_warp = 1.10, limit_weft = 1.30;
  // 20 % along the warp: beyond its 10 %: the target grows along the warp only, to 1.2 / 1.1.
  {
    const Eigen::Matrix2d G = stretch_along(warp, 1.2);
    const Eigen::Matrix2d T = clipped_target_grain(D, G, R, limit_warp, limit_weft, 0.0);
    const Eigen::Matrix2d M = T * D.inverse();  // the rest's growth
    CHECK((M * warp).norm() == Approx(1.2 / 1.1).epsilon(1e-12));
    CHECK((M * weft).norm() == Approx(1.0).epsilon(1e-12));
    // Simulated against the new rest, the warp is at its limit.
    const Eigen::Matrix2d G_new = G * D * T.inverse();
    CHECK((G_new * (M * warp).normalized()).norm() == Approx(1.1).epsilon(1e-12));
  }
  // 20 % along the weft: within its 30 %: nothing to clip.
  {
    const Eigen::Matrix2d G = stretch_along(weft, 1.2);
    CHECK(clipped_target_grain(D, G, R, limit_warp, limit_weft, 0.0) == D);
    // The paper's single limit (10 %) would have grown it.
    CHECK((clipped_target(D, G, 0.1, 0.0) - D).norm() > 1e-4);
  }
  // 40 % along the weft: grows along the weft to 1.4 / 1.3.
  {
    const Eigen::Matrix2d G = stretch_along(weft, 1.4);
    const Eigen::Matrix2d M = clipped_target_grain(D, G, R, limit_warp, limit_weft, 0.0) * D.inverse();
    CHECK((M * weft).norm() == Approx(1.4 / 1.3).epsilon(1e-12));
    CHECK((M * warp).norm() == Approx(1.0).epsilon(1e-12));
  }
  // Compression is left alone in every direction.
  CHECK(clipped_target_grain(D, stretch_along(warp, 0.7), R, limit_warp, limit_weft, 0.0) == D);
}

TEST_CASE("grain clips over a mesh: statistics per direction, the warp turned per face", "[adapt][fabric]") {
  const gp::Mesh m = upright_grid(6, 0.2);
  Eigen::MatrixXd V_warp = m.V, V_weft = m.V;
  V_warp.col(1) *= 1.2;  // along the body's vertical: the warp
  V_weft.col(0) *= 1.2;  // across: the weft
  GrainClip g;
  g.limit_warp = 1.10;
  g.limit_weft = 1.30;
  ClipStats s;
  std::vector<Eigen::Matrix2d> T = clipped_targets(m.V, V_warp, m.F, g, nullptr, &s, 0.0);
  CHECK(s.clipped_faces == m.F.rows());
  CHECK(s.max_warp_stretch == Approx(1.2).epsilon(1e-12));
  CHECK(s.max_weft_stretch == Approx(1.0).epsilon(1e-12));
  CHECK(s.max_limit_stretch == Approx(1.2 / 1.1).epsilon(1e-12));
  CHECK(s.target_area == Approx(0.04 * 1.2 / 1.1).epsilon(1e-10));
  T = clipped_targets(m.V, V_weft, m.F, g, nullptr, &s, 0.0);
  CHECK(s.clipped_faces == 0);
  CHECK(s.max_weft_stretch == Approx(1.2).epsilon(1e-12));
  CHECK(s.target_area == Approx(0.04).epsilon(1e-10));
  // The grain turned a right angle on every face: the vertical is now the weft.
  const std::vector<double> turned(m.F.rows(), kPi / 2.0);
  g.grain_angles = &turned;
  clipped_targets(m.V, V_warp, m.F, g, nullptr, &s, 0.0);
  CHECK(s.clipped_faces == 0);
  CHECK(s.max_weft_stretch == Approx(1.2).epsilon(1e-12));
  // A bias grain (45 degrees): a vertical pull of 20 % stretches warp and weft by 10.5 %
  // each (and shears them): beyond the warp's 10 %.
  const std::vector<double> bias(m.F.rows(), kPi / 4.0);
  g.grain_angles = &bias;
  clipped_targets(m.V, V_warp, m.F, g, nullptr, &s, 0.0);
  CHECK(s.max_warp_stretch == Approx(std::sqrt(0.5 * (1.0 + 1.44))).epsilon(1e-12));
  CHECK(s.max_weft_stretch == Approx(s.max_warp_stretch).epsilon(1e-12));
  CHECK(s.clipped_faces == m.F.rows());
  CHECK(s.max_limit_stretch == Approx(std::sqrt(0.5 * (1.0 + 1.44)) / 1.1).epsilon(1e-12));
  const std::vector<double> wrong(3, 0.0);
  g.grain_angles = &wrong;
  CHECK_THROWS_AS(clipped_targets(m.V, V_warp, m.F, g, nullptr, &s, 0.0), gp::UsageError);
}

TEST_CASE("the adapter with a fabric's limits grows the rest along the over-stretched direction only", "[adapt][fabric]") {
  const gp::Mesh m = upright_grid(6, 0.2);
  AdaptOptions o;
  o.margin = 0.0;
  o.hysteresis = 0.0;
  o.smoothing_length = 0.0;
  gp::Material knit;
  knit.stretch_limit_warp = 1.10;
  knit.stretch_limit_weft = 1.30;
  const RestShapeAdapter adapter(m.V, m.F, with_fabric_limits(o, knit));
  CHECK(adapter.options().limit_weft == 1.30);
  // 20 % across (weft): within the knit's limit, the rest stays.
  Eigen::MatrixXd V_sim = m.V;
  V_sim.col(0) *= 1.2;
  Eigen::MatrixXd V_rest = m.V;
  AdaptReport r = adapter.adapt(V_sim, V_rest);
  CHECK_FALSE(r.changed);
  CHECK(V_rest == m.V);
  // 20 % down the body (warp): the rest grows along the warp, as the paper's
  // single limit 1.1 grows it (whose clip, too, grows only the stretched
  // direction), to the same rest shape.
  V_sim = m.V;
  V_sim.col(1) *= 1.2;
  r = adapter.adapt(V_sim, V_rest);
  CHECK(r.changed);
  AdaptOptions iso = o;
  iso.delta = 0.1;
  const RestShapeAdapter paper(m.V, m.F, with_fabric_limits(iso, gp::Material{}));
  CHECK(paper.options().limit_warp == 0.0);
  Eigen::MatrixXd V_paper = m.V;
  CHECK(paper.adapt(V_sim, V_paper).changed);
  CHECK((V_rest - V_paper).norm() <= 1e-6);  // the stitching's iterations amplify rounding
  const double height = V_rest.col(1).maxCoeff() - V_rest.col(1).minCoeff();
  const double width = V_rest.col(0).maxCoeff() - V_rest.col(0).minCoeff();
  CHECK(height > 0.2 * 1.08);  // towards 1.2 / 1.1, as far as the stitching meets its targets
  CHECK(width < 0.2 * 1.02);
  // Across, the paper's material grows where the knit does not.
  V_sim = m.V;
  V_sim.col(0) *= 1.2;
  V_paper = m.V;
  CHECK(paper.adapt(V_sim, V_paper).changed);
  // Limits below the margin and hysteresis are refused.
  AdaptOptions bad = o;
  bad.margin = 0.2;
  bad.delta = 0.3;
  CHECK_THROWS_AS(RestShapeAdapter(m.V, m.F, with_fabric_limits(bad, knit)), gp::UsageError);
}
