#pragma once
// Per-element cloth energies with analytic gradients and Hessians. One triangle's positions are
// the columns of X = [x0 x1 x2]; gradients are 9-vectors (x0, x1, x2 stacked), Hessians 9x9.
//
// Membrane (Baraff & Witkin 1998, "Large steps in cloth simulation", sec. 4.2-4.3), per unit rest
// area A so that it does not depend on the resolution (BW's C = a(...) scales with a^2):
// W = Ds Dm^-1 = [w_u w_v], Ds = [x1-x0, x2-x0] (3x2), Dm the rest edges in the (u,v) frame (2x2);
//   stretch_energy = k_stretch * A / 2 * ((|w_u| - 1)^2 + r_weft (|w_v| - 1)^2)   [m, m^2; k in J/m^2 = N/m]
//     u is the warp and v the weft of the face's fabric, k_stretch the warp's stiffness and
//     r_weft = k_weft / k_warp (TriangleRest::weft_ratio; 1: the paper's isotropic material; the
//     measured fabrics and their units: common/fabric/README.md)
//     with k_stretch times compression_ratio for a condition under compression (|w| < 1): cloth
//     buckles at a far smaller load than it stretches under, at wavelengths below the mesh's
//     (the buckling stiffness of garment CAD; common/cloth/README.md, "Compression")
//   shear_energy   = k_shear   * A / 2 * (w_u . w_v)^2
// Bending (Bergou, Wardetzky, Harmon, Zorin, Grinspun 2006, "A quadratic bending model for
// inextensible surfaces"), per interior edge (x0, x1) with opposite vertices x2, x3 and c_k, d_k the
// cotangents of the rest angles at edge vertex k in the two triangles, k_bend in J = N m:
//   K = [c1+d1, c0+d0, -c0-c1, -d0-d1],   Q_e = 3 / (A_0 + A_1) K K^T,
//   bending_energy = k_bend / 2 * sum_e x^T Q_e x   (flat rest state: constant Hessian k_bend Q)
// Damping (BW sec. 4.5): force -k_d A J^T J v per condition C, J = dC/dx, a PSD matrix; stretch and
// shear damping in N s/m, bending damping in N m s (through Q).
#include <Eigen/Core>

