#include "avatar/isosurface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/error.h"

namespace gp {

Mesh marching_tetrahedra(const std::function<double(const Eigen::Vector3d&)>& field,
                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const IsosurfaceOptions& o,
                         IsosurfaceStats* stats) {
  const double h = o.cell;
  if (!(h > 0) || !((hi - lo).minCoeff() > 0))
    throw Error(ExitCode::internal, "marching_tetrahedra: empty box or cell size");
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / h));
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / h));
  const int nz = static_cast<int>(std::ceil((hi.z() - lo.z()) / h));
  const long long px = nx + 1, py = ny + 1, pz = nz + 1;
  const long long n_points = px * py * pz;
  if (n_points > 400000000LL) throw GeometryError("isosurface grid too large; use a larger cell size");
  auto index = [&](long long i, long long j, long long k) { return (k * py + j) * px + i; };
  auto position = [&](long long i, long long j, long long k) {
    return Eigen::Vector3d(lo.x() + i * h, lo.y() + j * h, lo.z() + k * h);
  };
  std::vector<float> value(n_points, 0.0f);
  std::vector<uint8_t> state(n_points, 0);  // 0 unknown, 1 filled by sign, 2 evaluated
  long long evals = 0;
  auto eval = [&](long long i, long long j, long long k) {
    const long long id = index(i, j, k);
    if (state[id] == 2) return;
    const double v = field(position(i, j, k));
    ++evals;
    if (!std::isfinite(v)) throw NumericalError("implicit function is not finite at a grid point");
    value[id] = static_cast<float>(v);
    state[id] = 2;
  };

  // Octree descent over blocks of cells [i0, i1) x [j0, j1) x [k0, k1).
  std::function<void(int, int, int, int, int, int)> visit = [&](int i0, int i1, int j0, int j1, int k0,
                                                                int k1) {
    const Eigen::Vector3d a = position(i0, j0, k0), b = position(i1, j1, k1);
    const double half_diag = 0.5 * (b - a).norm();
    const double fc = field(0.5 * (a + b));
    ++evals;
    if (std::abs(fc) > o.lipschitz * half_diag) {
      const float fill = fc > 0 ? 1.0f : -1.0f;
      for (int k = k0; k <= k1; ++k)
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i) {
            const long long id = index(i, j, k);
            if (state[id] == 0) {
              value[id] = fill * static_cast<float>(h);
              state[id] = 1;
            }
          }
      return;
    }
    if (i1 - i0 <= 2 && j1 - j0 <= 2 && k1 - k0 <= 2) {
      for (int k = k0; k <= k1; ++k)
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i) eval(i, j, k);
      return;
    }
    const int im = i1 - i0 > 1 ? (i0 + i1) / 2 : i1, jm = j1 - j0 > 1 ? (j0 + j1) / 2 : j1,
              km = k1 - k0 > 1 ? (k0 + k1) / 2 : k1;
    const int is[3] = {i0, im, i1}, js[3] = {j0, jm, j1}, ks[3] = {k0, km, k1};
    for (int c = 0; c < 2; ++c)
      for (int bj = 0; bj < 2; ++bj)
        for (int bi = 0; bi < 2; ++bi) {
          if (is[bi] == is[bi + 1] || js[bj] == js[bj + 1] || ks[c] == ks[c + 1]) continue;
          visit(is[bi], is[bi + 1], js[bj], js[bj + 1], ks[c], ks[c + 1]);
        }
  };
  const int B = 16;
  for (int k = 0; k < nz; k += B)
    for (int j = 0; j < ny; j += B)
      for (int i = 0; i < nx; i += B)
        visit(i, std::min(i + B, nx), j, std::min(j + B, ny), k, std::min(k + B, nz));

  // Kuhn tetrahedra: corner c has offsets (c & 1, c >> 1 & 1, c >> 2 & 1);
  // each tetrahedron walks from corner 0 to corner 7 adding one axis at a time.
  static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::array<std::array<int, 4>, 6> tets;
  for (int t = 0; t < 6; ++t) {
    int c = 0;
    tets[t][0] = 0;
    for (int s = 0; s < 3; ++s) {
      c |= 1 << perms[t][s];
      tets[t][s + 1] = c;
    }
  }

  std::unordered_map<uint64_t, int> vertex_of_edge;
  vertex_of_edge.reserve(1 << 16);
  std::vector<Eigen::Vector3d> verts;
  std::vector<Eigen::Vector3i> tris;
  const double fmin = o.min_edge_fraction;

  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::array<long long, 8> id;
        std::array<float, 8> v;
        int neg = 0;
        for (int c = 0; c < 8; ++c) {
          id[c] = index(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
          v[c] = value[id[c]];
          neg += v[c] < 0;
        }
        if (neg == 0 || neg == 8) continue;
        auto corner_pos = [&](int c) -> Eigen::Vector3d {
          return position(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
        };
        auto edge_vertex = [&](int ca, int cb) {
          // Lower corner first: Kuhn edges always go from a corner to one with
          // a superset of its offsets.
          if ((ca & cb) != ca) std::swap(ca, cb);
          const uint64_t key = static_cast<uint64_t>(id[ca]) * 8 + static_cast<uint64_t>(cb ^ ca);
          auto it = vertex_of_edge.find(key);
          if (it != vertex_of_edge.end()) return it->second;
          double t = static_cast<double>(v[ca]) / (static_cast<double>(v[ca]) - v[cb]);
          t = std::clamp(t, fmin, 1.0 - fmin);
          verts.push_back(corner_pos(ca) + t * (corner_pos(cb) - corner_pos(ca)));
          const int vid = static_cast<int>(verts.size()) - 1;
          vertex_of_edge.emplace(key, vid);
          return vid;
        };
        for (const auto& tet : tets) {
          int in[4], out[4], ni = 0, no = 0;
          for (int c : tet) (v[c] < 0 ? in[ni++] : out[no++]) = c;
          if (ni == 0 || no == 0) continue;
          // Direction from inside to outside, to orient the patch: decided on
          // the grid corners (never degenerate), not on the cut points.
          Eigen::Vector3d gin = Eigen::Vector3d::Zero(), gout = Eigen::Vector3d::Zero();
          for (int a = 0; a < ni; ++a) gin += corner_pos(in[a]) / ni;
          for (int a = 0; a < no; ++a) gout += corner_pos(out[a]) / no;
          const Eigen::Vector3d dir = gout - gin;
          auto mid = [&](int a, int b) -> Eigen::Vector3d { return 0.5 * (corner_pos(a) + corner_pos(b)); };
          auto emit = [&](std::array<std::pair<int, int>, 3> e) {
            const Eigen::Vector3d m0 = mid(e[0].first, e[0].second), m1 = mid(e[1].first, e[1].second),
                                  m2 = mid(e[2].first, e[2].second);
            if ((m1 - m0).cross(m2 - m0).dot(dir) < 0) std::swap(e[1], e[2]);
            tris.emplace_back(edge_vertex(e[0].first, e[0].second), edge_vertex(e[1].first, e[1].second),
                              edge_vertex(e[2].first, e[2].second));
          };
          if (ni == 1) {
            emit({{{in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]}}});
          } else if (no == 1) {
            emit({{{in[0], out[0]}, {in[1], out[0]}, {in[2], out[0]}}});
          } else {
            // Quad (i0,o0) (i0,o1) (i1,o1) (i1,o0), split along one diagonal.
            emit({{{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}}});
            emit({{{in[0], out[0]}, {in[1], out[1]}, {in[1], out[0]}}});
          }
        }
      }
  Mesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(verts.size()), 3);
  for (size_t a = 0; a < verts.size(); ++a) mesh.V.row(a) = verts[a].transpose();
  mesh.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t a = 0; a < tris.size(); ++a) mesh.F.row(a) = tris[a].transpose();
  if (stats) {
    stats->field_evaluations = evals;
    stats->grid_points = n_points;
  }
  return mesh;
}

}  // namespace gp
