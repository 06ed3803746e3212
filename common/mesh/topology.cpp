#include "mesh/topology.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

namespace gp {
namespace {

using EdgeKey = std::pair<int, int>;

struct EdgeKeyHash {
  size_t operator()(const EdgeKey& e) const {
    return std::hash<long long>()((static_cast<long long>(e.first) << 32) ^ static_cast<unsigned>(e.second));
  }
};

}  // namespace

Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F) {
  std::vector<EdgeKey> edges;
  edges.reserve(static_cast<size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) edges.push_back(std::minmax(F(f, k), F(f, (k + 1) % 3)));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Eigen::MatrixXi E(static_cast<Eigen::Index>(edges.size()), 2);
  for (size_t e = 0; e < edges.size(); ++e) E.row(static_cast<Eigen::Index>(e)) << edges[e].first, edges[e].second;
  return E;
}

Eigen::MatrixXi triangle_adjacency(const Eigen::MatrixXi& F) {
  // Undirected edge -> the (face, corner) pairs that use it.
  std::unordered_map<EdgeKey, std::vector<std::pair<int, int>>, EdgeKeyHash> uses;
  uses.reserve(static_cast<size_t>(F.rows()) * 2);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) uses[std::minmax(F(f, k), F(f, (k + 1) % 3))].push_back({f, k});
  Eigen::MatrixXi TT = Eigen::MatrixXi::Constant(F.rows(), 3, -1);
  for (const auto& [edge, list] : uses) {
    if (list.size() != 2) continue;
    TT(list[0].first, list[0].second) = list[1].first;
    TT(list[1].first, list[1].second) = list[0].first;
  }
  return TT;
}

std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F) {
  std::map<EdgeKey, int> count;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++count[std::minmax(F(f, k), F(f, (k + 1) % 3))];
  // Directed boundary edges a -> b in face order; a vertex may start several
  // (a pinched boundary), so keep them all and consume them in id order.
  std::map<int, std::vector<int>> next;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (count[std::minmax(a, b)] == 1) next[a].push_back(b);
    }
  for (auto& [a, list] : next) std::sort(list.begin(), list.end());
  std::vector<std::vector<int>> loops;
  while (!next.empty()) {
    const int start = next.begin()->first;
    std::vector<int> loop;
    int v = start;
    while (true) {
      auto it = next.find(v);
      if (it == next.end()) break;  // open chain (only for non-manifold input)
      loop.push_back(v);
      const int w = it->second.front();
      it->second.erase(it->second.begin());
      if (it->second.empty()) next.erase(it);
      v = w;
      if (v == start) break;
    }
    if (!loop.empty()) loops.push_back(loop);
  }
  return loops;
}

int face_components(const Eigen::MatrixXi& F, Eigen::VectorXi& component) {
  const int nf = static_cast<int>(F.rows());
  // Union-find over faces joined through shared undirected edges.
  std::vector<int> parent(nf);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::unordered_map<EdgeKey, int, EdgeKeyHash> first_face;
  first_face.reserve(static_cast<size_t>(nf) * 2);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto key = std::minmax(F(f, k), F(f, (k + 1) % 3));
      auto [it, inserted] = first_face.emplace(key, f);
      if (!inserted) {
        const int a = find(it->second), b = find(f);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
  component.resize(nf);
  std::unordered_map<int, int> id_of_root;
  int count = 0;
  for (int f = 0; f < nf; ++f) {
    const int r = find(f);
    auto [it, inserted] = id_of_root.emplace(r, count);
    if (inserted) ++count;
    component(f) = it->second;
  }
  return count;
}

std::vector<std::vector<int>> vertex_faces(const Eigen::MatrixXi& F, int n_vertices) {
  std::vector<std::vector<int>> vf(static_cast<size_t>(n_vertices));
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) vf[F(f, k)].push_back(f);
  for (auto& list : vf) list.erase(std::unique(list.begin(), list.end()), list.end());
  return vf;
}

std::vector<std::vector<int>> vertex_neighbors(const Eigen::MatrixXi& F, int n_vertices) {
  std::vector<std::vector<int>> nb(static_cast<size_t>(n_vertices));
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      nb[F(f, k)].push_back(F(f, (k + 1) % 3));
      nb[F(f, k)].push_back(F(f, (k + 2) % 3));
    }
  for (auto& list : nb) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return nb;
}

int euler_characteristic(const Eigen::MatrixXi& F) {
  std::vector<int> used(F.data(), F.data() + F.size());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  return static_cast<int>(used.size()) - static_cast<int>(unique_edges(F).rows()) +
         static_cast<int>(F.rows());
}

}  // namespace gp
