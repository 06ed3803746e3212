#pragma once
// Decimation of a closed, oriented triangle mesh to a vertex budget by quadric-error edge collapse
// (Garland and Heckbert, "Surface simplification using quadric error metrics", SIGGRAPH 1997) plus
// an edge-length term for well-shaped triangles. A collapse keeps the link condition (the end points
// share exactly the two opposite vertices) and turns no normal past `max_normal_turn`; ties by ids.
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

// The mesh with at most `target_vertices` vertices (fewer only if no valid collapse is left);
// surviving vertices keep their relative order.
Mesh simplify_mesh(const Mesh& mesh, int target_vertices, const SimplifyOptions& options = {});

}  // namespace gp
