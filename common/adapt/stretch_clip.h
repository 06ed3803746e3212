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
