#pragma once
// Clipped rest targets (Wolff et al. 2023, appendix A; the stretches and
// frames are mesh/principal_stretches.h). With F = U S V^T, the clipped
// gradient is G = U min(S, c) V^T and the target G^-1 D_sim = V diag(s_i /
// min(s_i, c)) V^T D_rest: stretch above c goes into the rest shape,
// compression is left alone. At s_i = 0 the factor is 1, so a target is
// never degenerate nor flipped.
#include <vector>

#include <Eigen/Core>

#include "mesh/principal_stretches.h"

namespace gp::adapt {

// Target rest edge matrix [t1-t0, t2-t0] (2D) from D_rest and F: when s1 >
// 1 + delta, every s_i above c = 1 + delta - hysteresis is clipped to c
// (hysteresis 0: the paper's rule).
Eigen::Matrix2d clipped_target(const Eigen::Matrix2d& D_rest, const Eigen::Matrix2d& F, double delta,
                               double hysteresis);

struct ClipStats {
  int clipped_faces = 0;      // faces with a principal stretch above 1 + delta (with a GrainClip:
                              //   above their limit in some direction)
  double max_stretch = 0.0;   // largest principal stretch before clipping
  double target_area = 0.0;   // sum of the target areas [m^2]
  // With a GrainClip only (else 0): the largest stretch along the warp and
  // along the weft, and the largest of s_u / limit_warp and s_v / limit_weft
  // (1: at a limit).
  double max_warp_stretch = 0.0;
  double max_weft_stretch = 0.0;
  double max_limit_stretch = 0.0;
};

// Per-direction limits of a fabric (common/fabric/README.md, "Stretch
// limits"), as the clip uses them: stretch ratios along the warp and the weft
// (the adaptation's own, its margin taken off), and each face's warp as the
// cloth model lays it (cloth::warp_direction).
struct GrainClip {
  double limit_warp = 1.1;
  double limit_weft = 1.1;
  Eigen::Vector3d material_direction = Eigen::Vector3d::UnitY();
  const std::vector<double>* grain_angles = nullptr;  // per face, radians; nullptr: no face turned
};

// The clip against per-direction limits: the stretches along the warp and
// the weft, s_u = |G R e_u| and s_v = |G R e_v| (R: the material frame's
// axes in the rest triangle's frame, columns warp and weft), each against its
// own limit. Where one exceeds its limit, the rest grows along that material
// direction by s / (limit - hysteresis): T = R diag(f_u, f_v) R^T D_rest.
// Shear (the bias) is not clipped: a woven gives way on the bias by turning
// its yarns, not by stretching them, at the fabric's shear stiffness
// (common/fabric/README.md, "Stretch limits"). A face stretched along one
// direction only clips as the paper's rule would with that direction's limit.
Eigen::Matrix2d clipped_target_grain(const Eigen::Matrix2d& D_rest, const Eigen::Matrix2d& G,
                                     const Eigen::Matrix2d& R, double limit_warp, double limit_weft,
                                     double hysteresis);

// Targets for all faces. area_factors (#F, > 0, optional: nullptr for none)
// scale the target areas (paint, T3). Throws GeometryError for degenerate rest
// triangles, UsageError for bad sizes or non-positive factors.
std::vector<Eigen::Matrix2d> clipped_targets(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_sim,
                                             const Eigen::MatrixXi& F, double delta,
                                             const Eigen::VectorXd* area_factors,
                                             ClipStats* stats, double hysteresis);

// The same against a fabric's per-direction limits (clipped_target_grain).
// Throws as clipped_targets, and UsageError for limits below 1 or grain
// angles not one per face.
std::vector<Eigen::Matrix2d> clipped_targets(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_sim,
                                             const Eigen::MatrixXi& F, const GrainClip& grain,
                                             const Eigen::VectorXd* area_factors, ClipStats* stats,
                                             double hysteresis);

}  // namespace gp::adapt
