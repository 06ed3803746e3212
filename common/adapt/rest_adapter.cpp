#include "adapt/rest_adapter.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/error.h"
#include "mesh/measures.h"

namespace gp::adapt {

AdaptOptions with_fabric_limits(AdaptOptions options, const Material& material) {
  if (material.has_own_limits()) {
    options.limit_warp = material.stretch_limit_warp;
    options.limit_weft = material.stretch_limit_weft;
  }
  // The fabric's lay per face (a bias-cut region), as the cloth model takes it.
  if (material.turned_grain()) options.grain_angles = material.grain_angles;
  return options;
}

RestShapeAdapter::RestShapeAdapter(const Eigen::MatrixXd& V_reference, const Eigen::MatrixXi& F,
                                   AdaptOptions options)
    : F_(F), options_(options), stitcher_(V_reference, F, options.smoothing_length), reference_areas_(F.rows()) {
  if (!(options.delta >= 0.0)) throw UsageError("stretch limit delta must be non-negative");
  if (!(options.margin >= 0.0 && options.hysteresis >= 0.0 && options.margin + options.hysteresis <= options.delta)) {
    throw UsageError("the adaptation's margin and hysteresis must be non-negative with a sum of at most delta");
  }
  if (!(options.arap.tolerance > 0.0) || !(options.arap.stretch_tolerance >= 0.0) ||
      options.arap.max_iterations < 1) {
    throw UsageError("ARAP tolerances must be positive (the stretch rule's non-negative) and the iteration cap at least 1");
  }
  if (!(options.smoothing_length >= 0.0) || options.rounds < 1) {
    throw UsageError("the smoothing length must be non-negative and the rounds at least 1");
  }
  if (!(options.max_face_growth > 1.0)) throw UsageError("the face growth cap must be above 1");
  if (options.limit_warp != 0.0 || options.limit_weft != 0.0) {
    const double least = std::min(options.limit_warp, options.limit_weft) - 1.0;
    if (!(least >= 0.0) || !(options.margin + options.hysteresis <= least)) {
      throw UsageError("the fabric's stretch limits must both be at least 1 plus the adaptation's margin and hysteresis");
    }
    if (!options.grain_angles.empty() && static_cast<Eigen::Index>(options.grain_angles.size()) != F.rows()) {
      throw UsageError("grain angles must be one per face");
    }
  }
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V_reference.row(F(f, 0)), b = V_reference.row(F(f, 1)), c = V_reference.row(F(f, 2));
    reference_areas_(f) = 0.5 * (b - a).cross(c - a).norm();
  }
}

AdaptReport RestShapeAdapter::adapt(const Eigen::MatrixXd& V_sim, Eigen::MatrixXd& V_rest,
                                    const Eigen::VectorXd* area_factors) const {
  AdaptReport report;
  report.area_before = mesh_area(V_rest, F_);
  const double clip_delta = options_.delta - options_.margin;  // the adaptation's own limit
  // With a fabric's own limits, each material direction against its own.
  const bool by_grain = options_.limit_warp > 0.0;
  GrainClip grain;
  grain.limit_warp = options_.limit_warp - options_.margin;
  grain.limit_weft = options_.limit_weft - options_.margin;
  grain.material_direction = options_.material_direction;
  grain.grain_angles = options_.grain_angles.empty() ? nullptr : &options_.grain_angles;
  auto clip_all = [&](const Eigen::VectorXd* factors, ClipStats* stats) {
    return by_grain ? clipped_targets(V_rest, V_sim, F_, grain, factors, stats, options_.hysteresis)
                    : clipped_targets(V_rest, V_sim, F_, clip_delta, factors, stats, options_.hysteresis);
  };
  const std::vector<Eigen::Matrix2d> targets = clip_all(area_factors, &report.clip);
  if (report.clip.clipped_faces == 0 && area_factors == nullptr) {
    report.area_after = report.area_before;
    return report;
  }
  std::vector<Eigen::Matrix2d> next = targets;
  // Targets held within max_face_growth of the design's area (a uniform
  // scale keeps their shape).
  auto cap = [&](std::vector<Eigen::Matrix2d>& T) {
    report.capped_faces = 0;
    for (int f = 0; f < F_.rows(); ++f) {
      const double area = 0.5 * std::abs(T[static_cast<size_t>(f)].determinant());
      const double bound = options_.max_face_growth * reference_areas_(f);
      if (area > bound) {
        T[static_cast<size_t>(f)] *= std::sqrt(bound / area);
        ++report.capped_faces;
      }
    }
  };
  for (int round = 0; round < options_.rounds; ++round) {
    if (round > 0) {
      ClipStats clip;
      next = clip_all(nullptr, &clip);
      if (clip.clipped_faces == 0) break;
    }
    cap(next);
    Eigen::MatrixXd V = V_rest;
    const ArapReport r = stitcher_.stitch(next, V, options_.arap);
    if (!V.allFinite()) throw NumericalError("ARAP stitching produced non-finite positions");
    V_rest = V;
    report.arap.iterations += r.iterations;
    report.arap.residual = std::max(report.arap.residual, r.residual);
    report.arap.misfit = r.misfit;
    report.arap.converged = (round == 0 || report.arap.converged) && r.converged;
    ++report.rounds;
  }
  report.changed = true;
  report.area_after = mesh_area(V_rest, F_);
  return report;
}

}  // namespace gp::adapt
