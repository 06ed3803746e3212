#pragma once
// Tool T4: the comfort offset. The initial garment is pushed off the body so
// that every vertex lies at the requested distance from the body surface.
#include <memory>
#include <vector>
#include <Eigen/Core>

#include "garment/surface_point.h"

namespace gp {
namespace collision {
class BodyCollider;
}

struct ComfortOffsetOptions {
  double offset = 0.0;        // metres, >= 0
  int max_iterations = 20;    // closest-point corrections per vertex
  double tolerance = 1e-6;    // metres; stop when | |x - c| - offset | is below
  // Start from the closest body point pushed along the normal field (true), or
  // from the current position, for vertices already near the offset surface.
  bool start_along_normal = true;
  // In a slot narrower than twice the offset, go to the crease where the
  // offsets of both walls meet (true), or keep swinging between the walls
  // until max_iterations (false: such vertices end closer than the offset).
  bool solve_creases = false;
};

struct ComfortOffsetStats {
  double max_error = 0.0;   // max over vertices of | distance to body - offset |, metres
  double mean_error = 0.0;  // metres
  double max_below = 0.0;   // max over vertices of offset - distance to body (0 if none is closer), metres
  double max_above = 0.0;   // max over vertices of distance to body - offset (0 if none is farther), metres
};

// Moves each vertex of V (#V by 3, near the body) to distance `offset`: along
// the body's normal field N_body (#Vb by 3) first, then by closest-point
// corrections x <- c + offset s (x - c) / |x - c| (s = -1 inside the body by
// pseudo-normals, +1 outside), which converge to the exact distance even where
// the normal offset runs into another body part. fixed[v] != 0: left alone
// but measured. Returns the distance errors.
ComfortOffsetStats apply_comfort_offset(Eigen::MatrixXd& V, const SurfaceLocator& body,
                                        const Eigen::MatrixXd& N_body,
                                        const ComfortOffsetOptions& options,
                                        const std::vector<char>& fixed = {});

// Distance errors | distance to body - offset | of every vertex of V.
ComfortOffsetStats measure_offset(const Eigen::MatrixXd& V, const SurfaceLocator& body, double offset);

// The comfort-offset surface with its creases rounded: the boundary of the
// morphological closing, by a ball of radius R (`fillet_radius`), of the
// region within `offset` of the body (Serra 1982, ch. 2). In a pinch narrower
// than twice the offset (an A-pose armpit) the exact surface {d = offset} has
// a crease that a projected mesh folds into. The closed surface is at
// distance R, on the body's side, from {d = offset + R}: exact where the
// body's concave radius exceeds offset + R, a fillet of radius R across
// narrower creases, never closer than `offset`. {d = offset + R} is sampled
// by the body mesh moved out (apply_comfort_offset with solve_creases),
// leaving out vertices that do not reach it and faces through the pinch; an
// exact closest-point correction holds the offset where its chords dip.
class OffsetSurface {
 public:
  // body and N_body (#Vb by 3 vertex normals) must outlive this object.
  // offset, fillet_radius >= 0 (m; radius 0: the exact surface). near (#Vb or
  // empty for all): the body vertices whose outer points are needed.
  OffsetSurface(const SurfaceLocator& body, const Eigen::MatrixXd& N_body, double offset,
                double fillet_radius, const ComfortOffsetOptions& correction = {},
                const std::vector<char>& near = {});
  ~OffsetSurface();
  OffsetSurface(const OffsetSurface&) = delete;
  OffsetSurface& operator=(const OffsetSurface&) = delete;

  // The surface point for x: from the nearest outer-surface point for x
  // between the outer surface and the body, else from the closest body
  // point; continuous across a pinch. Without fillet: one closest-point step.
  Eigen::Vector3d project(const Eigen::Vector3d& x) const;

  double offset() const { return offset_; }
  double fillet_radius() const { return fillet_radius_; }

 private:
  // x moved to the exact distance offset_ (the correction of apply_comfort_offset).
  Eigen::Vector3d to_exact_offset(const Eigen::Vector3d& x) const;

  const SurfaceLocator& body_;
  const Eigen::MatrixXd& N_body_;
  double offset_ = 0.0;
  double fillet_radius_ = 0.0;
  ComfortOffsetOptions correction_;
  std::unique_ptr<collision::BodyCollider> sided_;
  std::unique_ptr<SurfaceLocator> outer_;  // the body at distance offset + R
};

}  // namespace gp
