#include "collision/continuous_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <future>
#include <limits>
#include <string>
#include <Eigen/Geometry>

#include "collision/ccd.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "mesh/topology.h"

namespace gp::collision {
namespace {

using Eigen::Vector3d;

// Upper bound on the broad-phase grid's cells; the cell grows beyond the
// cloth's mean swept triangle where the cloth's box would need more.
constexpr long kMaxGridCells = 1L << 21;
// Margin [m] around the cloth's box within which the broad-phase grid holds
// the body, so that a still body's grid serves while the cloth moves a little.
constexpr double kRegionMargin = 0.02;
// Passes of the fail-safe (each holds the cloth vertices of the passages left
// by the last), at most.
constexpr int kFailSafePasses = 8;

// Bounding boxes are Eigen's (empty when constructed); grown by a margin on
// every side.
using Box = Eigen::AlignedBox3d;
void grow(Box& b, double m) {
  b.min().array() -= m;
  b.max().array() += m;
}

// A contact to answer: the cloth point sum_k weight[k] x[vertex[k]] must end
// at least `thickness` from the body point along `direction` (unit, from the
// body point towards the cloth's side).
struct Impact {
  std::array<int, 3> vertex{{-1, -1, -1}};
  std::array<double, 3> weight{{0.0, 0.0, 0.0}};
  Vector3d body_start = Vector3d::Zero();  // body point at the start and the end of the (sub)step
  Vector3d body_end = Vector3d::Zero();
  Vector3d direction = Vector3d::Zero();
  bool crossing = false;  // a passage through (else only nearer than the thickness at the end)
  // Largest push [m]: the thickness plus how far the two points moved
  // against each other over the step (their start was in order). A sliver
  // triangle's normal turns fast, and the distance along it at the end can
  // be far larger than any motion that happened.
  double max_push = 0.0;
};

// m.max_push from the cloth point's start and end (X0, X1 at m's weights).
void bound_push(Impact& m, const Eigen::MatrixXd& X0, const Eigen::MatrixXd& X1, double thickness) {
  Vector3d moved = Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (m.vertex[k] >= 0) moved += m.weight[k] * (X1.row(m.vertex[k]) - X0.row(m.vertex[k])).transpose();
  }
  m.max_push = thickness + (moved - (m.body_end - m.body_start)).norm();
}

// Whether the convex hulls of point sets A and B (each the start and end
// positions of a moving feature, which hold it throughout the step) are
// farther apart than `gap` along `axis` (any axis separates conservatively).
template <size_t NA, size_t NB>
bool separated_along(const Vector3d& axis, const std::array<Vector3d, NA>& A, const std::array<Vector3d, NB>& B,
                     double gap) {
  const double scaled = gap * axis.norm();
  double a_lo = axis.dot(A[0]), a_hi = a_lo, b_lo = axis.dot(B[0]), b_hi = b_lo;
  for (size_t i = 1; i < NA; ++i) {
    const double d = axis.dot(A[i]);
    a_lo = std::min(a_lo, d);
    a_hi = std::max(a_hi, d);
  }
  for (size_t i = 1; i < NB; ++i) {
    const double d = axis.dot(B[i]);
    b_lo = std::min(b_lo, d);
    b_hi = std::max(b_hi, d);
  }
  return b_lo > a_hi + scaled || a_lo > b_hi + scaled;
}

}  // namespace

struct ContinuousContact::Impl {
  ContinuousContactOptions options;
  Eigen::MatrixXi F;          // cloth faces
  Eigen::MatrixXi E;          // cloth edges (unique)
  int cloth_vertices = 0;
  std::vector<char> pinned;

  Eigen::MatrixXi F_body;
  std::vector<int> body_faces;            // culled face ids
  std::vector<std::array<int, 2>> body_edges;  // culled edges (body vertex ids)
  std::vector<int> body_vertices;         // culled vertex ids
  int body_vertex_count = 0;
  Eigen::MatrixXd B_previous, B_current;  // full body frames
  bool has_body = false;

  // Per enforce(): body positions at the start and end of the (sub)step,
  // rows of the full body (only culled rows filled).
  Eigen::MatrixXd Bs, Be;

