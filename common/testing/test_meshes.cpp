#include "testing/test_meshes.h"

#include <algorithm>

#include <cmath>
#include <map>
#include <vector>

#include <Eigen/Geometry>

namespace gp::testing {
namespace {

Mesh from_lists(const std::vector<Eigen::Vector3d>& V, const std::vector<Eigen::Vector3i>& F) {
  Mesh m;
  m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (size_t i = 0; i < V.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = V[i].transpose();
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t i = 0; i < F.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = F[i].transpose();
  return m;
}

}  // namespace

Mesh make_icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> V = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Eigen::Vector3i> F = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& v : V) v.normalize();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      V.push_back((V[a] + V[b]).normalized());
      const int id = static_cast<int>(V.size()) - 1;
      midpoint[key] = id;
      return id;
    };
    std::vector<Eigen::Vector3i> next;
    for (const auto& f : F) {
      const int a = mid(f[0], f[1]), b = mid(f[1], f[2]), c = mid(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    F = std::move(next);
  }
  for (auto& v : V) v *= radius;
  return from_lists(V, F);
}

Mesh make_uv_sphere(int rings, int segments, double radius) {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  V.push_back({0, radius, 0});
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      V.push_back({radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta),
                   radius * std::sin(theta) * std::cos(phi)});
    }
  }
  V.push_back({0, -radius, 0});
  const int south = static_cast<int>(V.size()) - 1;
  auto ring_vertex = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) F.push_back({0, ring_vertex(1, s), ring_vertex(1, s + 1)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int a = ring_vertex(r, s), b = ring_vertex(r, s + 1);
      const int c = ring_vertex(r + 1, s), d = ring_vertex(r + 1, s + 1);
      F.push_back({a, c, d});
      F.push_back({a, d, b});
    }
  for (int s = 0; s < segments; ++s)
    F.push_back({south, ring_vertex(rings - 1, s + 1), ring_vertex(rings - 1, s)});
  return from_lists(V, F);
}

Mesh make_torus(int nu, int nv, double ring_radius, double tube_radius) {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * M_PI * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2 * M_PI * j / nv;
      const double rr = ring_radius + tube_radius * std::cos(v);
      V.push_back({rr * std::cos(u), tube_radius * std::sin(v), rr * std::sin(u)});
    }
  }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      F.push_back({a, c, b});
      F.push_back({a, d, c});
    }
  return from_lists(V, F);
}

Mesh make_open_cylinder(int nu, int nv, double radius, double height) {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * M_PI * i / nu;
      V.push_back({radius * std::sin(u), height * j / nv, radius * std::cos(u)});
    }
  auto id = [&](int i, int j) { return j * nu + (i % nu); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      F.push_back({a, b, c});
      F.push_back({a, c, d});
    }
  return from_lists(V, F);
}

