#include "garment/surface_path.h"

#include <algorithm>

#include "core/error.h"

namespace gp {

std::vector<int> closed_edge_path(const Eigen::MatrixXd& V,
                                  const std::vector<std::vector<int>>& neighbors,
                                  const std::vector<int>& click_vertex_ids, const std::string& where) {
  // Repeated consecutive clicks (a double click) add nothing to the loop.
  std::vector<int> clicks;
  std::vector<size_t> click_index;
  for (size_t i = 0; i < click_vertex_ids.size(); ++i) {
    if (!clicks.empty() && clicks.back() == click_vertex_ids[i]) continue;
    clicks.push_back(click_vertex_ids[i]);
    click_index.push_back(i);
  }
  while (clicks.size() > 1 && clicks.back() == clicks.front()) {
    clicks.pop_back();
    click_index.pop_back();
  }
  if (clicks.size() < 3)
    throw SpecError("the loop does not close: it needs at least three distinct points, found " +
                        std::to_string(clicks.size()),
                    where);
  std::vector<int> path;
  for (size_t i = 0; i < clicks.size(); ++i) {
    const size_t j = (i + 1) % clicks.size();
    const std::vector<int> piece = shortest_edge_path(V, neighbors, clicks[i], clicks[j]);
    if (piece.empty())
      throw GeometryError("points " + std::to_string(click_index[i]) + " and " +
                              std::to_string(click_index[j]) +
                              " lie on different connected components of the body",
                          where);
    path.insert(path.end(), piece.begin(), piece.end() - 1);
  }
  std::vector<int> sorted = path;
  std::sort(sorted.begin(), sorted.end());
  const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
  if (dup != sorted.end())
    throw GeometryError("the loop crosses or touches itself at body vertex " + std::to_string(*dup) +
                            " (the edge paths between its points meet; add or move points)",
                        where);
  return path;
}

}  // namespace gp
