// The anisotropic membrane (a warp and a weft of their own stiffness, the
// grain turned per face) against central finite differences, with the warp
// rotated against the mesh; its rest state, frames and per-direction stretches.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "cloth/cloth_energy.h"
#include "finite_differences.h"
#include "cloth/cloth_model.h"
#include "core/error.h"
#include "testing/test_meshes.h"

using namespace gp::cloth;
using gp::cloth::testing::fd_gradient;
using gp::cloth::testing::fd_hessian;
using gp::cloth::testing::min_eigenvalue;

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}


}  // namespace

TEST_CASE("anisotropic stretch: gradients and Hessians match finite differences with the warp rotated", "[energy][fabric]") {
  std::mt19937 rng(47);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double k = 2065.0;  // a denim warp, N/m
  int checked = 0;
  // Weft-to-warp ratios of the library (interlock, denim, poplin), 1, and a
  // weft stiffer than the warp; grain angles 0, a bias, a right angle, random.
  for (const double ratio : {0.143, 0.212, 0.984, 1.0, 2.5}) {
    for (const double compression : {1.0, 0.1}) {
      for (int rep = 0; rep < 24; ++rep) {
        const double scale = rep % 3 == 0 ? 1e-3 : (rep % 3 == 1 ? 0.02 : 1.0);
        Eigen::Matrix3d X_rest;
        X_rest << 0.0, 1.0, 0.3 + 0.2 * u(rng), 0.0, 0.1 * u(rng), 0.9 + 0.1 * u(rng), 0.0, 0.2 * u(rng),
            0.2 * u(rng);
        X_rest = (random_rotation(rng) * X_rest * scale).eval();
        // The warp against the mesh: any 3D direction, then a turn in the plane.
        const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
        const double angles[] = {0.0, kPi / 4.0, kPi / 2.0, kPi * u(rng)};
        const double angle = angles[rep % 4];
        TriangleRest rest = triangle_rest(X_rest, dir, angle);
        rest.weft_ratio = ratio;
        const Eigen::Matrix3d R = random_rotation(rng);
        Eigen::Matrix3d X = R * X_rest;
        if (rep % 2 == 0) {
          for (int i = 0; i < 9; ++i) X(i) += 0.3 * scale * u(rng);
        } else {
          // Stretched along the warp, compressed along the weft (or the reverse).
          const Eigen::Vector3d d = warp_direction(X_rest, dir, angle);
          const Eigen::Vector3d n = (X_rest.col(1) - X_rest.col(0)).cross(X_rest.col(2) - X_rest.col(0)).normalized();
          const Eigen::Vector3d w = n.cross(d);
          const double su = 1.0 + 0.2 * u(rng), sv = 1.0 + 0.2 * u(rng);
          const Eigen::Matrix3d A = su * d * d.transpose() + sv * w * w.transpose() + n * n.transpose();
          X = R * A * X_rest;
        }
        INFO("ratio " << ratio << " compression " << compression << " rep " << rep);
        const double eps = 1e-6 * scale;
        auto se = [&](const Eigen::Matrix3d& Y) { return stretch_energy(Y, rest, k, compression); };
        auto sg = [&](const Eigen::Matrix3d& Y) { return stretch_gradient(Y, rest, k, compression); };
        const Vector9d g = sg(X);
        const double force_scale = k * rest.area / scale;
        CHECK((g - fd_gradient(X, eps, se)).norm() <= 1e-6 * force_scale * (1.0 + g.norm() / force_scale));
        const Eigen::Matrix<double, 3, 2> W = triangle_w(X, rest);
        const bool at_kink =
            compression != 1.0 && std::min(std::abs(W.col(0).norm() - 1.0), std::abs(W.col(1).norm() - 1.0)) < 1e-4;
        const Matrix9d H = stretch_hessian(X, rest, k, false, compression);
        const double hess_scale = k * rest.area / (scale * scale);
        if (!at_kink) {
          CHECK((H - fd_hessian(X, eps, sg)).norm() <= 1e-5 * hess_scale * (1.0 + H.norm() / hess_scale));
        }
        // The projection stays PSD and only adds.
        const Matrix9d Hp = stretch_hessian(X, rest, k, true, compression);
        CHECK(min_eigenvalue(Hp) >= -1e-10 * (1.0 + Hp.norm()));
        CHECK(min_eigenvalue(Hp - H) >= -1e-10 * (1.0 + Hp.norm()));
        // The energy is the warp's term plus ratio times the weft's.
        const double lu = W.col(0).norm() - 1.0, lv = W.col(1).norm() - 1.0;
        const double cu = lu < 0.0 ? compression : 1.0, cv = lv < 0.0 ? compression : 1.0;
        CHECK(se(X) == Approx(0.5 * k * rest.area * (cu * lu * lu + ratio * cv * lv * lv)).epsilon(1e-10).margin(1e-300));
        // The assembled block carries the same anisotropy.
        const MembraneCoefficients c{k, 30.0, 100.0, 1.0, compression};
        Vector9d gb;
        Matrix9d Kb;
        const double h = 0.0025;
        const double eb = membrane_system_block(X, rest, c, h, gb, Kb);
        CHECK(eb == Approx(se(X) + shear_energy(X, rest, c.k_shear)).epsilon(1e-12).margin(1e-300));
        CHECK((gb - g - shear_gradient(X, rest, c.k_shear)).norm() <= 1e-10 * (1.0 + gb.norm()));
        const Matrix9d K_ref = h * h * (Hp + shear_hessian(X, rest, c.k_shear, true)) +
                               h * (stretch_damping(X, rest, c.damping_stretch) + shear_damping(X, rest, c.damping_shear));
        CHECK((Kb - K_ref).norm() <= 1e-10 * (1.0 + K_ref.norm()));
        ++checked;
      }
    }
  }
  CHECK(checked == 5 * 2 * 24);
}

