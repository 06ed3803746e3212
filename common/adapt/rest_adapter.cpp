#include "adapt/rest_adapter.h"

#include <cmath>

#include <Eigen/Dense>

#include "core/error.h"
#include "mesh/measures.h"

namespace gp::adapt {

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
  const std::vector<Eigen::Matrix2d> targets =
      clipped_targets(V_rest, V_sim, F_, clip_delta, area_factors, &report.clip, options_.hysteresis);
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
      next = clipped_targets(V_rest, V_sim, F_, clip_delta, nullptr, &clip, options_.hysteresis);
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
