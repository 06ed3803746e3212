#include "pattern/mesh_cut.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <set>

#include "core/error.h"
#include "mesh/topology.h"

namespace gp {

CutMesh cut_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<CutPath>& paths) {
  const int n = static_cast<int>(V.rows());
  // Directed edge (a, b) -> face that traverses it.
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> e{F(f, k), F(f, (k + 1) % 3)};
      if (!directed.emplace(e, f).second)
        throw GeometryError("the mesh is not edge-manifold or not consistently oriented at edge (" +
                            std::to_string(e.first) + ", " + std::to_string(e.second) + ")",
                            "face " + std::to_string(f));
    }

  CutMesh out;
  std::set<std::pair<int, int>> cut;  // undirected, (min, max)
  for (const CutPath& p : paths) {
    const size_t m = p.vertex_ids.size();
    const size_t count = p.closed ? m : (m == 0 ? 0 : m - 1);
    double arc = 0.0;
    for (size_t k = 0; k < count; ++k) {
      const int a = p.vertex_ids[k], b = p.vertex_ids[(k + 1) % m];
      const double length = (V.row(a) - V.row(b)).norm();
      const auto left = directed.find({a, b}), right = directed.find({b, a});
      if (left == directed.end() && right == directed.end())
        throw GeometryError("cut path vertices " + std::to_string(a) + " and " + std::to_string(b) +
                            " share no edge");
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      if (left != directed.end() && right != directed.end() && cut.insert(key).second) {
        CutEdge e;
        e.seam = p.seam;
        e.a = a;
        e.b = b;
        e.left_face = left->second;
        e.right_face = right->second;
        e.length = length;
        e.arc_start = arc;
        out.edges.push_back(e);
      }
      arc += length;
    }
  }

  // Split every vertex into fans: faces around a vertex joined across its
  // uncut interior edges (union-find over the faces of its star).
  const auto star = vertex_faces(F, n);
  std::vector<int> face_corner_vertex(static_cast<size_t>(F.rows()) * 3, -1);
  std::vector<int> origin;
  std::vector<int> parent;
  auto find = [&](int x) {
    while (parent[static_cast<size_t>(x)] != x) x = parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
    return x;
  };
  for (int v = 0; v < n; ++v) {
    const auto& faces = star[static_cast<size_t>(v)];
    if (faces.empty()) continue;
    parent.resize(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    // Neighbour vertex w -> local indices of the faces containing edge (v, w).
    std::map<int, std::vector<int>> across;
    for (size_t i = 0; i < faces.size(); ++i) {
      const int f = faces[i];
      for (int k = 0; k < 3; ++k)
        if (F(f, k) != v) across[F(f, k)].push_back(static_cast<int>(i));
    }
    for (const auto& [w, fs] : across) {
      if (fs.size() != 2) continue;
      if (cut.count({std::min(v, w), std::max(v, w)})) continue;
      const int ra = find(fs[0]), rb = find(fs[1]);
      if (ra != rb) parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
    }
    // Fans in order of their smallest face (faces are ascending).
    std::map<int, int> fan_vertex;
    for (size_t i = 0; i < faces.size(); ++i) {
      const int r = find(static_cast<int>(i));
      auto it = fan_vertex.find(r);
      if (it == fan_vertex.end()) {
        it = fan_vertex.emplace(r, static_cast<int>(origin.size())).first;
        origin.push_back(v);
      }
      const int f = faces[i];
      for (int k = 0; k < 3; ++k)
        if (F(f, k) == v) face_corner_vertex[static_cast<size_t>(f) * 3 + static_cast<size_t>(k)] = it->second;
    }
  }
  out.F.resize(F.rows(), 3);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) out.F(f, k) = face_corner_vertex[static_cast<size_t>(f) * 3 + static_cast<size_t>(k)];
  out.origin = Eigen::Map<const Eigen::VectorXi>(origin.data(), static_cast<int>(origin.size()));
  out.V.resize(static_cast<int>(origin.size()), 3);
  for (size_t i = 0; i < origin.size(); ++i) out.V.row(static_cast<int>(i)) = V.row(origin[i]);

  auto corner = [&](int f, int v) {
    for (int k = 0; k < 3; ++k)
      if (F(f, k) == v) return out.F(f, k);
    return -1;
  };
  for (CutEdge& e : out.edges) {
    e.left_a = corner(e.left_face, e.a);
    e.left_b = corner(e.left_face, e.b);
    e.right_a = corner(e.right_face, e.a);
    e.right_b = corner(e.right_face, e.b);
  }
  return out;
}

}  // namespace gp
