// Every cloth energy against central finite differences, over random, scaled,
// compressed, near-degenerate and inverted configurations; rest state, rigid
// motions, PSD projection, and the assembled membrane block.
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

using Matrix34d = Eigen::Matrix<double, 3, 4>;

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// A rest triangle of size ~`scale` and a family of deformed ones.
struct Case {
  Eigen::Matrix3d X_rest;
  Eigen::Matrix3d X;
  const char* kind;
};

std::vector<Case> make_cases(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Case> cases;
  const double scales[] = {1e-3, 0.02, 1.0, 50.0};
  for (double scale : scales) {
    for (int rep = 0; rep < 6; ++rep) {
      Eigen::Matrix3d X_rest;
      X_rest << 0.0, 1.0, 0.3 + 0.2 * u(rng), 0.0, 0.1 * u(rng), 0.9 + 0.1 * u(rng), 0.0,
          0.2 * u(rng), 0.2 * u(rng);
      X_rest = (random_rotation(rng) * X_rest * scale).eval();
      const Eigen::Matrix3d R = random_rotation(rng);
      // General deformation.
      Eigen::Matrix3d X = R * X_rest;
      for (int i = 0; i < 9; ++i) X(i) += 0.3 * scale * u(rng);
      cases.push_back({X_rest, X, "random"});
      // Uniform compression (negative curvature of stretch).
      cases.push_back({X_rest, (0.6 * R * X_rest).eval(), "compressed"});
      // Near-degenerate: x2 almost on the line x0-x1.
      Eigen::Matrix3d D = R * X_rest;
      D.col(2) = D.col(0) + 0.5 * (D.col(1) - D.col(0));
      D(1, 2) += 1e-4 * scale;
      cases.push_back({X_rest, D, "near-degenerate"});
      // Inverted: x2 mirrored through the edge x0-x1.
      Eigen::Matrix3d Inv = X_rest;
      const Eigen::Vector3d e = (Inv.col(1) - Inv.col(0)).normalized();
      const Eigen::Vector3d d = Inv.col(2) - Inv.col(0);
      Inv.col(2) = Inv.col(0) + 2.0 * d.dot(e) * e - d;
      cases.push_back({X_rest, Inv, "inverted"});
    }
  }
  return cases;
}


}  // namespace

TEST_CASE("stretch and shear gradients and Hessians match finite differences", "[energy]") {
  const double k = 800.0;
  int checked = 0, kinks = 0;
  // The stretch term at the paper's symmetric stiffness, at the shipped
  // compression ratio, and at the smallest one the material accepts.
  for (const double ratio : {1.0, 0.1, 1e-3}) {
    for (const Case& c : make_cases(7)) {
      const TriangleRest rest = triangle_rest(c.X_rest);
      const double scale = (c.X_rest.col(1) - c.X_rest.col(0)).norm();
      const double eps = 1e-6 * scale;
      INFO("case " << c.kind << " scale " << scale << " compression ratio " << ratio);

      auto se = [&](const Eigen::Matrix3d& X) { return stretch_energy(X, rest, k, ratio); };
      auto sg = [&](const Eigen::Matrix3d& X) { return stretch_gradient(X, rest, k, ratio); };
      auto he = [&](const Eigen::Matrix3d& X) { return shear_energy(X, rest, k); };
      auto hg = [&](const Eigen::Matrix3d& X) { return shear_gradient(X, rest, k); };

      const Vector9d g_s = sg(c.X), g_h = hg(c.X);
      // Gradient scale k*A/L is the natural force magnitude of one triangle.
      const double force_scale = k * rest.area / scale;
      CHECK((g_s - fd_gradient(c.X, eps, se)).norm() <= 1e-6 * force_scale * (1.0 + g_s.norm() / force_scale));
      CHECK((g_h - fd_gradient(c.X, eps, he)).norm() <= 1e-6 * force_scale * (1.0 + g_h.norm() / force_scale));

      const double hess_scale = k * rest.area / (scale * scale);
      const Matrix9d H_s = stretch_hessian(c.X, rest, k, false, ratio);
      const Matrix9d H_h = shear_hessian(c.X, rest, k);
      // With a softer compression the stiffness jumps at |w| = 1 (the force is
      // continuous there, its derivative is not), so differences across it are
      // no Hessian: the mirrored cases keep both lengths at exactly 1.
      const Eigen::Matrix<double, 3, 2> W = triangle_w(c.X, rest);
      const bool at_kink =
          ratio != 1.0 && std::min(std::abs(W.col(0).norm() - 1.0), std::abs(W.col(1).norm() - 1.0)) < 1e-4;
      kinks += at_kink ? 1 : 0;
      if (!at_kink) {
        CHECK((H_s - fd_hessian(c.X, eps, sg)).norm() <= 1e-5 * hess_scale * (1.0 + H_s.norm() / hess_scale));
      }
      CHECK((H_h - fd_hessian(c.X, eps, hg)).norm() <= 1e-5 * hess_scale * (1.0 + H_h.norm() / hess_scale));
      CHECK((H_s - H_s.transpose()).norm() <= 1e-12 * H_s.norm());
      ++checked;
    }
  }
  CHECK(checked == 3 * 96);
  CHECK(kinks == 2 * 24);  // the mirrored triangles, at the two softened ratios
}

