#pragma once
// Tool T1, first half: clicked body vertices joined by shortest edge paths
// (Dijkstra over the mesh edges, Euclidean edge lengths) into a closed loop.
#include <string>
#include <vector>
#include <Eigen/Core>

namespace gp {

// Shortest edge path from vertex `from` to vertex `to`, both included, over the
// graph `neighbors` (one ring per vertex, e.g. gp::vertex_neighbors) with edge
// lengths taken from V (#V by 3). Lengths are summed as whole nanometres, so
// that paths of equal length (a mirror-symmetric body) tie exactly instead of
// by their last bits, and ties are broken by vertex id: the path does not
// change when V changes by rounding. Empty when `to` cannot be reached.
std::vector<int> shortest_edge_path(const Eigen::MatrixXd& V,
                                    const std::vector<std::vector<int>>& neighbors, int from,
                                    int to);

// Joins consecutive clicks (and the last to the first) by shortest edge paths
// into a closed vertex path, listed once around (the first vertex is not
// repeated at the end). `where` names the spec field of the clicks
// ("shirt.json: /loops/0/points"); errors name the click by index.
// Throws SpecError for fewer than three distinct clicks (the loop cannot
// close), GeometryError when two clicks lie on different connected components
// or when the joined path passes a vertex twice (the loop crosses itself).
std::vector<int> closed_edge_path(const Eigen::MatrixXd& V,
                                  const std::vector<std::vector<int>>& neighbors,
                                  const std::vector<int>& click_vertex_ids, const std::string& where);

}  // namespace gp