TEST_CASE("the warp direction lies in the face, turned by the grain angle from the projected vertical", "[energy][fabric]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int rep = 0; rep < 50; ++rep) {
    Eigen::Matrix3d X;
    for (int i = 0; i < 9; ++i) X(i) = u(rng);
    const Eigen::Vector3d n = (X.col(1) - X.col(0)).cross(X.col(2) - X.col(0)).normalized();
    const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
    if (std::abs(n.dot(up)) > 0.9) continue;  // the fallback (first edge) is not the subject here
    const Eigen::Vector3d d0 = warp_direction(X, up, 0.0);
    CHECK(std::abs(d0.norm() - 1.0) <= 1e-14);
    CHECK(std::abs(d0.dot(n)) <= 1e-14);
    CHECK(d0.dot(up) > 0.0);
    CHECK((d0 - (up - up.dot(n) * n).normalized()).norm() <= 1e-14);
    const double angle = kPi * u(rng);
    const Eigen::Vector3d d = warp_direction(X, up, angle);
    CHECK(std::abs(d.dot(n)) <= 1e-14);
    CHECK(std::atan2(n.cross(d0).dot(d), d0.dot(d)) == Approx(angle).margin(1e-12));
    // The rest frame's u axis is that direction: stretching along it moves w_u only.
    const TriangleRest rest = triangle_rest(X, up, angle);
    const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() + 0.1 * d * d.transpose();
    const Eigen::Matrix<double, 3, 2> W = triangle_w(A * X, rest);
    CHECK(W.col(0).norm() == Approx(1.1).epsilon(1e-12));
    CHECK(W.col(1).norm() == Approx(1.0).epsilon(1e-12));
  }
  // Unturned, the frame is the one of the former single-direction code path.
  Eigen::Matrix3d X;
  X << 0.0, 0.1, 0.02, 0.0, 0.01, 0.12, 0.0, 0.03, -0.01;
  const TriangleRest a = triangle_rest(X), b = triangle_rest(X, Eigen::Vector3d::UnitY(), 0.0);
  CHECK(a.a == b.a);
  CHECK(a.b == b.b);
  CHECK(a.area == b.area);
}

