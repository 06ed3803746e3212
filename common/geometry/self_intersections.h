#pragma once
// Self-intersection test of a closed or open manifold triangle mesh with CGAL
// (Polygon_mesh_processing::self_intersections, box-intersection filtered,
// exact predicates). Triangles sharing a vertex or an edge count only when
// they overlap beyond that shared part.
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace gp {

struct SelfIntersectionResult {
  long long pair_count = 0;                     // intersecting triangle pairs
  std::vector<std::pair<int, int>> first_pairs;  // up to `max_pairs` of them, sorted
};

// V #V by 3, F #F by 3; the mesh must be manifold and consistently oriented
// (GeometryError otherwise, since CGAL's face graph cannot hold it).
SelfIntersectionResult self_intersections(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                          int max_pairs = 20);

}  // namespace gp