  // Broad phase: a uniform grid over the culled body's features swept over
  // the (sub)step, one compressed cell list per kind (0 vertices, 1 edges,
  // 2 faces), rebuilt only when the body's span changes (every step while the
  // body moves; once while it stands still). The cloth's swept features look
  // up the cells of their boxes: the body is sampled where the cloth is, and
  // the cloth is small against the culled body.
  // A cell entry: a body item's swept box (single precision, rounded
  // outwards, so that the lists stream through the cache) and its index.
  struct Entry {
    float lo[3], hi[3];
    int item;
    int cell_x;  // x index of the cell the entry is listed in
  };
  Box grid_box = Box();
  double cell = 1.0, inverse_cell = 1.0;
  long n_cells[3] = {0, 0, 0};
  std::vector<int> cell_start[3];
  std::vector<Entry> cell_entries[3];
  long body_version = 0, grid_version = -1;  // body frames set / the grid's
  double grid_s0 = -1.0, grid_s1 = -1.0;
  Box grid_region = Box();  // the grid holds the body items meeting this box
  double mean_body_edge = 0.0;     // of the culled body in the first frame [m]
  std::vector<Entry> items[3];     // build scratch
  std::vector<int> fill;
  int threads = 1;

  ContinuousContactStats stats;

  Vector3d x(const Eigen::MatrixXd& X, int v) const { return X.row(v).transpose(); }

  long cell_of(double coordinate, int axis) const {
    // Truncation rounds towards zero, which the clamp makes the first cell.
    return std::clamp(static_cast<long>((coordinate - grid_box.min()(axis)) * inverse_cell), 0L, n_cells[axis] - 1);
  }

  // Cells of box [lo, hi], clamped to the grid; false when it misses the grid.
  bool cell_range(const double lo_corner[3], const double hi_corner[3], long lo[3], long hi[3]) const {
    for (int a = 0; a < 3; ++a) {
      if (hi_corner[a] < grid_box.min()(a) || lo_corner[a] > grid_box.max()(a)) return false;
      lo[a] = cell_of(lo_corner[a], a);
      hi[a] = cell_of(hi_corner[a], a);
    }
    return true;
  }

  // Orders the culled body items by the cell of their centroid in this first
  // frame (z, then y, then x, the grid's own order), so that filling the grid
  // of a later, nearby frame writes its cells nearly in sequence rather than
  // at random (the grid is refilled every step while the body moves).
  void sort_body_items(const Eigen::MatrixXd& V_body) {
    const double c = std::max(2.0 * mean_body_edge, 1e-6);
    auto key = [c](const Vector3d& p) {
      return std::array<long, 3>{static_cast<long>(std::floor(p.z() / c)), static_cast<long>(std::floor(p.y() / c)),
                                 static_cast<long>(std::floor(p.x() / c))};
    };
    auto centroid = [&V_body](std::initializer_list<int> rows) {
      Vector3d sum = Vector3d::Zero();
      for (int r : rows) sum += V_body.row(r).transpose();
      return Vector3d(sum / static_cast<double>(rows.size()));
    };
    auto by_key = [](auto& list, auto key_of) {
      std::vector<std::pair<std::array<long, 3>, size_t>> keyed(list.size());
      for (size_t i = 0; i < list.size(); ++i) keyed[i] = {key_of(list[i]), i};
      std::sort(keyed.begin(), keyed.end());
      auto sorted = list;
      for (size_t i = 0; i < list.size(); ++i) sorted[i] = list[keyed[i].second];
      list = std::move(sorted);
    };
    by_key(body_vertices, [&](int v) { return key(centroid({v})); });
    by_key(body_edges, [&](const std::array<int, 2>& e) { return key(centroid({e[0], e[1]})); });
    by_key(body_faces, [&](int f) { return key(centroid({F_body(f, 0), F_body(f, 1), F_body(f, 2)})); });
  }

