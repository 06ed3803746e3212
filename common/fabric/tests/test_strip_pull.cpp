// A strip of each fabric pulled along its warp, its weft and its bias, solved
// for its static state with the cloth model's membrane (cloth_energy.h): the
// reaction per width over the strain is the fabric's stiffness in that
// direction (README.md, "The library": the bias column).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "cloth/cloth_energy.h"
#include "cloth/cloth_model.h"
#include "fabric/fabric.h"

using namespace gp::cloth;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Strip {
  Eigen::MatrixXd V;  // #V by 3, in the xy-plane
  Eigen::MatrixXi F;
  std::vector<int> left, right;
};

// nx by ny quads of a length x width strip along x, each split along alternating diagonals.
Strip make_strip(int nx, int ny, double length, double width) {
  Strip s;
  s.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) s.V.row(j * (nx + 1) + i) << length * i / nx, width * j / ny, 0.0;
  s.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      if ((i + j) % 2 == 0) {
        s.F.row(f++) << a, b, d;
        s.F.row(f++) << a, d, c;
      } else {
        s.F.row(f++) << a, b, c;
        s.F.row(f++) << b, d, c;
      }
    }
  }
  for (int j = 0; j <= ny; ++j) {
    s.left.push_back(j * (nx + 1));
    s.right.push_back(j * (nx + 1) + nx);
  }
  return s;
}

// Membrane energy gradient and (projected) Hessian of the whole strip, 3#V.
void membrane(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const ClothRestState& rest,
              const ClothParameters& p, Eigen::VectorXd& g, Eigen::MatrixXd& H) {
  const int n = static_cast<int>(V.rows());
  g = Eigen::VectorXd::Zero(3 * n);
  H = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix3d X;
    for (int k = 0; k < 3; ++k) X.col(k) = V.row(F(f, k)).transpose();
    const Vector9d gf = stretch_gradient(X, rest.triangles[f], p.k_stretch, p.compression_ratio) +
                        shear_gradient(X, rest.triangles[f], p.k_shear);
    const Matrix9d Hf = stretch_hessian(X, rest.triangles[f], p.k_stretch, true, p.compression_ratio) +
                        shear_hessian(X, rest.triangles[f], p.k_shear, true);
    for (int a = 0; a < 3; ++a) {
      g.segment<3>(3 * F(f, a)) += gf.segment<3>(3 * a);
      for (int b = 0; b < 3; ++b) H.block<3, 3>(3 * F(f, a), 3 * F(f, b)) += Hf.block<3, 3>(3 * a, 3 * b);
    }
  }
}

// The strip's ends held at x = 0 and x = L (1 + strain), free across (one
// corner held in y against rigid sliding), every vertex in the plane; Newton
// to equilibrium. Returns the pull's reaction per width over the strain [N/m].
double pulled_stiffness(const gp::fabric::Fabric& fabric, double grain_angle, double strain) {
  const double length = 0.2, width = 0.05;
  const Strip s = make_strip(16, 4, length, width);
  ClothParameters p;
  p.k_stretch = fabric.k_warp;
  p.k_stretch_weft = fabric.k_weft;
  p.k_shear = fabric.k_shear;
  p.compression_ratio = fabric.compression_ratio;
  p.material_direction = Eigen::Vector3d::UnitX();  // the warp along the pull, then turned
  p.grain_angles.assign(s.F.rows(), grain_angle);
  const ClothRestState rest = build_rest_state(s.V, s.F, p);

  const int n = static_cast<int>(s.V.rows());
  std::vector<bool> fixed(3 * n, false);
  for (int v = 0; v < n; ++v) fixed[3 * v + 2] = true;
  for (int v : s.left) fixed[3 * v] = true;
  for (int v : s.right) fixed[3 * v] = true;
  fixed[3 * s.left[0] + 1] = true;
  std::vector<int> free_ids;
  for (int i = 0; i < 3 * n; ++i)
    if (!fixed[i]) free_ids.push_back(i);

  Eigen::MatrixXd V = s.V;
  V.col(0) *= 1.0 + strain;  // a uniform start; the lateral freedom is found by Newton
  Eigen::VectorXd g;
  Eigen::MatrixXd H;
  for (int it = 0; it < 60; ++it) {
    membrane(V, s.F, rest, p, g, H);
    Eigen::VectorXd gf(free_ids.size());
    Eigen::MatrixXd Hf(free_ids.size(), free_ids.size());
    for (size_t i = 0; i < free_ids.size(); ++i) {
      gf(i) = g(free_ids[i]);
      for (size_t j = 0; j < free_ids.size(); ++j) Hf(i, j) = H(free_ids[i], free_ids[j]);
    }
    if (gf.norm() < 1e-12 * fabric.k_warp * width) break;
    const Eigen::VectorXd dx = Hf.ldlt().solve(-gf);
    for (size_t i = 0; i < free_ids.size(); ++i) V(free_ids[i] / 3, free_ids[i] % 3) += dx(i);
  }
  membrane(V, s.F, rest, p, g, H);
  double reaction = 0.0;
  for (int v : s.right) reaction += g(3 * v);  // dE/dx at the pulled end: the pulling force
  return reaction / (width * strain);
}

}  // namespace

TEST_CASE("a strip pulled along warp, weft and bias gives its fabric's stiffnesses", "[fabric][cloth]") {
  const double strain = 1e-3;
  for (const char* name : {"cotton-poplin", "denim-11oz", "jersey-interlock", "swimwear-knit", "paper"}) {
    const gp::fabric::Fabric& f = *gp::fabric::find_fabric(name);
    INFO(name);
    const double warp = pulled_stiffness(f, 0.0, strain);
    const double weft = pulled_stiffness(f, kPi / 2.0, strain);
    const double bias = pulled_stiffness(f, kPi / 4.0, strain);
    const double bias_expected = 1.0 / (0.25 * (1.0 / f.k_warp + 1.0 / f.k_weft + 1.0 / f.k_shear));
    // The membrane is linear to within the strain (1e-3) here.
    CHECK(warp == Approx(f.k_warp).epsilon(3e-3));
    CHECK(weft == Approx(f.k_weft).epsilon(3e-3));
    CHECK(bias == Approx(bias_expected).epsilon(3e-3));
    // The ratios a cutter reads off the fabric.
    CHECK(weft / warp == Approx(f.k_weft / f.k_warp).epsilon(5e-3));
    // The other bias (-45 degrees) is the same.
    CHECK(pulled_stiffness(f, -kPi / 4.0, strain) == Approx(bias).epsilon(1e-6));
  }
  // Wovens give way on the bias, far below their warp and weft.
  const gp::fabric::Fabric& poplin = *gp::fabric::find_fabric("cotton-poplin");
  CHECK(pulled_stiffness(poplin, kPi / 4.0, strain) < 0.05 * poplin.k_weft);
}
