#pragma once
// Tool T4: the comfort offset. The initial garment is pushed off the body so
// that every vertex lies at the requested distance from the body surface.
#include <vector>
#include <Eigen/Core>

#include "garment/surface_point.h"

namespace gp {

struct ComfortOffsetOptions {
  double offset = 0.0;        // metres, >= 0
  int max_iterations = 20;    // closest-point corrections per vertex
  double tolerance = 1e-6;    // metres; stop when | |x - c| - offset | is below
  // Start from the closest body point pushed along the normal field (true), or
  // from the current position, for vertices already near the offset surface.
  bool start_along_normal = true;
};

struct ComfortOffsetStats {
  double max_error = 0.0;   // max over vertices of | distance to body - offset |, metres
  double mean_error = 0.0;  // metres
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

}  // namespace gp