  // The grid for the current (sub)step: body items whose swept boxes meet
  // `region` (the cloth's swept box), in cells of 1.5 mean body edges (a
  // cloth triangle's box, a few body edges across, meets a few rows of cells
  // holding a few body features each: smaller cells cost more rows, larger
  // ones more features per row). Kept while the body is the same and the
  // cloth stays inside the region it was built for, which is the cloth's box
  // grown by kRegionMargin.
  void build_body_grid(double s0, double s1, const Box& cloth) {
    const bool inside = (cloth.min().array() >= grid_region.min().array()).all() &&
                        (cloth.max().array() <= grid_region.max().array()).all();
    if (grid_version == body_version && grid_s0 == s0 && grid_s1 == s1 && inside) return;
    grid_version = body_version;
    grid_s0 = s0;
    grid_s1 = s1;
    grid_region = cloth;
    grow(grid_region, kRegionMargin);
    // Single precision rounded outwards: the box grown by a relative 2^-22
    // (plus a floor) holds the double one after rounding to float.
    auto swept_entry = [&](std::initializer_list<int> rows, int item, Entry& e) {
      Box b = Box();
      for (int r : rows) {
        b.extend(x(Bs, r));
        b.extend(x(Be, r));
      }
      grow(b, options.thickness);
      if (!b.intersects(grid_region)) return false;
      for (int a = 0; a < 3; ++a) {
        const double slack = 2.4e-7 * std::max(std::abs(b.min()(a)), std::abs(b.max()(a))) + 1e-12;
        e.lo[a] = static_cast<float>(b.min()(a) - slack);
        e.hi[a] = static_cast<float>(b.max()(a) + slack);
      }
      e.item = item;
      return true;
    };
    Entry made;
    for (auto& list : items) list.clear();
    for (size_t i = 0; i < body_vertices.size(); ++i) {
      if (swept_entry({body_vertices[i]}, static_cast<int>(i), made)) items[0].push_back(made);
    }
    for (size_t i = 0; i < body_edges.size(); ++i) {
      if (swept_entry({body_edges[i][0], body_edges[i][1]}, static_cast<int>(i), made)) items[1].push_back(made);
    }
    for (size_t i = 0; i < body_faces.size(); ++i) {
      const int f = body_faces[i];
      if (swept_entry({F_body(f, 0), F_body(f, 1), F_body(f, 2)}, static_cast<int>(i), made)) items[2].push_back(made);
    }
    grid_box = Box();
    for (const Entry& item : items[2]) {
      grid_box.extend(Vector3d(item.lo[0], item.lo[1], item.lo[2]));
      grid_box.extend(Vector3d(item.hi[0], item.hi[1], item.hi[2]));
    }
    grid_box.min() = grid_box.min().cwiseMax(grid_region.min());
    grid_box.max() = grid_box.max().cwiseMin(grid_region.max());
    if (!grid_box.min().allFinite() || !grid_box.max().allFinite() || !(grid_box.max().array() >= grid_box.min().array()).all()) {
      grid_box = grid_region;  // no body item near the cloth: one empty grid over the region
    }
    cell = std::max(1.5 * mean_body_edge, 1e-6);
    const Vector3d size = grid_box.max() - grid_box.min();
    auto dims = [&](double c) {
      for (int a = 0; a < 3; ++a) n_cells[a] = static_cast<long>(size(a) / c) + 1;
    };
    dims(cell);
    while (n_cells[0] * n_cells[1] * n_cells[2] > kMaxGridCells) {
      cell *= 1.5;
      dims(cell);
    }
    inverse_cell = 1.0 / cell;
    for (int kind = 0; kind < 3; ++kind) {
      std::vector<int>& start = cell_start[kind];
      start.assign(static_cast<size_t>(n_cells[0] * n_cells[1] * n_cells[2] + 1), 0);
      auto for_cells_of = [&](const Entry& item, auto&& visit) {
        const double lo_corner[3] = {item.lo[0], item.lo[1], item.lo[2]};
        const double hi_corner[3] = {item.hi[0], item.hi[1], item.hi[2]};
        long lo[3], hi[3];
        if (!cell_range(lo_corner, hi_corner, lo, hi)) return;
        for (long k = lo[2]; k <= hi[2]; ++k)
          for (long j = lo[1]; j <= hi[1]; ++j)
            for (long i = lo[0]; i <= hi[0]; ++i) visit((k * n_cells[1] + j) * n_cells[0] + i);
      };
      for (const Entry& e : items[kind]) for_cells_of(e, [&](long c) { ++start[static_cast<size_t>(c) + 1]; });
      for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
      cell_entries[kind].resize(static_cast<size_t>(start.back()));
      fill.assign(start.begin(), start.end() - 1);
      for (const Entry& e : items[kind]) {
        for_cells_of(e, [&](long c) {
          Entry& listed = cell_entries[kind][static_cast<size_t>(fill[static_cast<size_t>(c)]++)];
          listed = e;
          listed.cell_x = static_cast<int>(c % n_cells[0]);
        });
      }
    }
  }

