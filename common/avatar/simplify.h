#pragma once
// Decimation of a closed, oriented triangle mesh to a vertex budget by quadric-error edge collapse
// (Garland and Heckbert, "Surface simplification using quadric error metrics", SIGGRAPH 1997), plus
// an edge-length term that keeps triangles well shaped. A collapse is refused when it would break
// the link condition (the end points share exactly the two opposite vertices) or turn a triangle
// by more than `max_normal_turn`. Ties go by vertex ids.
#include <Eigen/Core>

#include "io/mesh.h"

namespace gp {

struct SimplifyOptions {
  // Weight of the squared edge length against the quadric error (both m^4 after area weighting).
  double length_weight = 1.0;
  // [deg] largest turn of a triangle's normal by one collapse; later passes that still miss the
  // budget allow 1.5 and then 2.5 times as much.
  double max_normal_turn = 30.0;
};

// Returns the mesh with at most `target_vertices` vertices (fewer only if no
// valid collapse is left). Surviving vertices keep their relative order.
Mesh simplify_mesh(const Mesh& mesh, int target_vertices, const SimplifyOptions& options = {});

}  // namespace gp
