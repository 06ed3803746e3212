#include "avatar/isosurface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/error.h"

namespace gp {

namespace {

// The sample grid: (nx + 1) (ny + 1) (nz + 1) points from `lo`, `h` apart.
struct Grid {
  Eigen::Vector3d lo;
  double h = 0.0;
  int nx = 0, ny = 0, nz = 0;
  long long px = 0, py = 0, pz = 0;
  long long index(long long i, long long j, long long k) const { return (k * py + j) * px + i; }
  Eigen::Vector3d position(long long i, long long j, long long k) const {
    return Eigen::Vector3d(lo.x() + i * h, lo.y() + j * h, lo.z() + k * h);
  }
};

Grid make_grid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double h) {
  if (!(h > 0) || !((hi - lo).minCoeff() > 0))
    throw Error(ExitCode::internal, "marching_tetrahedra: empty box or cell size");
  Grid g;
  g.lo = lo;
  g.h = h;
  g.nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / h));
  g.ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / h));
  g.nz = static_cast<int>(std::ceil((hi.z() - lo.z()) / h));
  g.px = g.nx + 1, g.py = g.ny + 1, g.pz = g.nz + 1;
  if (g.px * g.py * g.pz > 400000000LL) throw GeometryError("isosurface grid too large; use a larger cell size");
  return g;
}

// The field's value at every grid point, by an octree descent over blocks of
// cells: a block whose centre value exceeds the Lipschitz bound over its half
// diagonal lies wholly on one side and is filled with +-h by sign; blocks
// near the surface are split down to 2 x 2 x 2 cells and evaluated.
class GridSampler {
 public:
  GridSampler(const std::function<double(const Eigen::Vector3d&)>& field, const Grid& grid, const IsosurfaceOptions& o)
      : field_(field), g_(grid), o_(o), value_(static_cast<size_t>(grid.px * grid.py * grid.pz), 0.0f),
        state_(value_.size(), 0) {}

  std::vector<float> sample() {
    const int B = 16;
    for (int k = 0; k < g_.nz; k += B)
      for (int j = 0; j < g_.ny; j += B)
        for (int i = 0; i < g_.nx; i += B)
          visit(i, std::min(i + B, g_.nx), j, std::min(j + B, g_.ny), k, std::min(k + B, g_.nz));
    return std::move(value_);
  }
  long long evaluations() const { return evals_; }

 private:
  void eval(long long i, long long j, long long k) {
    const long long id = g_.index(i, j, k);
    if (state_[id] == 2) return;
    const double v = field_(g_.position(i, j, k));
    ++evals_;
    if (!std::isfinite(v)) throw NumericalError("implicit function is not finite at a grid point");
    value_[id] = static_cast<float>(v);
    state_[id] = 2;
  }