  // Calls visit(i) once for every culled body item of `kind` whose swept box
  // meets b: a pair is reported in the one cell that holds the low corner of
  // the two boxes' intersection, which both boxes cover.
  template <class Visit>
  void for_candidates(int kind, const Box& b, ContinuousContactStats& st, Visit visit) const {
    const double lo_corner[3] = {b.min().x(), b.min().y(), b.min().z()}, hi_corner[3] = {b.max().x(), b.max().y(), b.max().z()};
    long lo[3], hi[3];
    if (!cell_range(lo_corner, hi_corner, lo, hi)) return;
    const std::vector<int>& start = cell_start[kind];
    const std::vector<Entry>& entries = cell_entries[kind];
    // Cells are numbered x fastest: the cells lo[0]..hi[0] of a row hold one
    // contiguous run of entries.
    for (long k = lo[2]; k <= hi[2]; ++k) {
      for (long j = lo[1]; j <= hi[1]; ++j) {
        const long row = (k * n_cells[1] + j) * n_cells[0];
        const int first = start[static_cast<size_t>(row + lo[0])], last = start[static_cast<size_t>(row + hi[0]) + 1];
        st.candidates += last - first;
        for (int q = first; q < last; ++q) {
          const Entry& e = entries[static_cast<size_t>(q)];
          if (e.lo[0] > hi_corner[0] || e.hi[0] < lo_corner[0] || e.lo[1] > hi_corner[1] || e.hi[1] < lo_corner[1] ||
              e.lo[2] > hi_corner[2] || e.hi[2] < lo_corner[2]) {
            continue;
          }
          // Only in the cell of the intersection's low corner (along an axis
          // where the query starts above the item: the query's first cell).
          const long i = e.cell_x;
          if ((e.lo[0] < lo_corner[0] ? i != lo[0] : cell_of(e.lo[0], 0) != i) ||
              (e.lo[1] < lo_corner[1] ? j != lo[1] : cell_of(e.lo[1], 1) != j) ||
              (e.lo[2] < lo_corner[2] ? k != lo[2] : cell_of(e.lo[2], 2) != k)) {
            continue;
          }
          ++st.overlaps;
          visit(e.item);
        }
      }
    }
  }

  Box swept(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, std::initializer_list<int> rows) const {
    Box b = Box();
    for (int r : rows) {
      b.extend(x(A, r));
      b.extend(x(B, r));
    }
    return b;
  }