TEST_CASE("compression is resisted by its own fraction of the stretch stiffness", "[energy]") {
  const double k = 800.0, ratio = 0.1;
  const Eigen::Matrix3d X_rest = (Eigen::Matrix3d() << 0, 0.02, 0, 0, 0, 0.02, 0, 0, 0).finished();
  const TriangleRest rest = triangle_rest(X_rest);
  // Uniform compression to 0.9: both conditions at -0.1.
  CHECK(stretch_energy(0.9 * X_rest, rest, k, ratio) == Approx(ratio * k * rest.area * 0.01).epsilon(1e-12));
  CHECK(stretch_energy(0.9 * X_rest, rest, k, ratio) ==
        Approx(ratio * stretch_energy(0.9 * X_rest, rest, k)).epsilon(1e-12));
  // Stretch is untouched by the ratio.
  CHECK(stretch_energy(1.1 * X_rest, rest, k, ratio) == Approx(stretch_energy(1.1 * X_rest, rest, k)).epsilon(1e-14));
  // Stretched along one axis, compressed along the other: only that condition is softened.
  Eigen::Matrix3d X = X_rest;
  X.row(0) *= 1.05;
  X.row(1) *= 0.95;
  CHECK(stretch_energy(X, rest, k, ratio) == Approx(0.5 * k * rest.area * (1.0 + ratio) * 0.05 * 0.05).epsilon(1e-10));
  // At |w| = 1 the force is continuous: a hair either side of the rest
  // length gives forces of the same vanishing size.
  for (const double t : {1.0 - 1e-9, 1.0 + 1e-9}) {
    CHECK(stretch_gradient(t * X_rest, rest, k, ratio).norm() <= 1e-8 * k * rest.area / 0.02);
  }
  // The projected Hessian of a compressed triangle is PSD and ratio times the symmetric one.
  const Matrix9d Hc = stretch_hessian(0.8 * X_rest, rest, k, true, ratio);
  CHECK(min_eigenvalue(Hc) >= -1e-10 * Hc.norm());
  CHECK((Hc - ratio * stretch_hessian(0.8 * X_rest, rest, k, true)).norm() <= 1e-12 * Hc.norm());
}

