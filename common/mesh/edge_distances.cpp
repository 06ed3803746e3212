#include "mesh/edge_distances.h"

#include <functional>
#include <queue>
#include <utility>

namespace gp {

void edge_distances(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
                    const std::vector<int>& sources, double limit, std::vector<double>& dist,
                    std::vector<int>& reached) {
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  reached.clear();
  for (int s : sources) {
    dist[static_cast<size_t>(s)] = 0.0;
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[static_cast<size_t>(v)]) continue;
    reached.push_back(v);
    for (int w : neighbors[static_cast<size_t>(v)]) {
      const double nd = d + (V.row(v) - V.row(w)).norm();
      if (nd <= limit && nd < dist[static_cast<size_t>(w)]) {
        dist[static_cast<size_t>(w)] = nd;
        queue.push({nd, w});
      }
    }
  }
}

}  // namespace gp
