#include "adapt/stretch_clip.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "cloth/cloth_energy.h"
#include "core/error.h"

namespace gp::adapt {
namespace {

void check_clip_shapes(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_sim) {
  if (V_rest.rows() != V_sim.rows() || V_rest.cols() != 3 || V_sim.cols() != 3) {
    throw UsageError("rest and simulated positions must both be #V by 3");
  }
}

// The per-face area factors (one per face, positive, finite) and the
// simulated positions (finite) of a clipping.
void check_clip_inputs(const Eigen::MatrixXd& V_sim, const Eigen::MatrixXi& F, const Eigen::VectorXd* area_factors) {
  if (area_factors) {
    if (area_factors->size() != F.rows()) throw UsageError("one area factor per face is needed");
    for (int f = 0; f < F.rows(); ++f) {
      if (!((*area_factors)(f) > 0.0) || !std::isfinite((*area_factors)(f))) {
        throw UsageError("area factors must be positive", "face " + std::to_string(f));
      }
    }
  }
  if (!V_sim.allFinite()) throw NumericalError("simulated positions are not finite");
}

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
  check_clip_shapes(V_rest, V_sim);
  if (!(delta >= 0.0)) throw UsageError("stretch limit delta must be non-negative");
  if (!(hysteresis >= 0.0) || !(hysteresis < 1.0 + delta)) {
    throw UsageError("clipping hysteresis must be in [0, 1 + delta)");
  }
  check_clip_inputs(V_sim, F, area_factors);
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

Eigen::Matrix2d clipped_target_grain(const Eigen::Matrix2d& D_rest, const Eigen::Matrix2d& G,
                                     const Eigen::Matrix2d& R, double limit_warp, double limit_weft,
                                     double hysteresis) {
  const Eigen::Matrix2d Gm = G * R;  // columns: the images of the unit warp and weft
  const double su = Gm.col(0).norm(), sv = Gm.col(1).norm();
  if (!(su > limit_warp) && !(sv > limit_weft)) return D_rest;
  const double cu = limit_warp - hysteresis, cv = limit_weft - hysteresis;
  const Eigen::Vector2d factor(su > cu ? su / cu : 1.0, sv > cv ? sv / cv : 1.0);
  return R * factor.asDiagonal() * R.transpose() * D_rest;
}

std::vector<Eigen::Matrix2d> clipped_targets(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXd& V_sim,
                                             const Eigen::MatrixXi& F, const GrainClip& grain,
                                             const Eigen::VectorXd* area_factors, ClipStats* stats,
                                             double hysteresis) {
  check_clip_shapes(V_rest, V_sim);
  if (!(grain.limit_warp >= 1.0) || !(grain.limit_weft >= 1.0)) {
    throw UsageError("the grain's stretch limits must be at least 1");
  }
  const double least = std::min(grain.limit_warp, grain.limit_weft);
  if (!(hysteresis >= 0.0) || !(hysteresis < least)) throw UsageError("clipping hysteresis must be in [0, limit)");
  if (grain.grain_angles && static_cast<Eigen::Index>(grain.grain_angles->size()) != F.rows()) {
    throw UsageError("grain angles must be one per face");
  }
  check_clip_inputs(V_sim, F, area_factors);
  std::vector<Eigen::Matrix2d> targets(F.rows());
  ClipStats local;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix3d X_rest = face_positions(V_rest, F, f);
    Eigen::Matrix2d G;
    Eigen::Vector3d warp;
    try {
      G = deformation_gradient(X_rest, face_positions(V_sim, F, f));
      warp = cloth::warp_direction(X_rest, grain.material_direction,
                                   grain.grain_angles ? (*grain.grain_angles)[f] : 0.0);
    } catch (const GeometryError& e) {
      throw GeometryError(e.what(), "face " + std::to_string(f));
    }
    // The rest triangle's frame (mesh/principal_stretches.h): x along the
    // first edge, y in the plane towards x2; the warp's angle in it.
    const Eigen::Vector3d e1 = X_rest.col(1) - X_rest.col(0), e2 = X_rest.col(2) - X_rest.col(0);
    const Eigen::Vector3d x = e1.normalized();
    const Eigen::Vector3d y = e1.cross(e2).normalized().cross(x);
    const double phi = std::atan2(warp.dot(y), warp.dot(x));
    Eigen::Matrix2d R;
    R << std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi);
    const Eigen::Matrix2d Gm = G * R;
    local.max_stretch = std::max(local.max_stretch, Eigen::JacobiSVD<Eigen::Matrix2d>(G).singularValues()(0));
    local.max_warp_stretch = std::max(local.max_warp_stretch, Gm.col(0).norm());
    local.max_weft_stretch = std::max(local.max_weft_stretch, Gm.col(1).norm());
    const double s_limit = std::max(Gm.col(0).norm() / grain.limit_warp, Gm.col(1).norm() / grain.limit_weft);
    local.max_limit_stretch = std::max(local.max_limit_stretch, s_limit);
    if (s_limit > 1.0) ++local.clipped_faces;
    Eigen::Matrix2d T =
        clipped_target_grain(triangle_frame_edges(X_rest), G, R, grain.limit_warp, grain.limit_weft, hysteresis);
    if (area_factors) T *= std::sqrt((*area_factors)(f));
    targets[f] = T;
    local.target_area += 0.5 * T.determinant();
  }
  if (stats) *stats = local;
  return targets;
}

}  // namespace gp::adapt