TEST_CASE("projected Hessians are PSD and only remove negative curvature", "[energy]") {
  const double k = 200.0;
  for (const Case& c : make_cases(11)) {
    const TriangleRest rest = triangle_rest(c.X_rest);
    INFO("case " << c.kind);
    const Matrix9d S = stretch_hessian(c.X, rest, k), Sp = stretch_hessian(c.X, rest, k, true);
    const Matrix9d H = shear_hessian(c.X, rest, k), Hp = shear_hessian(c.X, rest, k, true);
    const double tol_s = 1e-10 * (1.0 + Sp.norm());
    const double tol_h = 1e-10 * (1.0 + Hp.norm());
    CHECK(min_eigenvalue(Sp) >= -tol_s);
    CHECK(min_eigenvalue(Hp) >= -tol_h);
    // Projection adds the clamped negative part: P - H is PSD.
    CHECK(min_eigenvalue(Sp - S) >= -tol_s);
    CHECK(min_eigenvalue(Hp - H) >= -tol_h);
  }
  // A compressed triangle has an indefinite exact stretch Hessian.
  const Eigen::Matrix3d X_rest = (Eigen::Matrix3d() << 0, 1, 0, 0, 0, 1, 0, 0, 0).finished();
  const TriangleRest rest = triangle_rest(X_rest);
  CHECK(min_eigenvalue(stretch_hessian(0.5 * X_rest, rest, 800.0)) < -1.0);
  // A sheared one has an indefinite exact shear Hessian, while its projection
  // equals it wherever the exact one is already PSD (at rest).
  Eigen::Matrix3d Xs = X_rest;
  Xs(0, 2) = 0.8;
  CHECK(min_eigenvalue(shear_hessian(Xs, rest, 200.0)) < -1.0);
  CHECK((shear_hessian(X_rest, rest, 200.0, true) - shear_hessian(X_rest, rest, 200.0)).norm() < 1e-12);
}

TEST_CASE("membrane system block is the sum of the per-term functions", "[energy]") {
  const double h = 0.0025;
  for (const double ratio : {1.0, 0.1}) {
    const MembraneCoefficients c{800.0, 200.0, 100.0, 1.0, ratio};
    for (const Case& cs : make_cases(3)) {
      const TriangleRest rest = triangle_rest(cs.X_rest);
      Vector9d g;
      Matrix9d K;
      const double e = membrane_system_block(cs.X, rest, c, h, g, K);
      const Matrix9d K_ref = h * h * (stretch_hessian(cs.X, rest, c.k_stretch, true, ratio) +
                                      shear_hessian(cs.X, rest, c.k_shear, true)) +
                             h * (stretch_damping(cs.X, rest, c.damping_stretch) +
                                  shear_damping(cs.X, rest, c.damping_shear));
      const Vector9d g_ref =
          stretch_gradient(cs.X, rest, c.k_stretch, ratio) + shear_gradient(cs.X, rest, c.k_shear);
      CHECK(std::abs(e - stretch_energy(cs.X, rest, c.k_stretch, ratio) - shear_energy(cs.X, rest, c.k_shear)) <=
            1e-12 * (1.0 + e));
      CHECK((g - g_ref).norm() <= 1e-10 * (1.0 + g_ref.norm()));
      CHECK((K - K_ref).norm() <= 1e-10 * (1.0 + K_ref.norm()));
      CHECK(min_eigenvalue(K) >= -1e-10 * (1.0 + K.norm()));
      CHECK(min_eigenvalue(stretch_damping(cs.X, rest, 1.0)) >= -1e-12);
      CHECK(min_eigenvalue(shear_damping(cs.X, rest, 1.0)) >= -1e-12);
    }
  }
}