  // The contacts of the cloth features [begin, end) of one kind (0 faces:
  // against body vertices, 1 edges: against body edges, 2 vertices: against
  // body faces), appended to out in ascending order.
  void detect_range(int kind, const Eigen::MatrixXd& X0, const Eigen::MatrixXd& X1, int begin, int end,
                    std::vector<Impact>& out, ContinuousContactStats& st) const {
    const double thick = options.thickness, tol = options.tolerance;
    // Body vertices against cloth triangles.
    for (int f = begin; kind == 0 && f < end; ++f) {
      const int i = F(f, 0), j = F(f, 1), k = F(f, 2);
      const Box box = swept(X0, X1, {i, j, k});
      const Vector3d a0 = x(X0, i), b0 = x(X0, j), c0 = x(X0, k);
      const Vector3d a1 = x(X1, i), b1 = x(X1, j), c1 = x(X1, k);
      const std::array<Vector3d, 6> cloth{{a0, b0, c0, a1, b1, c1}};
      const Vector3d n_start = (b0 - a0).cross(c0 - a0), n_end = (b1 - a1).cross(c1 - a1);
      for_candidates(0, box, st, [&](int item) {
        const int v = body_vertices[static_cast<size_t>(item)];
        const Vector3d p0 = x(Bs, v), p1 = x(Be, v);
        // Separated along either normal of the triangle: no contact.
        const std::array<Vector3d, 2> point{{p0, p1}};
        if (separated_along(n_start, cloth, point, thick) || separated_along(n_end, cloth, point, thick)) return;
        ++st.narrow;
        Impact m;
        m.vertex = {i, j, k};
        m.body_start = p0;
        m.body_end = p1;
        const auto hit = point_triangle_ccd(p0, p1, a0, a1, b0, b1, c0, c1, tol);
        if (hit && hit->side != 0) {
          // Through (or touching): the cloth goes back to the far side of the
          // body vertex, as seen before the contact.
          const Vector3d n = (b1 - a1).cross(c1 - a1);
          if (!(n.norm() > 0.0)) return;
          m.weight = {hit->weights(0), hit->weights(1), hit->weights(2)};
          m.direction = -hit->side * n.normalized();
          m.crossing = true;
          ++st.crossings;
        } else {
          const Vector3d w = closest_triangle_weights(p1, a1, b1, c1);
          const Vector3d gap = w(0) * a1 + w(1) * b1 + w(2) * c1 - p1;
          if (!(gap.norm() < thick) || !(gap.norm() > 0.0)) return;
          m.weight = {w(0), w(1), w(2)};
          m.direction = gap.normalized();
        }
        ++st.body_vertex_contacts;
        bound_push(m, X0, X1, thick);
        out.push_back(m);
      });
    }
    // Body edges against cloth edges.
    for (int ce = begin; kind == 1 && ce < end; ++ce) {
      const int i = E(ce, 0), j = E(ce, 1);
      const Box box = swept(X0, X1, {i, j});
      const Vector3d c0 = x(X0, i), c1 = x(X1, i), d0 = x(X0, j), d1 = x(X1, j);
      for_candidates(1, box, st, [&](int item) {
        const auto& e = body_edges[static_cast<size_t>(item)];
        const Vector3d a0 = x(Bs, e[0]), a1 = x(Be, e[0]), b0 = x(Bs, e[1]), b1 = x(Be, e[1]);
        // Separated along the common normal of the two edges at the start or
        // at the end: no contact.
        const std::array<Vector3d, 4> body_points{{a0, b0, a1, b1}}, cloth_points{{c0, d0, c1, d1}};
        if (separated_along(Vector3d((b0 - a0).cross(d0 - c0)), body_points, cloth_points, thick) ||
            separated_along(Vector3d((b1 - a1).cross(d1 - c1)), body_points, cloth_points, thick)) {
          return;
        }
        ++st.narrow;
        Impact m;
        m.vertex = {i, j, -1};
        const auto hit = edge_edge_ccd(a0, a1, b0, b1, c0, c1, d0, d1, tol);
        double s = 0.0, u = 0.0;
        if (hit && hit->side != 0) {
          const Vector3d n = (b1 - a1).cross(d1 - c1);
          if (!(n.norm() > 1e-12 * (b1 - a1).norm() * (d1 - c1).norm())) return;
          s = hit->s;
          u = hit->u;
          m.direction = hit->side * n.normalized();
          m.crossing = true;
          ++st.crossings;
        } else {
          closest_segment_parameters(a1, b1, c1, d1, s, u);
          const Vector3d gap = c1 + u * (d1 - c1) - a1 - s * (b1 - a1);
          // Ends of the edges: the vertex-triangle tests see those.
          if (!(gap.norm() < thick) || !(gap.norm() > 0.0) || u <= 0.0 || u >= 1.0 || s <= 0.0 || s >= 1.0) return;
          m.direction = gap.normalized();
        }
        m.weight = {1.0 - u, u, 0.0};
        m.body_start = a0 + s * (b0 - a0);
        m.body_end = a1 + s * (b1 - a1);
        ++st.edge_contacts;
        bound_push(m, X0, X1, thick);
        out.push_back(m);
      });
    }
    // Cloth vertices against body triangles: passages into the body only.
    for (int v = begin; kind == 2 && v < end; ++v) {
      const Box box = swept(X0, X1, {v});
      const Vector3d p0 = x(X0, v), p1 = x(X1, v);
      for_candidates(2, box, st, [&](int item) {
        const int bf = body_faces[static_cast<size_t>(item)];
        const int ia = F_body(bf, 0), ib = F_body(bf, 1), ic = F_body(bf, 2);
        const Vector3d a0 = x(Bs, ia), a1 = x(Be, ia), b0 = x(Bs, ib), b1 = x(Be, ib), c0 = x(Bs, ic),
                       c1 = x(Be, ic);
        const std::array<Vector3d, 6> body_points{{a0, b0, c0, a1, b1, c1}};
        const std::array<Vector3d, 2> point{{p0, p1}};
        if (separated_along(Vector3d((b0 - a0).cross(c0 - a0)), body_points, point, tol) ||
            separated_along(Vector3d((b1 - a1).cross(c1 - a1)), body_points, point, tol)) {
          return;
        }
        ++st.narrow;
        const auto hit = point_triangle_ccd(p0, p1, a0, a1, b0, b1, c0, c1, tol);
        if (!hit || hit->side <= 0) return;
        const Vector3d n = (b1 - a1).cross(c1 - a1);
        if (!(n.norm() > 0.0)) return;
        Impact m;
        m.vertex = {v, -1, -1};
        m.weight = {1.0, 0.0, 0.0};
        const Vector3d& w = hit->weights;
        m.body_start = w(0) * a0 + w(1) * b0 + w(2) * c0;
        m.body_end = w(0) * a1 + w(1) * b1 + w(2) * c1;
        m.direction = n.normalized();
        m.crossing = true;
        ++st.cloth_vertex_contacts;
        ++st.crossings;
        bound_push(m, X0, X1, thick);
        out.push_back(m);
      });
    }
  }


