#include "registration/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <Eigen/Geometry>

#include "core/math.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {

template <class T>
void keep_example(std::vector<T>& list, const T& value, int max_examples) {
  if (static_cast<int>(list.size()) < max_examples) list.push_back(value);
}

// Number of edge-connected fans among the faces around vertex v: 1 for a
// manifold vertex (interior or on the boundary).
int fan_count(int v, const std::vector<int>& faces, const Eigen::MatrixXi& F) {
  if (faces.empty()) return 0;
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  // Faces around v sharing another vertex share an edge through v. The
  // one-ring is small, so a linear scan beats any map.
  std::vector<std::pair<int, int>> first_with;  // (other vertex, first face slot)
  first_with.reserve(faces.size() * 2);
  for (size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int w = F(faces[i], k);
      if (w == v) continue;
      auto it = std::find_if(first_with.begin(), first_with.end(),
                             [w](const std::pair<int, int>& p) { return p.first == w; });
      if (it == first_with.end()) first_with.push_back({w, static_cast<int>(i)});
      else parent[find(static_cast<int>(i))] = find(it->second);
    }
  int fans = 0;
  for (size_t i = 0; i < faces.size(); ++i) fans += (find(static_cast<int>(i)) == static_cast<int>(i));
  return fans;
}

}  // namespace

MeshCheckResult check_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                           const MeshCheckOptions& options) {
  MeshCheckResult r;
  const int nv = static_cast<int>(V.rows());
  r.vertex_count = nv;
  r.face_count = F.rows();
  const int max_ex = options.max_examples;

  std::vector<bool> finite(static_cast<size_t>(nv), true);
  for (int i = 0; i < nv; ++i)
    if (!V.row(i).allFinite()) {
      finite[i] = false;
      ++r.nonfinite_vertices;
      keep_example(r.nonfinite_vertex_ids, i, max_ex);
    }

  // Bounding box of the finite vertices only.
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(INFINITY), hi = -lo;
  for (int i = 0; i < nv; ++i)
    if (finite[i]) {
      lo = lo.cwiseMin(V.row(i));
      hi = hi.cwiseMax(V.row(i));
    }
  r.bounding_box_diagonal = (nv > 0 && lo.allFinite()) ? (hi - lo).norm() : 0.0;

  // Edge use: every face edge as (min, max, runs min->max), sorted so that the
  // uses of one undirected edge are adjacent.
  struct EdgeUse {
    int a, b;
    bool forward;
    bool operator<(const EdgeUse& o) const { return a != o.a ? a < o.a : b < o.b; }
  };
  std::vector<EdgeUse> uses;
  uses.reserve(static_cast<size_t>(F.rows()) * 3);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      uses.push_back({std::min(a, b), std::max(a, b), a < b});
    }
  std::sort(uses.begin(), uses.end());
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    int forward = 0;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) forward += uses[j++].forward;
    const size_t count = j - i;
    const std::pair<int, int> e(uses[i].a, uses[i].b);
    if (count > 2) {
      ++r.nonmanifold_edges;
      keep_example(r.nonmanifold_edge_examples, e, max_ex);
    } else if (count == 2 && forward != 1) {
      ++r.inconsistent_orientation_edges;
      keep_example(r.inconsistent_edge_examples, e, max_ex);
    }
    i = j;
  }

  const auto vf = vertex_faces(F, nv);
  for (int v = 0; v < nv; ++v) {
    if (vf[v].empty()) {
      ++r.unreferenced_vertices;
      keep_example(r.unreferenced_vertex_ids, v, max_ex);
    } else if (fan_count(v, vf[v], F) > 1) {
      ++r.nonmanifold_vertices;
      keep_example(r.nonmanifold_vertex_ids, v, max_ex);
    }
  }

  if (r.nonmanifold_edges == 0) {
    for (const auto& loop : boundary_loops(F)) {
      r.boundary_loop_sizes.push_back(static_cast<int>(loop.size()));
      r.boundary_loop_first_vertex.push_back(loop.front());
    }
  }
  Eigen::VectorXi component;
  r.components = face_components(F, component);

  // Triangle shape. Faces touching a non-finite vertex are left to that finding.
  const double area_floor = options.degenerate_area_fraction * r.bounding_box_diagonal *
                            r.bounding_box_diagonal;
  const double needle_cos = gp::math::cos(options.needle_angle_degrees * M_PI / 180.0);
  for (int f = 0; f < F.rows(); ++f) {
    if (!finite[F(f, 0)] || !finite[F(f, 1)] || !finite[F(f, 2)]) continue;
    const Eigen::Vector3d p[3] = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    r.area += area;
    if (area <= area_floor) {
      ++r.degenerate_faces;
      keep_example(r.degenerate_face_ids, f, max_ex);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d u = (p[(k + 1) % 3] - p[k]).normalized();
      const Eigen::Vector3d w = (p[(k + 2) % 3] - p[k]).normalized();
      if (u.dot(w) > needle_cos) {
        ++r.needle_faces;
        keep_example(r.needle_face_ids, f, max_ex);
        break;
      }
    }
  }

  // Duplicates: sort finite vertices lexicographically and compare neighbours
  // within the tolerance (exact duplicates always end up adjacent).
  const double tol = options.duplicate_distance_fraction * r.bounding_box_diagonal;
  std::vector<int> order;
  for (int i = 0; i < nv; ++i)
    if (finite[i]) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (V(a, k) != V(b, k)) return V(a, k) < V(b, k);
    return a < b;
  });
  for (size_t i = 1; i < order.size(); ++i) {
    const int a = order[i - 1], b = order[i];
    if ((V.row(a) - V.row(b)).norm() <= tol) {
      ++r.duplicate_vertices;
      keep_example(r.duplicate_vertex_examples, std::pair<int, int>(std::minmax(a, b)), max_ex);
    }
  }
  return r;
}

}  // namespace gp