  // The block of cells [i0, i1) x [j0, j1) x [k0, k1).
  void visit(int i0, int i1, int j0, int j1, int k0, int k1) {
    const Eigen::Vector3d a = g_.position(i0, j0, k0), b = g_.position(i1, j1, k1);
    const double half_diag = 0.5 * (b - a).norm();
    const double fc = field_(0.5 * (a + b));
    ++evals_;
    if (std::abs(fc) > o_.lipschitz * half_diag) {
      const float fill = fc > 0 ? 1.0f : -1.0f;
      for (int k = k0; k <= k1; ++k)
        for (int j = j0; j <= j1; ++j)
          for (int i = i0; i <= i1; ++i) {
            const long long id = g_.index(i, j, k);
            if (state_[id] == 0) {
              value_[id] = fill * static_cast<float>(g_.h);
              state_[id] = 1;
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
  }

  const std::function<double(const Eigen::Vector3d&)>& field_;
  const Grid& g_;
  const IsosurfaceOptions& o_;
  std::vector<float> value_;
  std::vector<uint8_t> state_;  // 0 unknown, 1 filled by sign, 2 evaluated
  long long evals_ = 0;
};

// Kuhn tetrahedra: corner c has offsets (c & 1, c >> 1 & 1, c >> 2 & 1);
// each tetrahedron walks from corner 0 to corner 7 adding one axis at a time.
std::array<std::array<int, 4>, 6> kuhn_tetrahedra() {
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
  return tets;
}

// The triangles of the zero level set, cell by cell and tetrahedron by
// tetrahedron; a cut point is shared by every triangle on its grid edge.
class Polygonizer {
 public:
  Polygonizer(const Grid& grid, const std::vector<float>& value, double min_edge_fraction)
      : g_(grid), value_(value), fmin_(min_edge_fraction), tets_(kuhn_tetrahedra()) {
    vertex_of_edge_.reserve(1 << 16);
  }

  Mesh polygonize() {
    for (int k = 0; k < g_.nz; ++k)
      for (int j = 0; j < g_.ny; ++j)
        for (int i = 0; i < g_.nx; ++i) cell(i, j, k);
    Mesh mesh;
    mesh.V.resize(static_cast<Eigen::Index>(verts_.size()), 3);
    for (size_t a = 0; a < verts_.size(); ++a) mesh.V.row(a) = verts_[a].transpose();
    mesh.F.resize(static_cast<Eigen::Index>(tris_.size()), 3);
    for (size_t a = 0; a < tris_.size(); ++a) mesh.F.row(a) = tris_[a].transpose();
    return mesh;
  }

 private:
  void cell(int i, int j, int k) {
    std::array<long long, 8> id;
    std::array<float, 8> v;
    int neg = 0;
    for (int c = 0; c < 8; ++c) {
      id[c] = g_.index(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
      v[c] = value_[id[c]];
      neg += v[c] < 0;
    }
    if (neg == 0 || neg == 8) return;
    auto corner_pos = [&](int c) -> Eigen::Vector3d {
      return g_.position(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
    };
    auto edge_vertex = [&](int ca, int cb) {
      // Lower corner first: Kuhn edges always go from a corner to one with
      // a superset of its offsets.
      if ((ca & cb) != ca) std::swap(ca, cb);
      const uint64_t key = static_cast<uint64_t>(id[ca]) * 8 + static_cast<uint64_t>(cb ^ ca);
      auto it = vertex_of_edge_.find(key);
      if (it != vertex_of_edge_.end()) return it->second;
      double t = static_cast<double>(v[ca]) / (static_cast<double>(v[ca]) - v[cb]);
      t = std::clamp(t, fmin_, 1.0 - fmin_);
      verts_.push_back(corner_pos(ca) + t * (corner_pos(cb) - corner_pos(ca)));
      const int vid = static_cast<int>(verts_.size()) - 1;
      vertex_of_edge_.emplace(key, vid);
      return vid;
    };
    for (const auto& tet : tets_) {
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
        tris_.emplace_back(edge_vertex(e[0].first, e[0].second), edge_vertex(e[1].first, e[1].second),
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

  const Grid& g_;
  const std::vector<float>& value_;
  const double fmin_;
  const std::array<std::array<int, 4>, 6> tets_;
  std::unordered_map<uint64_t, int> vertex_of_edge_;
  std::vector<Eigen::Vector3d> verts_;
  std::vector<Eigen::Vector3i> tris_;
};

}  // namespace

Mesh marching_tetrahedra(const std::function<double(const Eigen::Vector3d&)>& field,
                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const IsosurfaceOptions& o,
                         IsosurfaceStats* stats) {
  const Grid grid = make_grid(lo, hi, o.cell);
  GridSampler sampler(field, grid, o);
  const std::vector<float> value = sampler.sample();
  Mesh mesh = Polygonizer(grid, value, o.min_edge_fraction).polygonize();
  if (stats) {
    stats->field_evaluations = sampler.evaluations();
    stats->grid_points = grid.px * grid.py * grid.pz;
  }
  return mesh;
}

}  // namespace gp
