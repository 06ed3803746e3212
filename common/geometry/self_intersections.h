#pragma once
// Self-intersection tests of a closed or open manifold triangle mesh with CGAL
// (Polygon_mesh_processing::self_intersections, box-intersection filtered,
// exact predicates). Triangles sharing a vertex or an edge count only when
// they overlap beyond that shared part.
//
// V is #V by 3, F is #F by 3. The mesh must be manifold and consistently
// oriented: GeometryError names the first face CGAL's face graph cannot hold.
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace gp {

struct SelfIntersectionResult {
  long long pair_count = 0;                     // intersecting triangle pairs
  std::vector<std::pair<int, int>> first_pairs;  // up to `max_pairs` of them, sorted
};

SelfIntersectionResult self_intersections(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                          int max_pairs = 20);

// Ids of all triangles that intersect another one (ascending, each once).
std::vector<int> self_intersecting_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// True if any two triangles intersect; stops at the first pair found.
bool has_self_intersection(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace gp