TEST_CASE("bending gradient and Hessian match finite differences; flat rest is force free", "[energy]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int rep = 0; rep < 20; ++rep) {
    const double scale = rep % 2 ? 0.01 : 1.0;
    Matrix34d X_rest;
    // Flat stencil in the xz plane: edge x0-x1, x2 and x3 on opposite sides.
    X_rest << 0.0, 1.0, 0.5 + 0.3 * u(rng), 0.5 + 0.3 * u(rng), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
        0.5 + 0.4 * u(rng), -0.5 + 0.4 * u(rng);
    X_rest *= scale;
    const BendingStencil s = bending_stencil(X_rest);
    const double k = 1e-6;
    CHECK(bending_gradient(X_rest, s, k).norm() <= 1e-12 * k / scale);
    CHECK(bending_energy(X_rest, s, k) <= 1e-20);

    Matrix34d X = X_rest;
    for (int i = 0; i < 12; ++i) X(i) += 0.2 * scale * u(rng);
    const double eps = 1e-6 * scale;
    Vector12d g_fd;
    Matrix12d H_fd;
    for (int i = 0; i < 12; ++i) {
      Matrix34d Xp = X, Xm = X;
      Xp(i % 3, i / 3) += eps;
      Xm(i % 3, i / 3) -= eps;
      g_fd(i) = (bending_energy(Xp, s, k) - bending_energy(Xm, s, k)) / (2.0 * eps);
      H_fd.col(i) = (bending_gradient(Xp, s, k) - bending_gradient(Xm, s, k)) / (2.0 * eps);
    }
    const Vector12d g = bending_gradient(X, s, k);
    CHECK((g - g_fd).norm() <= 1e-6 * (g.norm() + k / scale));
    CHECK((bending_hessian(s, k) - H_fd).norm() <= 1e-6 * (bending_hessian(s, k).norm()));
    // Rigid motions do not change the energy.
    Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    Matrix34d Y = R * X;
    Y.colwise() += Eigen::Vector3d(3, -1, 2);
    CHECK(bending_energy(Y, s, k) == Approx(bending_energy(X, s, k)).epsilon(1e-9));
  }
  // A stencil folded by 90 degrees stores energy.
  Matrix34d X;
  X << 0, 1, 0.5, 0.5, 0, 0, 0, 0.5, 0, 0, 0.5, 0;
  Matrix34d X_flat;
  X_flat << 0, 1, 0.5, 0.5, 0, 0, 0, 0, 0, 0, 0.5, -0.5;
  CHECK(bending_energy(X, bending_stencil(X_flat), 1.0) > 0.1);
}

TEST_CASE("zero-area rest triangles are rejected with a GeometryError", "[energy]") {
  Eigen::Matrix3d X;
  X << 0, 1, 2, 0, 1, 2, 0, 0, 0;  // collinear
  CHECK_THROWS_AS(triangle_rest(X), gp::GeometryError);
  X << 0, 0, 0, 0, 0, 0, 0, 0, 0;
  CHECK_THROWS_AS(triangle_rest(X), gp::GeometryError);
  X << 0, 1, std::nan(""), 0, 0, 1, 0, 0, 0;
  CHECK_THROWS_AS(triangle_rest(X), gp::GeometryError);

  gp::Mesh grid = gp::testing::make_grid(2, 2);
  grid.V.row(4) = grid.V.row(0);  // faces (0,3,4) and (0,4,1) collapse
  try {
    build_rest_state(grid.V, grid.F, ClothParameters{});
    FAIL("expected a GeometryError");
  } catch (const gp::GeometryError& e) {
    CHECK(std::string(e.where()).find("face") != std::string::npos);
  }
}

