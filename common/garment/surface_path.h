#pragma once
// Tool T1, first half: clicked body vertices joined by shortest edge paths
// (mesh/graph_paths.h: Dijkstra over the mesh edges, Euclidean edge lengths)
// into a closed loop.
#include <string>
#include <vector>
#include <Eigen/Core>

#include "mesh/graph_paths.h"  // shortest_edge_path

namespace gp {

// Consecutive clicks (and the last to the first) joined into a closed path,
// listed once around; `where` names the clicks' spec field. Throws SpecError
// for fewer than three distinct clicks, GeometryError for clicks on different
// components or a path that passes a vertex twice.
std::vector<int> closed_edge_path(const Eigen::MatrixXd& V,
                                  const std::vector<std::vector<int>>& neighbors,
                                  const std::vector<int>& click_vertex_ids, const std::string& where);

}  // namespace gp