  // Every contact of the step from X0 to X1, in a fixed order: cloth faces,
  // cloth edges, cloth vertices, each ascending. Each kind's list is split in
  // two halves, the second queried on another thread when threads > 1; the
  // halves and so the answer do not depend on the thread count.
  std::vector<Impact> detect(const Eigen::MatrixXd& X0, const Eigen::MatrixXd& X1) {
    const int counts[3] = {static_cast<int>(F.rows()), static_cast<int>(E.rows()), cloth_vertices};
    std::vector<Impact> parts[3][2];
    ContinuousContactStats half_stats[2];
    auto run = [&](int half) {
      for (int kind = 0; kind < 3; ++kind) {
        const int middle = counts[kind] / 2;
        detect_range(kind, X0, X1, half == 0 ? 0 : middle, half == 0 ? middle : counts[kind], parts[kind][half],
                     half_stats[half]);
      }
    };
    if (threads > 1) {
      auto second = std::async(std::launch::async, run, 1);
      run(0);
      second.get();
    } else {
      run(0);
      run(1);
    }
    std::vector<Impact> out;
    for (auto& kind : parts) {
      for (auto& half : kind) out.insert(out.end(), half.begin(), half.end());
    }
    for (const ContinuousContactStats& h : half_stats) {
      stats.candidates += h.candidates;
      stats.narrow += h.narrow;
      stats.overlaps += h.overlaps;
      stats.body_vertex_contacts += h.body_vertex_contacts;
      stats.edge_contacts += h.edge_contacts;
      stats.cloth_vertex_contacts += h.cloth_vertex_contacts;
      stats.crossings += h.crossings;
    }
    return out;
  }