Mesh make_bent_tube(int nu, double radius, double leg, double bend_radius, double turn) {
  // Stations along the centreline: position, and the unit normal N in the
  // xy-plane (towards the inside of the bend); the ring is N, +z.
  struct Station {
    Eigen::Vector3d p, n;
  };
  std::vector<Station> stations;
  const double spacing = 2.0 * M_PI * radius / nu;
  const int n_leg = std::max(1, static_cast<int>(std::ceil(leg / spacing)));
  const int n_arc = std::max(1, static_cast<int>(std::ceil(turn * (bend_radius + radius) / spacing)));
  for (int j = 0; j < n_leg; ++j) stations.push_back({{0.0, -leg + leg * j / n_leg, 0.0}, {1.0, 0.0, 0.0}});
  const Eigen::Vector3d centre(bend_radius, 0.0, 0.0);
  for (int j = 0; j <= n_arc; ++j) {
    const double a = turn * j / n_arc;
    const Eigen::Vector3d n(std::cos(a), -std::sin(a), 0.0);
    stations.push_back({centre - bend_radius * n, n});
  }
  const Eigen::Vector3d end = stations.back().p, n_end = stations.back().n;
  const Eigen::Vector3d t_end(std::sin(turn), std::cos(turn), 0.0);
  for (int j = 1; j <= n_leg; ++j) stations.push_back({end + leg * j / n_leg * t_end, n_end});

  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  for (const Station& s : stations)
    for (int i = 0; i < nu; ++i) {
      const double u = 2.0 * M_PI * i / nu;
      V.push_back(s.p + radius * (std::cos(u) * s.n + std::sin(u) * Eigen::Vector3d::UnitZ()));
    }
  const int rows = static_cast<int>(stations.size());
  auto id = [&](int i, int j) { return j * nu + (i % nu); };
  for (int j = 0; j + 1 < rows; ++j)
    for (int i = 0; i < nu; ++i) {
      F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  const int first = static_cast<int>(V.size());
  V.push_back(stations.front().p);
  V.push_back(stations.back().p);
  for (int i = 0; i < nu; ++i) {
    F.push_back({first, id(i + 1, 0), id(i, 0)});
    F.push_back({first + 1, id(i, rows - 1), id(i + 1, rows - 1)});
  }
  // Outward normals: positive enclosed volume.
  double volume = 0.0;
  for (const auto& f : F) volume += V[f[0]].dot(V[f[1]].cross(V[f[2]]));
  if (volume < 0)
    for (auto& f : F) std::swap(f[1], f[2]);
  return from_lists(V, F);
}

Mesh make_grid(int nx, int nz, double sx, double sz) {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i) V.push_back({sx * i / nx, 0.0, sz * j / nz});
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < nz; ++j)
    for (int i = 0; i < nx; ++i) {
      // Normals point to +y.
      F.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      F.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  return from_lists(V, F);
}

SubMesh face_subset(const Mesh& m, const std::vector<int>& face_ids) {
  SubMesh out;
  std::vector<int> new_id(m.V.rows(), -1);
  out.mesh.F.resize(static_cast<Eigen::Index>(face_ids.size()), 3);
  for (size_t i = 0; i < face_ids.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const int v = m.F(face_ids[i], k);
      if (new_id[v] < 0) {
        new_id[v] = static_cast<int>(out.vertex_ids.size());
        out.vertex_ids.push_back(v);
      }
      out.mesh.F(static_cast<Eigen::Index>(i), k) = new_id[v];
    }
  }
  out.mesh.V.resize(static_cast<Eigen::Index>(out.vertex_ids.size()), 3);
  for (size_t i = 0; i < out.vertex_ids.size(); ++i) out.mesh.V.row(static_cast<Eigen::Index>(i)) = m.V.row(out.vertex_ids[i]);
  return out;
}

double max_edge_stretch(const Eigen::MatrixXd& X, const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F) {
  double s = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      s = std::max(s, (X.row(a) - X.row(b)).norm() / (V_rest.row(a) - V_rest.row(b)).norm());
    }
  }
  return s;
}

std::vector<int> ring_vertex_ids(const Eigen::MatrixXd& V, const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                                 double reach, int count) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  std::vector<int> ids;
  for (int j = 0; j < count; ++j) {
    const double phi = 2.0 * M_PI * j / count;
    const Eigen::Vector3d dir = std::cos(phi) * u + std::sin(phi) * w;
    int best = -1;
    double best_score = 1e300;
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      const Eigen::Vector3d d = V.row(v).transpose() - center;
      const double h = d.dot(n);
      const Eigen::Vector3d radial = d - h * n;
      if (radial.norm() > reach || radial.norm() < 1e-9) continue;
      const double score = std::abs(h) + 0.05 * (radial.normalized() - dir).norm();
      if (score < best_score) {
        best_score = score;
        best = static_cast<int>(v);
      }
    }
    ids.push_back(best);
  }
  return ids;
}

}  // namespace gp::testing
