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

// Moves each vertex of V (#V by 3, on or near the body) to distance `offset`
// from the body: first along the body's normal field N_body (#Vb by 3,
// per-vertex normals, interpolated at the closest body point), then by
// closest-point corrections x <- c + offset * s (x - c) / |x - c| with c the
// closest body point (CGAL AABB tree in `body`) and s = -1 for a point inside
// the body (signed by pseudo-normals, collision/body_collider.h), +1 outside,
// which converge to the exact distance outside the body even in concave
// places where the normal offset comes too close to, or into, another body
// part. Vertices with fixed[v] != 0 are left alone (their distance is still
// measured). Returns the distance errors.
ComfortOffsetStats apply_comfort_offset(Eigen::MatrixXd& V, const SurfaceLocator& body,
                                        const Eigen::MatrixXd& N_body,
                                        const ComfortOffsetOptions& options,
                                        const std::vector<char>& fixed = {});

// Distance errors | distance to body - offset | of every vertex of V.
ComfortOffsetStats measure_offset(const Eigen::MatrixXd& V, const SurfaceLocator& body, double offset);

// The comfort-offset surface with its creases rounded off: the boundary of
// the morphological closing, by a ball of radius R (`fillet_radius`), of the
// region within `offset` of the body (Serra, "Image Analysis and Mathematical
// Morphology", 1982, ch. 2). Where two body parts come closer than twice the
// offset (the armpit of an A-pose), the exact-distance surface {d = offset}
// has a sharp crease and the body inside the pinch has no image on it, so a
// mesh projected onto it folds and its triangles collapse onto the crease.
// The closed surface is the set of points at distance R, on the body's side,
// from the surface {d = offset + R}: the exact offset surface wherever the
// body's concave radius of curvature exceeds offset + R, a round fillet of
// radius R across narrower creases, and never closer than `offset` to the
// body. The surface {d = offset + R} is sampled by the body mesh with its
// vertices moved to that distance (apply_comfort_offset with solve_creases);
// vertices that do not reach it and faces that cut through the pinch are left
// out. Where the sampled surface dips below the offset (chords on convex
// parts, about (edge length)^2 / (8 radius)) the exact closest-point
// correction holds the offset.
class OffsetSurface {
 public:
  // body: the body's locator, N_body its per-vertex normals (#Vb by 3); both
  // must outlive this object. offset >= 0 and fillet_radius >= 0 in metres;
  // fillet_radius 0 gives the exact offset surface. near (#Vb or empty): the
  // body vertices whose offset + R points are needed, those within about
  // 3 (offset + R) of where the surface is used (empty: all; building them
  // costs a few closest-point queries each).
  OffsetSurface(const SurfaceLocator& body, const Eigen::MatrixXd& N_body, double offset,
                double fillet_radius, const ComfortOffsetOptions& correction = {},
                const std::vector<char>& near = {});
  ~OffsetSurface();
  OffsetSurface(const OffsetSurface&) = delete;
  OffsetSurface& operator=(const OffsetSurface&) = delete;

  // The point of the surface for x: through x from the nearest point of the
  // outer surface {d = offset + R} for x between it and the body; from the
  // closest body point for x inside the body or beyond the outer surface.
  // A body point x goes to the surface point over it, continuously across a
  // pinch (torso and arm sides of an armpit stay apart, in order). Without
  // fillet: one closest-point step onto the exact surface (apply_comfort_offset
  // iterates it).
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