  // Moves the cloth point of m to `thickness` from its body point; false when
  // every vertex of it is pinned.
  bool respond(const Impact& m, Eigen::MatrixXd& X1) const {
    Vector3d c = Vector3d::Zero();
    double free_weight = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (m.vertex[k] < 0) continue;
      c += m.weight[k] * x(X1, m.vertex[k]);
      if (!pinned[m.vertex[k]]) free_weight += m.weight[k] * m.weight[k];
    }
    const double deficit = std::min(options.thickness - (c - m.body_end).dot(m.direction), m.max_push);
    if (!(deficit > 0.0)) return true;
    if (!(free_weight > 1e-12)) return false;
    for (int k = 0; k < 3; ++k) {
      const int v = m.vertex[k];
      if (v < 0 || pinned[v]) continue;
      X1.row(v) += (m.weight[k] * deficit / free_weight) * m.direction.transpose();
    }
    return true;
  }

  void enforce(const Eigen::MatrixXd& X0, Eigen::MatrixXd& X1, double s0, double s1) {
    const auto t0 = Clock::now();
    if (!has_body) throw UsageError("ContinuousContact::enforce before set_body");
    if (X0.rows() != cloth_vertices || X1.rows() != cloth_vertices || X0.cols() != 3 || X1.cols() != 3) {
      throw UsageError("cloth positions must be #V by 3 for the cloth given at construction");
    }
    ++stats.calls;
    for (int v : body_vertices) {
      Bs.row(v) = B_previous.row(v) + s0 * (B_current.row(v) - B_previous.row(v));
      Be.row(v) = B_previous.row(v) + s1 * (B_current.row(v) - B_previous.row(v));
    }
    Box cloth = Box();
    for (int v = 0; v < cloth_vertices; ++v) {
      cloth.extend(x(X0, v));
      cloth.extend(x(X1, v));
    }
    grow(cloth, options.thickness);
    build_body_grid(s0, s1, cloth);
    // The first round answers every contact, passages and pairs nearer than
    // the thickness; later rounds only the passages that responses made, and
    // a pair left nearer than the thickness (squeezed between two body parts)
    // is no intersection.
    ++stats.rounds;
    std::vector<Impact> impacts = detect(X0, X1);
    auto only_crossings = [](std::vector<Impact>& list) {
      list.erase(std::remove_if(list.begin(), list.end(), [](const Impact& m) { return !m.crossing; }), list.end());
    };
    for (int round = 0; round < options.max_rounds && !impacts.empty(); ++round) {
      for (const Impact& m : impacts) respond(m, X1);
      ++stats.rounds;
      impacts = detect(X0, X1);
      only_crossings(impacts);
    }
    if (!impacts.empty()) {
      // Fail-safe: the cloth vertices of the remaining passages keep their
      // position relative to the body point over the step, and so, in turn,
      // do those of the passages this leaves (a triangle with one vertex held
      // and two moved can still pass through), until none is left: on a body
      // standing still the held region is back where it started, which was
      // free of intersections.
      ++stats.fail_safe_calls;
      std::vector<char> held(static_cast<size_t>(cloth_vertices), 0);
      for (int pass = 0; pass < kFailSafePasses && !impacts.empty(); ++pass) {
        bool moved = false;
        for (const Impact& m : impacts) {
          for (int k = 0; k < 3; ++k) {
            const int v = m.vertex[k];
            if (v < 0 || pinned[v] || held[v]) continue;
            held[v] = 1;
            moved = true;
            X1.row(v) = X0.row(v) + (m.body_end - m.body_start).transpose();
            ++stats.fail_safe_vertices;
          }
        }
        if (!moved) break;
        ++stats.rounds;
        impacts = detect(X0, X1);
        only_crossings(impacts);
      }
      stats.unresolved += static_cast<long>(impacts.size());
    }
    stats.seconds += seconds_since(t0);
  }
};

