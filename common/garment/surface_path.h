#pragma once
// Tool T1, first half: clicked body vertices joined by shortest edge paths
// (Dijkstra over the mesh edges, Euclidean edge lengths) into a closed loop.
#include <string>
#include <vector>
#include <Eigen/Core>

namespace gp {

// Shortest edge path from `from` to `to` (both included) over `neighbors`
// (one ring per vertex) with V's (#V by 3) edge lengths. Lengths sum as whole
// nanometres and ties go to the lower vertex id, so mirror-symmetric paths
// tie exactly and rounding of V changes no path. Empty when unreachable.
std::vector<int> shortest_edge_path(const Eigen::MatrixXd& V,
                                    const std::vector<std::vector<int>>& neighbors, int from,
                                    int to);

// Consecutive clicks (and the last to the first) joined into a closed path,
// listed once around; `where` names the clicks' spec field. Throws SpecError
// for fewer than three distinct clicks, GeometryError for clicks on different
// components or a path that passes a vertex twice.
std::vector<int> closed_edge_path(const Eigen::MatrixXd& V,
                                  const std::vector<std::vector<int>>& neighbors,
                                  const std::vector<int>& click_vertex_ids, const std::string& where);

}  // namespace gp