TEST_CASE("rest state gives zero force and rigid motions leave energies unchanged", "[energy]") {
  // A curved rest shape (open cylinder): membrane forces vanish at rest.
  const gp::Mesh cyl = gp::testing::make_open_cylinder(24, 10, 0.2, 0.5);
  ClothParameters params;
  params.gravity.setZero();
  params.k_bend = 0.0;
  const ClothRestState rest = build_rest_state(cyl.V, cyl.F, params);
  CHECK(cloth_gradient(cyl.V, cyl.F, rest, params).norm() <= 1e-9 * params.k_stretch * 0.2);
  CHECK(cloth_energies(cyl.V, cyl.F, rest, params).total() <= 1e-20);

  // Flat grid with bending: zero force at rest, bending included.
  const gp::Mesh grid = gp::testing::make_grid(8, 8, 0.3, 0.3);
  ClothParameters pb;
  pb.gravity.setZero();
  pb.k_bend = 1e-3;
  const ClothRestState rest_g = build_rest_state(grid.V, grid.F, pb);
  CHECK(cloth_gradient(grid.V, grid.F, rest_g, pb).norm() <= 1e-9);
  CHECK(rest_g.total_area == Approx(0.09).epsilon(1e-12));
  CHECK(rest_g.masses.sum() == Approx(0.09 * pb.density).epsilon(1e-12));

  // Deformed state, then a rigid motion: energies equal, gradient rotated.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd V = grid.V;
  for (int i = 0; i < V.size(); ++i) V(i) += 0.01 * u(rng);
  const Eigen::Matrix3d R = random_rotation(rng);
  const Eigen::RowVector3d t(0.3, -2.0, 1.0);
  const Eigen::MatrixXd W = (V * R.transpose()).rowwise() + t;
  const ClothEnergies e0 = cloth_energies(V, grid.F, rest_g, pb);
  const ClothEnergies e1 = cloth_energies(W, grid.F, rest_g, pb);
  CHECK(e0.stretch > 0.0);
  CHECK(e1.stretch == Approx(e0.stretch).epsilon(1e-10));
  CHECK(e1.shear == Approx(e0.shear).epsilon(1e-10));
  CHECK(e1.bend == Approx(e0.bend).epsilon(1e-9));
  const Eigen::MatrixXd g0 = cloth_gradient(V, grid.F, rest_g, pb);
  const Eigen::MatrixXd g1 = cloth_gradient(W, grid.F, rest_g, pb);
  CHECK((g1 - g0 * R.transpose()).norm() <= 1e-9 * g0.norm());

  // Whole-mesh gradient against finite differences of the total energy (gravity on).
  ClothParameters pg;
  pg.k_bend = 1e-3;
  const ClothRestState rest_p = build_rest_state(grid.V, grid.F, pg);
  const Eigen::MatrixXd G = cloth_gradient(V, grid.F, rest_p, pg);
  const double eps = 1e-7;
  double max_err = 0.0;
  for (int i = 0; i < V.size(); i += 7) {
    Eigen::MatrixXd Vp = V, Vm = V;
    Vp(i) += eps;
    Vm(i) -= eps;
    const double fd = (cloth_energies(Vp, grid.F, rest_p, pg).total() -
                       cloth_energies(Vm, grid.F, rest_p, pg).total()) / (2.0 * eps);
    max_err = std::max(max_err, std::abs(fd - G(i)));
  }
  CHECK(max_err <= 1e-6 * (1.0 + G.cwiseAbs().maxCoeff()));
}

TEST_CASE("updating the rest state in place equals building it anew", "[energy]") {
  const gp::Mesh cyl = gp::testing::make_open_cylinder(12, 6, 0.2, 0.4);
  const ClothParameters params;
  ClothRestState rest = build_rest_state(cyl.V, cyl.F, params);
  Eigen::MatrixXd V2 = cyl.V;
  V2.col(0) *= 1.3;
  V2.col(1) *= 0.9;
  update_rest_state(V2, cyl.F, params, rest);
  const ClothRestState fresh = build_rest_state(V2, cyl.F, params);
  CHECK(rest.total_area == Approx(fresh.total_area).epsilon(1e-14));
  CHECK((rest.masses - fresh.masses).norm() <= 1e-15);
  CHECK((Eigen::MatrixXd(rest.Q) - Eigen::MatrixXd(fresh.Q)).norm() <= 1e-10 * Eigen::MatrixXd(fresh.Q).norm());
  CHECK(rest.Q.nonZeros() == fresh.Q.nonZeros());
  for (size_t f = 0; f < rest.triangles.size(); ++f) {
    CHECK((rest.triangles[f].a - fresh.triangles[f].a).norm() <= 1e-12);
  }
  CHECK_THROWS_AS(update_rest_state(V2.topRows(5), cyl.F, params, rest), gp::UsageError);
}
