#include "adapt/stretch_clip.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/error.h"

namespace gp::adapt {
namespace {

Eigen::Matrix3d face_positions(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  Eigen::Matrix3d X;
  for (int k = 0; k < 3; ++k) X.col(k) = V.row(F(f, k)).transpose();
  return X;
}

}  // namespace

Eigen::Matrix2d clipped_target(const Eigen::Matrix2d& D_rest, const Eigen::Matrix2d& F, double delta,
                               double hysteresis) {
  const Eigen::JacobiSVD<Eigen::Matrix2d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector2d s = svd.singularValues();
  const double limit = 1.0 + delta;
  if (!(s(0) > limit)) return D_rest;  // nothing to clip: the rest triangle is its own target
  const double clip = limit - hysteresis;
  // s_i / min(s_i, clip), with the pseudo-inverse convention (factor 1) at s_i = 0.
  Eigen::Vector2d factor;
  for (int i = 0; i < 2; ++i) factor(i) = s(i) > clip ? s(i) / clip : 1.0;
  const Eigen::Matrix2d& Vm = svd.matrixV();
  return Vm * factor.asDiagonal() * Vm.transpose() * D_rest;
}

std::vector<Eigen::Matrix2d> clipped_targets(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_sim,
                                             const Eigen::MatrixXi& F, double delta,
                                             const Eigen::VectorXd* area_factors, ClipStats* stats,
                                             double hysteresis) {
  if (V_rest.rows() != V_sim.rows() || V_rest.cols() != 3 || V_sim.cols() != 3) {
    throw UsageError("rest and simulated positions must both be #V by 3");
  }
  if (!(delta >= 0.0)) throw UsageError("stretch limit delta must be non-negative");
  if (!(hysteresis >= 0.0) || !(hysteresis < 1.0 + delta)) {
    throw UsageError("clipping hysteresis must be in [0, 1 + delta)");
  }
  if (area_factors) {
    if (area_factors->size() != F.rows()) throw UsageError("one area factor per face is needed");
    for (int f = 0; f < F.rows(); ++f) {
      if (!((*area_factors)(f) > 0.0) || !std::isfinite((*area_factors)(f))) {
        throw UsageError("area factors must be positive", "face " + std::to_string(f));
      }
    }
  }
  if (!V_sim.allFinite()) throw NumericalError("simulated positions are not finite");
  std::vector<Eigen::Matrix2d> targets(F.rows());
  ClipStats local;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix3d X_rest = face_positions(V_rest, F, f);
    Eigen::Matrix2d G;
    try {
      G = deformation_gradient(X_rest, face_positions(V_sim, F, f));
    } catch (const GeometryError& e) {
      throw GeometryError(e.what(), "face " + std::to_string(f));
    }
    const double s_max = Eigen::JacobiSVD<Eigen::Matrix2d>(G).singularValues()(0);
    local.max_stretch = std::max(local.max_stretch, s_max);
    if (s_max > 1.0 + delta) ++local.clipped_faces;
    Eigen::Matrix2d T = clipped_target(triangle_frame_edges(X_rest), G, delta, hysteresis);
    if (area_factors) T *= std::sqrt((*area_factors)(f));
    targets[f] = T;
    local.target_area += 0.5 * T.determinant();
  }
  if (stats) *stats = local;
  return targets;
}

}  // namespace gp::adapt