ContinuousContact::ContinuousContact(const Eigen::MatrixXi& F_cloth, const Eigen::MatrixXi& F_body,
                                     std::vector<int> body_face_ids, const ContinuousContactOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  if (!(options.thickness > 0.0) || !(options.tolerance >= 0.0) || options.max_rounds < 0) {
    throw UsageError("thickness must be positive, tolerance and max_rounds non-negative");
  }
  if (F_cloth.cols() != 3 || F_body.cols() != 3) throw UsageError("faces must be #F by 3");
  s.options = options;
  s.F = F_cloth;
  s.cloth_vertices = F_cloth.size() ? F_cloth.maxCoeff() + 1 : 0;
  s.E = unique_edges(F_cloth);
  s.pinned.assign(static_cast<size_t>(s.cloth_vertices), 0);

  s.F_body = F_body;
  if (body_face_ids.empty()) {
    body_face_ids.resize(static_cast<size_t>(F_body.rows()));
    for (int f = 0; f < F_body.rows(); ++f) body_face_ids[static_cast<size_t>(f)] = f;
  }
  std::sort(body_face_ids.begin(), body_face_ids.end());
  body_face_ids.erase(std::unique(body_face_ids.begin(), body_face_ids.end()), body_face_ids.end());
  for (int f : body_face_ids) {
    if (f < 0 || f >= F_body.rows()) throw UsageError("body face id out of range");
  }
  s.body_faces = body_face_ids;
  s.body_vertex_count = F_body.size() ? F_body.maxCoeff() + 1 : 0;
  Eigen::MatrixXi culled(static_cast<Eigen::Index>(s.body_faces.size()), 3);
  for (size_t i = 0; i < s.body_faces.size(); ++i) culled.row(static_cast<Eigen::Index>(i)) = F_body.row(s.body_faces[i]);
  const Eigen::MatrixXi body_edges = unique_edges(culled);
  for (Eigen::Index e = 0; e < body_edges.rows(); ++e) s.body_edges.push_back({body_edges(e, 0), body_edges(e, 1)});
  std::vector<char> used(static_cast<size_t>(s.body_vertex_count), 0);
  for (int f : s.body_faces) {
    for (int k = 0; k < 3; ++k) used[static_cast<size_t>(F_body(f, k))] = 1;
  }
  for (int v = 0; v < s.body_vertex_count; ++v) {
    if (used[static_cast<size_t>(v)]) s.body_vertices.push_back(v);
  }
}

ContinuousContact::~ContinuousContact() = default;
ContinuousContact::ContinuousContact(ContinuousContact&&) noexcept = default;
ContinuousContact& ContinuousContact::operator=(ContinuousContact&&) noexcept = default;

void ContinuousContact::set_threads(int threads) {
  if (threads < 1) throw UsageError("threads must be at least 1");
  impl_->threads = threads;
}

void ContinuousContact::set_pinned(const std::vector<int>& ids) {
  Impl& s = *impl_;
  std::fill(s.pinned.begin(), s.pinned.end(), 0);
  for (int v : ids) {
    if (v < 0 || v >= s.cloth_vertices) throw UsageError("pinned vertex id out of range");
    s.pinned[static_cast<size_t>(v)] = 1;
  }
}

void ContinuousContact::set_body(const Eigen::MatrixXd& V_body) {
  Impl& s = *impl_;
  if (V_body.rows() < s.body_vertex_count || V_body.cols() != 3) {
    throw UsageError("body positions do not match the body faces");
  }
  for (int v : s.body_vertices) {
    if (!V_body.row(v).allFinite()) throw GeometryError("non-finite body vertex", "body vertex " + std::to_string(v));
  }
  if (!s.has_body) {
    double length = 0.0;
    for (const auto& e : s.body_edges) length += (V_body.row(e[0]) - V_body.row(e[1])).norm();
    s.mean_body_edge = length / std::max<size_t>(s.body_edges.size(), 1);
    s.sort_body_items(V_body);
    s.B_previous = V_body;
    s.Bs.setZero(V_body.rows(), 3);
    s.Be.setZero(V_body.rows(), 3);
  } else {
    s.B_previous.swap(s.B_current);
  }
  s.B_current = V_body;
  s.has_body = true;
  ++s.body_version;
}

void ContinuousContact::enforce(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end) {
  if (!(s_start >= 0.0 && s_start <= s_end && s_end <= 1.0)) throw UsageError("need 0 <= s_start <= s_end <= 1");
  impl_->enforce(X_start, X_end, s_start, s_end);
}

const ContinuousContactOptions& ContinuousContact::options() const { return impl_->options; }
const ContinuousContactStats& ContinuousContact::stats() const { return impl_->stats; }

}  // namespace gp::collision
