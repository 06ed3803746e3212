#pragma once
// Per-triangle stretch measure and clipped rest targets (Wolff et al. 2023,
// appendix A).
//
// The principal stretches and the triangle frames are mesh/principal_stretches.h.
//
// Clipping: with F = U S V^T and S = diag(s1, s2), the clipped gradient is
// G = U min(S, 1+delta) V^T, and the target rest triangle is G^-1 D_sim =
// V diag(s_i / min(s_i, 1+delta)) V^T D_rest, i.e. the rest triangle stretched by
// max(1, s_i/(1+delta)) along each principal direction: stretch above 1+delta is
// taken into the rest shape, compression is left untouched. Where s_i = 0 (a
// collapsed simulated triangle) the pseudo-inverse of S_clipped is used and the
// factor on that direction is 1 (untouched), so a target is never degenerate and,
// since the factors are positive, never flipped.
#include <vector>

#include <Eigen/Core>

#include "mesh/principal_stretches.h"

namespace gp::adapt {

// Target rest edge matrix (2D, columns t1-t0, t2-t0) from the rest edge matrix
// D_rest and the deformation gradient F: when the largest principal stretch is
// above 1 + delta, every principal stretch above c = 1 + delta - hysteresis is
// clipped to c (hysteresis 0: the paper's clipping at 1 + delta). A small
// hysteresis keeps a garment held stretched by the body (whose stretch returns to
// the clip value after every adaptation) from hovering just above the limit.
Eigen::Matrix2d clipped_target(const Eigen::Matrix2d& D_rest, const Eigen::Matrix2d& F, double delta,
                               double hysteresis);

struct ClipStats {
  int clipped_faces = 0;      // faces with a principal stretch above 1 + delta
  double max_stretch = 0.0;   // largest principal stretch before clipping
  double target_area = 0.0;   // sum of the target areas [m^2]
};

// Targets for all faces. area_factors (#F, > 0, optional: nullptr for none)
// scale the target areas (paint, T3). Throws GeometryError for degenerate rest
// triangles, UsageError for bad sizes or non-positive factors.
std::vector<Eigen::Matrix2d> clipped_targets(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_sim,
                                             const Eigen::MatrixXi& F, double delta,
                                             const Eigen::VectorXd* area_factors,
                                             ClipStats* stats, double hysteresis);

}  // namespace gp::adapt
