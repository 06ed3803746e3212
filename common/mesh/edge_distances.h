#pragma once
// Shortest distances along mesh edges (Dijkstra over the one-ring graph): the geodesic disc of a
// paint region, the body part around a point, how far a push spreads over a garment.
#include <vector>

#include <Eigen/Core>

namespace gp {

// Distances from the `sources` (0 there) along the edges of a mesh with positions V (#V by 3) and
// one-ring neighbours `neighbors` (vertex_neighbors), up to `limit` [m]: every vertex reached gets
// its distance in `dist` (#V, filled with infinity by the caller, who may reset it through
// `reached` afterwards) and is listed once in `reached`, in the order settled (nearest first).
void edge_distances(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
                    const std::vector<int>& sources, double limit, std::vector<double>& dist,
                    std::vector<int>& reached);

}  // namespace gp
