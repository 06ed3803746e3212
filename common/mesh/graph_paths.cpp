#include "mesh/graph_paths.h"

#include <algorithm>
#include <cmath>

namespace gp {

std::vector<int> trace_parents(const std::vector<int>& parent, int to) {
  std::vector<int> path;
  for (int v = to; v != -1; v = parent[static_cast<size_t>(v)]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

void edge_distances(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
                    const std::vector<int>& sources, double limit, std::vector<double>& dist,
                    std::vector<int>& reached) {
  GraphSearch<double> search;
  search.dist.swap(dist);
  search.settled.swap(reached);
  dijkstra(
      neighbors, sources, [&](int v, int w) { return (V.row(v) - V.row(w)).norm(); }, limit,
      [](int) { return false; }, search);
  dist.swap(search.dist);
  reached.swap(search.settled);
}

std::vector<int> shortest_edge_path(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
                                    int from, int to) {
  // Whole nanometres: sums are exact, so that rounding of V changes no path.
  constexpr double kUnitsPerMetre = 1e9;
  constexpr long long kNoEdge = std::numeric_limits<long long>::max();
  GraphSearch<long long> search = graph_search(neighbors.size(), kNoEdge, true);
  dijkstra(
      neighbors, {from},
      [&](int v, int w) {
        const double length = (V.row(v) - V.row(w)).norm();
        return std::isfinite(length) ? std::llround(length * kUnitsPerMetre) : kNoEdge;
      },
      kNoEdge, [&](int v) { return v == to; }, search, /*ties_to_lower_parent=*/true);
  if (from != to && search.parent[static_cast<size_t>(to)] < 0) return {};
  return trace_parents(search.parent, to);
}

}  // namespace gp