namespace gp::cloth {

using Vector9d = Eigen::Matrix<double, 9, 1>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

// Rest data of one triangle: w_u = sum_i a(i) x_i, w_v = sum_i b(i) x_i, u the warp and v the weft.
struct TriangleRest {
  double area = 0.0;           // rest area [m^2]
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  // k_weft / k_warp of the face's fabric: the weft's stretch term is this times the warp's (the
  // cloth model sets it from ClothParameters; 1 is isotropic). A property of the face's material,
  // kept beside its frame so that every term that reads the frame also reads the anisotropy.
  double weft_ratio = 1.0;
};

// Unit warp direction in the plane of the rest triangle X_rest = [x0 x1 x2]: `material_direction`
// projected into the plane, turned by `grain_angle` (radians, counter-clockwise about the face
// normal (x1-x0) x (x2-x0): a turned grain, e.g. 45 degrees for a bias cut); where the direction is
// nearly normal to the triangle, the first edge is used instead. The u axis of triangle_rest.
// Throws GeometryError for a degenerate rest triangle, as triangle_rest.
Eigen::Vector3d warp_direction(const Eigen::Matrix3d& X_rest,
                               const Eigen::Vector3d& material_direction = Eigen::Vector3d::UnitY(),
                               double grain_angle = 0.0);

// Rest data from the rest triangle X_rest = [x0 x1 x2]. The u axis is the warp_direction (the
// `material_direction` projected into the triangle's plane and turned by `grain_angle`); where it
// is nearly normal to the triangle, the first edge is used instead. weft_ratio is left 1. Throws GeometryError for a degenerate (or non-finite)
// rest triangle, where 2A / (longest edge)^2 < 1e-6 (slivers below that make the implicit system
// too ill-conditioned for an accurate step; see cloth_energy.cpp).
TriangleRest triangle_rest(const Eigen::Matrix3d& X_rest,
                           const Eigen::Vector3d& material_direction = Eigen::Vector3d::UnitY(),
                           double grain_angle = 0.0);

// Rest data from a flat triangle given by its 2D corners P = [p0 p1 p2] (a sewing pattern piece,
// the pattern's x axis the warp direction). A mirrored triangle gives the same energies (they
// depend on |w_u|, |w_v| and w_u . w_v only). Throws GeometryError for a zero-area triangle, as
// triangle_rest.
TriangleRest triangle_rest_flat(const Eigen::Matrix<double, 2, 3>& P);
// W = [w_u w_v] of triangle X.
Eigen::Matrix<double, 3, 2> triangle_w(const Eigen::Matrix3d& X, const TriangleRest& rest);

// Stretch (k: the warp's stiffness in N/m, the weft's is k * rest.weft_ratio; compression_ratio in
// (0, 1], the fraction of k resisting compression).
// project_psd clamps the negative curvature across w under compression (|w| < 1), which is the
// exact eigen-projection of the 9x9 block.
double stretch_energy(const Eigen::Matrix3d& X, const TriangleRest& rest, double k,
                      double compression_ratio = 1.0);
Vector9d stretch_gradient(const Eigen::Matrix3d& X, const TriangleRest& rest, double k,
                          double compression_ratio = 1.0);
Matrix9d stretch_hessian(const Eigen::Matrix3d& X, const TriangleRest& rest, double k,
                         bool project_psd = false, double compression_ratio = 1.0);

// Shear (k in N/m). project_psd is the exact eigen-projection of the 6x6 Hessian in (w_u, w_v)
// space (closed form, see cloth_energy.cpp), mapped to 9x9.
double shear_energy(const Eigen::Matrix3d& X, const TriangleRest& rest, double k);
Vector9d shear_gradient(const Eigen::Matrix3d& X, const TriangleRest& rest, double k);
Matrix9d shear_hessian(const Eigen::Matrix3d& X, const TriangleRest& rest, double k,
                       bool project_psd = false);

// Damping matrices k_d A J^T J (PSD) of the stretch and shear conditions.
Matrix9d stretch_damping(const Eigen::Matrix3d& X, const TriangleRest& rest, double k_d);
Matrix9d shear_damping(const Eigen::Matrix3d& X, const TriangleRest& rest, double k_d);

// Bending stencil of one interior edge: weights K and coefficient 3/(A0+A1).
struct BendingStencil {
  Eigen::Vector4i vertex_ids = Eigen::Vector4i::Constant(-1);  // x0, x1 (edge), x2, x3
  Eigen::Vector4d K = Eigen::Vector4d::Zero();
  double coefficient = 0.0;  // 3 / (A0 + A1) [1/m^2]
};

// Stencil from the rest positions X_rest = [x0 x1 x2 x3] (columns). Throws GeometryError when
// either rest triangle is degenerate.
BendingStencil bending_stencil(const Eigen::Matrix<double, 3, 4>& X_rest);

// Bending energy of one stencil at X = [x0 x1 x2 x3] (k in J).
double bending_energy(const Eigen::Matrix<double, 3, 4>& X, const BendingStencil& s, double k);
Vector12d bending_gradient(const Eigen::Matrix<double, 3, 4>& X, const BendingStencil& s, double k);
Matrix12d bending_hessian(const BendingStencil& s, double k);

// Gravity on lumped masses m (#V, kg) with acceleration g (m/s^2): E = -sum m_i g.x_i.
double gravity_energy(const Eigen::MatrixXd& V, const Eigen::VectorXd& m, const Eigen::Vector3d& g);
Eigen::MatrixXd gravity_gradient(const Eigen::MatrixXd& V, const Eigen::VectorXd& m,
                                 const Eigen::Vector3d& g);

// The membrane system block of one triangle for an implicit Euler step of size h,
//   K = h^2 (H_stretch + H_shear)_projected + h (D_stretch + D_shear),
// together with the membrane energy gradient; this is what the simulator assembles (sum of the
// per-term functions above, computed once in (w_u, w_v) space). Returns the membrane energy.
struct MembraneCoefficients {
  double k_stretch = 800.0;  // the warp's; the weft's is k_stretch * rest.weft_ratio
  double k_shear = 200.0;
  double damping_stretch = 100.0;
  double damping_shear = 1.0;
  double compression_ratio = 0.1;  // fraction of k_stretch under compression (|w| < 1)
};
double membrane_system_block(const Eigen::Matrix3d& X, const TriangleRest& rest,
                             const MembraneCoefficients& c, double h, Vector9d& gradient,
                             Matrix9d& K);

}  // namespace gp::cloth
