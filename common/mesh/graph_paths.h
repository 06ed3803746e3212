#pragma once
// Shortest paths along mesh edges: one Dijkstra (multi-source, with parents,
// a distance limit and a stop rule) for the whole house, and what is built on
// it: edge distances (the geodesic disc of a paint region, how far a push
// spreads over a garment), shortest edge paths between two vertices (the
// clicked loops of tool T1, seams on the rest shape) and path tracing (the
// pattern's topology cuts).
#include <functional>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace gp {

// What a search fills in. `dist` (#V) must hold `unreached` for every vertex
// before the search (the caller's choice, so that a search over a few
// vertices of a large mesh can reset only those it reached); `parent` (#V,
// -1) is filled when not empty; `settled` lists every vertex once in the
// order settled (nearest first).
template <class Length>
struct GraphSearch {
  std::vector<Length> dist;
  std::vector<int> parent;
  std::vector<int> settled;
};

// Dijkstra over `neighbors` (one ring per vertex) from the `sources` (0
// there), edge lengths from `cost(v, w)` (Length; a non-finite double, or
// for an integer Length its largest value, is no edge), keeping only
// distances <= `limit`. Stops once `stop(v)` holds for a settled vertex v
// (after listing it). Ties between queue entries go to the lower vertex id
// through the (distance, id) order of the queue; with
// `ties_to_lower_parent`, an equal distance through a lower predecessor id
// also takes over the parent, so that mirror-symmetric paths tie exactly.
template <class Length, class Cost, class Stop>
void dijkstra(const std::vector<std::vector<int>>& neighbors, const std::vector<int>& sources, Cost&& cost,
              Length limit, Stop&& stop, GraphSearch<Length>& search, bool ties_to_lower_parent = false) {
  using Entry = std::pair<Length, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  std::vector<Length>& dist = search.dist;
  std::vector<int>& parent = search.parent;
  const bool parents = !parent.empty();
  search.settled.clear();
  for (int s : sources) {
    dist[static_cast<size_t>(s)] = Length(0);
    queue.push({Length(0), s});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[static_cast<size_t>(v)]) continue;
    search.settled.push_back(v);
    if (stop(v)) return;
    for (int w : neighbors[static_cast<size_t>(v)]) {
      const Length c = cost(v, w);
      if constexpr (std::numeric_limits<Length>::has_infinity) {
        if (!(c < std::numeric_limits<Length>::infinity())) continue;
      } else {
        if (c == std::numeric_limits<Length>::max()) continue;
      }
      const Length nd = d + c;
      if (!(nd <= limit)) continue;
      const size_t wi = static_cast<size_t>(w);
      const bool shorter = nd < dist[wi];
      if (shorter || (ties_to_lower_parent && parents && nd == dist[wi] && v < parent[wi])) {
        dist[wi] = nd;
        if (parents) parent[wi] = v;
        queue.push({nd, w});
      }
    }
  }
}

// A fresh search over n vertices: every distance `unreached`, parents -1
// when `with_parents`.
template <class Length>
GraphSearch<Length> graph_search(size_t n, Length unreached, bool with_parents) {
  GraphSearch<Length> s;
  s.dist.assign(n, unreached);
  if (with_parents) s.parent.assign(n, -1);
  return s;
}

// The path from a source to `to` (both included) through `parent`.
std::vector<int> trace_parents(const std::vector<int>& parent, int to);

// Distances from the `sources` (0 there) along the edges of a mesh with
// positions V (#V by 3) and one-ring neighbours `neighbors`
// (vertex_neighbors), up to `limit` [m]: every vertex reached gets its
// distance in `dist` (#V, filled with infinity by the caller, who may reset
// it through `reached` afterwards) and is listed once in `reached`, in the
// order settled (nearest first).
void edge_distances(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
                    const std::vector<int>& sources, double limit, std::vector<double>& dist,
                    std::vector<int>& reached);

// Shortest edge path from `from` to `to` (both included) over `neighbors`
// (one ring per vertex) with V's (#V by 3) edge lengths. Lengths sum as whole
// nanometres and ties go to the lower vertex id, so mirror-symmetric paths
// tie exactly and rounding of V changes no path. Empty when unreachable.
std::vector<int> shortest_edge_path(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
                                    int from, int to);

}  // namespace gp