TEST_CASE("the cloth model carries the fabric's weft ratio and the grain per face", "[energy][fabric]") {
  const gp::Mesh grid = gp::testing::make_grid(6, 6, 0.3, 0.3);  // in the xz-plane
  ClothParameters p;
  p.gravity.setZero();
  p.k_bend = 0.0;
  p.k_stretch = 2065.0;
  p.k_stretch_weft = 437.0;
  p.material_direction = Eigen::Vector3d::UnitX();
  ClothRestState rest = build_rest_state(grid.V, grid.F, p);
  for (const TriangleRest& t : rest.triangles) CHECK(t.weft_ratio == Approx(437.0 / 2065.0).epsilon(1e-15));
  // Rest gives no force, anisotropic or not.
  CHECK(cloth_gradient(grid.V, grid.F, rest, p).norm() <= 1e-9 * p.k_stretch);
  // 5 % along x (the warp) and along z (the weft): energies in the ratio of the stiffnesses.
  Eigen::MatrixXd Vx = grid.V, Vz = grid.V;
  Vx.col(0) *= 1.05;
  Vz.col(2) *= 1.05;
  const double ex = cloth_energies(Vx, grid.F, rest, p).stretch, ez = cloth_energies(Vz, grid.F, rest, p).stretch;
  CHECK(ex == Approx(0.5 * 2065.0 * 0.09 * 0.05 * 0.05).epsilon(1e-10));
  CHECK(ez / ex == Approx(437.0 / 2065.0).epsilon(1e-10));
  // Per-direction stretches, and stretches relative to per-direction limits.
  const Eigen::MatrixXd S = face_grain_stretches(Vz, grid.F, rest);
  CHECK(S.col(0).maxCoeff() == Approx(1.0).epsilon(1e-12));
  CHECK(S.col(1).minCoeff() == Approx(1.05).epsilon(1e-12));
  const Eigen::VectorXd L = face_limit_stretches(Vz, grid.F, rest, 1.10, 1.30);
  // Warp at rest (1 / 1.10) outweighs the weft's 5 % against its 30 % (1.05 / 1.30).
  CHECK(L.maxCoeff() == Approx(1.0 / 1.10).epsilon(1e-10));
  CHECK(face_limit_stretches(Vx, grid.F, rest, 1.10, 1.30).maxCoeff() == Approx(1.05 / 1.10).epsilon(1e-10));
  const Eigen::VectorXd L_iso = face_limit_stretches(Vz, grid.F, rest, 1.1, 1.1);
  CHECK((L_iso - face_principal_stretches(Vz, grid.F, rest).col(0) / 1.1).norm() <= 1e-12);
  // The grain turned a right angle on every face swaps warp and weft.
  p.grain_angles.assign(grid.F.rows(), kPi / 2.0);
  update_rest_state(grid.V, grid.F, p, rest);
  CHECK(cloth_energies(Vz, grid.F, rest, p).stretch == Approx(ex).epsilon(1e-9));
  // Flat rest triangles from a pattern get the fabric's ratio too.
  std::vector<TriangleRest> flat = rest.triangles;
  for (TriangleRest& t : flat) t.weft_ratio = 1.0;
  set_rest_triangles(flat, grid.F, p, rest);
  for (const TriangleRest& t : rest.triangles) CHECK(t.weft_ratio == Approx(437.0 / 2065.0).epsilon(1e-15));
  // Bad sizes and stiffnesses are refused.
  p.grain_angles.assign(3, 0.0);
  CHECK_THROWS_AS(build_rest_state(grid.V, grid.F, p), gp::UsageError);
  p.grain_angles.clear();
  p.k_stretch = 0.0;
  CHECK_THROWS_AS(build_rest_state(grid.V, grid.F, p), gp::UsageError);
}
