#pragma once
// The cloth model of a whole garment mesh: material parameters, the rest-state
// data every step needs (per-triangle (u,v) frames, bending stencils, lumped
// masses), and the total energy and its gradient (used by tests, checks and
// reports; the simulator assembles the same terms itself).
// V_rest, V are #V by 3 positions in metres; F is #F by 3 vertex ids.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth/cloth_energy.h"

namespace gp::cloth {

// Material parameters. Defaults are the paper's values (Wolff et al. 2023), read
// in this project's per-unit-rest-area formulation (see cloth_energy.h); the
// measured fabrics: common/fabric/README.md.
struct ClothParameters {
  double k_stretch = 800.0;        // N/m, per unit rest area, along the warp (u)
  double k_stretch_weft = 800.0;   // N/m, along the weft (v); equal to k_stretch: isotropic (the paper)
  // Fraction of k_stretch that resists compression (|w| < 1): cloth buckles
  // under a small fraction of the load it stretches under (README.md,
  // "Compression"); 1 is the paper's symmetric stretch term.
  double compression_ratio = 0.1;
  double k_shear = 200.0;          // N/m, per unit rest area
  double k_bend = 1e-6;            // J (N m), quadratic bending (Bergou et al. 2006)
  double damping_stretch = 100.0;  // N s/m
  double damping_shear = 1.0;      // N s/m
  double damping_bend = 1e-5;      // N m s
  double density = 0.15;           // kg/m^2 of rest area (a light cotton shirting)
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};               // m/s^2
  // Warp direction (u axis) before any turn: the body's vertical in the design
  // pose, as a tailor lays the grain.
  Eigen::Vector3d material_direction{0.0, 1.0, 0.0};
  // Per face (#F, optional, radians): the grain turned about the face normal
  // from that (a bias-cut region: pi/4); empty: no face turned.
  std::vector<double> grain_angles;
};

// k_stretch_weft / k_stretch, the TriangleRest::weft_ratio of every face.
// Throws UsageError for a weft stiffness without a warp one, or a negative one.
double weft_ratio(const ClothParameters& params);

// The grain angle of face f (0 when params has none). Throws UsageError when
// params has angles but not one per face of a mesh of `face_count` faces.
double grain_angle(const ClothParameters& params, int f, long face_count);

struct ClothRestState {
  std::vector<TriangleRest> triangles;   // #F
  std::vector<BendingStencil> stencils;  // one per interior (two-face) edge
  Eigen::VectorXd masses;                // #V lumped masses [kg]: density * area / 3 per face
  Eigen::SparseMatrix<double> Q;         // #V by #V bending matrix sum_e Q_e (scalar, per coordinate)
  double total_area = 0.0;               // m^2
};

// Rest state of the mesh (V_rest, F). Throws GeometryError naming the face for a
// zero-area rest triangle, InputError for out-of-range vertex ids.
ClothRestState build_rest_state(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                const ClothParameters& params);

// Recomputes `rest` for a new rest shape V_rest with the same connectivity
// (keeps the stencils' vertex ids and the pattern of Q; used after every
// adaptation). Throws like build_rest_state.
void update_rest_state(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                       const ClothParameters& params, ClothRestState& rest);

// Replaces the per-face rest triangles of `rest` (for example the flat pieces of
// a sewn pattern, see triangle_rest_flat) and recomputes the lumped masses and
// total area from their areas; the bending stencils stay (the model assumes a
// flat rest state either way). Throws UsageError when the count differs from
// the rest state's faces, GeometryError naming the face for a zero or
// non-finite area. Every triangle's weft_ratio is set from params (the
// fabric is the model's, whatever the triangles came from).
void set_rest_triangles(const std::vector<TriangleRest>& triangles, const Eigen::MatrixXi& F,
                        const ClothParameters& params, ClothRestState& rest);

// Energies of the configuration V [J].
struct ClothEnergies {
  double stretch = 0.0;
  double shear = 0.0;
  double bend = 0.0;
  double gravity = 0.0;
  double total() const { return stretch + shear + bend + gravity; }
};
ClothEnergies cloth_energies(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                             const ClothRestState& rest, const ClothParameters& params);

// Principal stretches s1 >= s2 of every face of the configuration V against
// its rest triangle (the singular values of W = [w_u w_v], whatever the rest
// triangles came from: a rest shape or flat pattern pieces). #F by 2.
Eigen::MatrixXd face_principal_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                         const ClothRestState& rest);

// Stretch of every face along its warp and its weft, |w_u| and |w_v|, #F by 2
// (1: the rest length; against the rest triangles, as face_principal_stretches).
Eigen::MatrixXd face_grain_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const ClothRestState& rest);

// Largest stretch of every face relative to per-direction limits,
// max(|w_u| / limit_warp, |w_v| / limit_weft), #F: a face is within its
// fabric's limits when this is at most 1. The bias (shear) is not limited:
// a woven gives way there by turning its yarns (common/fabric/README.md,
// "Stretch limits").
Eigen::VectorXd face_limit_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const ClothRestState& rest, double limit_warp, double limit_weft);

// Gradient of the total energy (stretch + shear + bend + gravity), #V by 3 [N].
Eigen::MatrixXd cloth_gradient(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const ClothRestState& rest, const ClothParameters& params);

}  // namespace gp::cloth
