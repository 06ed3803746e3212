#include "marker/nest_marker.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/error.h"

namespace gp {
namespace {

using Interval = std::pair<int, int>;  // cells, inclusive

// A piece in one orientation, rasterised with its lower left corner at the
// origin: per row of cells, the disjoint runs of cells it touches.
struct Shape {
  int piece = -1;
  bool mirrored = false;
  int rotation = 0;
  std::vector<Eigen::Vector2d> outline;  // lower left corner of its box at the origin
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();  // oriented outline + shift = outline
  int w = 0, h = 0;                      // cells
  std::vector<std::vector<Interval>> rows;
};

std::vector<Interval> merge(std::vector<Interval> v) {
  std::sort(v.begin(), v.end());
  std::vector<Interval> out;
  for (const Interval& i : v) {
    if (!out.empty() && i.first <= out.back().second + 1) out.back().second = std::max(out.back().second, i.second);
    else out.push_back(i);
  }
  return out;
}

// Conservative raster: the band [y0, y1] of the polygon projects onto x as
// the union of its edges clipped to the band and its inside spans along the
// band's two lines (each piece of the polygon inside the band is bounded by
// those); every cell whose open interval meets that projection is taken.
Shape rasterise(const std::vector<Eigen::Vector2d>& poly, double res) {
  Shape s;
  double xmax = 0.0, ymax = 0.0;
  for (const auto& p : poly) xmax = std::max(xmax, p.x()), ymax = std::max(ymax, p.y());
  s.w = std::max(1, static_cast<int>(std::ceil(xmax / res - 1e-9)));
  s.h = std::max(1, static_cast<int>(std::ceil(ymax / res - 1e-9)));
  s.rows.resize(static_cast<size_t>(s.h));
  const size_t n = poly.size();
  auto spans_at = [&](double y, std::vector<std::pair<double, double>>& out) {
    std::vector<double> xs;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2d& a = poly[i];
      const Eigen::Vector2d& b = poly[(i + 1) % n];
      if ((a.y() > y) != (b.y() > y)) xs.push_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
    }
    std::sort(xs.begin(), xs.end());
    for (size_t k = 0; k + 1 < xs.size(); k += 2) out.emplace_back(xs[k], xs[k + 1]);
  };
  for (int j = 0; j < s.h; ++j) {
    const double y0 = j * res, y1 = (j + 1) * res;
    std::vector<std::pair<double, double>> proj;
    for (size_t i = 0; i < n; ++i) {
      Eigen::Vector2d a = poly[i], b = poly[(i + 1) % n];
      if (std::max(a.y(), b.y()) < y0 || std::min(a.y(), b.y()) > y1) continue;
      if (a.y() > b.y()) std::swap(a, b);
      auto at = [&](double y) { return b.y() == a.y() ? a.x() : a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()); };
      const double xa = a.y() < y0 ? at(y0) : a.x(), xb = b.y() > y1 ? at(y1) : b.x();
      proj.emplace_back(std::min(xa, xb), std::max(xa, xb));
    }
    const double eps = 1e-9 * res;
    spans_at(y0 + eps, proj);
    spans_at(y1 - eps, proj);
    std::vector<Interval> cells;
    for (const auto& [a, b] : proj) {
      const int k0 = std::max(0, static_cast<int>(std::floor(a / res + 1e-9)));
      const int k1 = std::min(s.w - 1, std::max(k0, static_cast<int>(std::ceil(b / res - 1e-9)) - 1));
      cells.emplace_back(k0, k1);
    }
    s.rows[static_cast<size_t>(j)] = merge(cells);
  }
  return s;
}

// The marker's occupied cells: per row, disjoint sorted runs.
class Occupancy {
 public:
  explicit Occupancy(int rows) : rows_(static_cast<size_t>(rows)) {}
  // The first run of row r meeting [a, b], or nullptr.
  const Interval* conflict(int r, int a, int b, long long& work) const {
    ++work;
    const auto& row = rows_[static_cast<size_t>(r)];
    auto it = std::lower_bound(row.begin(), row.end(), a, [](const Interval& i, int v) { return i.second < v; });
    if (it != row.end() && it->first <= b) return &*it;
    return nullptr;
  }
  void add(int r, int a, int b) {
    auto& row = rows_[static_cast<size_t>(r)];
    auto it = std::lower_bound(row.begin(), row.end(), Interval{a, b});
    row.insert(it, Interval{a, b});
    // Merge neighbours that touch.
    std::vector<Interval> merged;
    for (const Interval& i : row) {
      if (!merged.empty() && i.first <= merged.back().second + 1) merged.back().second = std::max(merged.back().second, i.second);
      else merged.push_back(i);
    }
    row.swap(merged);
  }

 private:
  std::vector<std::vector<Interval>> rows_;
};

struct Copy {
  int piece = 0, copy = 0;
  bool mirrored = false;
  std::vector<int> shapes;  // indices into the shape table
  double area = 0.0;
};

struct Placed {
  int shape = -1, x = 0, y = 0;
};

// Bottom-left fill of the copies in `order`. Returns the length in cells;
// stops early (returns a value > cutoff) once the marker is longer than `cutoff`.
int fill(const std::vector<Copy>& copies, const std::vector<int>& order, const std::vector<Shape>& shapes, int rows,
         int cutoff, long long& work, std::vector<Placed>* placed) {
  Occupancy occ(rows);
  int length = 0;
  if (placed) placed->clear();
  for (int c : order) {
    const Copy& copy = copies[static_cast<size_t>(c)];
    Placed best;
    long best_key = std::numeric_limits<long>::max();
    for (int si : copy.shapes) {
      const Shape& s = shapes[static_cast<size_t>(si)];
      for (int y = 0; y + s.h <= rows; ++y) {
        int x = 0;
        bool moved = true;
        while (moved) {
          moved = false;
          // Nothing right of here can beat the best placement found.
          if (static_cast<long>(x + s.w) * 4096 * 4096 >= best_key) break;
          for (int k = 0; k < s.h && !moved; ++k)
            for (const Interval& i : s.rows[static_cast<size_t>(k)]) {
              if (const Interval* hit = occ.conflict(y + k, x + i.first, x + i.second, work)) {
                x = hit->second + 1 - i.first;
                moved = true;
                break;
              }
            }
        }
        if (moved) continue;
        const long key = (static_cast<long>(x + s.w) * 4096 + x) * 4096 + y;
        if (key < best_key) best_key = key, best = {si, x, y};
      }
    }
    if (best.shape < 0) return std::numeric_limits<int>::max();
    const Shape& s = shapes[static_cast<size_t>(best.shape)];
    for (int k = 0; k < s.h; ++k)
      for (const Interval& i : s.rows[static_cast<size_t>(k)]) occ.add(best.y + k, best.x + i.first, best.x + i.second);
    length = std::max(length, best.x + s.w);
    if (placed) placed->push_back(best);
    if (length > cutoff) return length;
  }
  return length;
}

// A small deterministic generator (SplitMix64), so that the search does not
// depend on the standard library's distributions.
struct Rng {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  int below(int n) { return static_cast<int>(next() % static_cast<uint64_t>(n)); }
};

}  // namespace

std::vector<Eigen::Vector2d> oriented_outline(const std::vector<Eigen::Vector2d>& outline, bool mirrored, int rotation) {
  std::vector<Eigen::Vector2d> out;
  const int r = ((rotation % 360) + 360) % 360;
  for (Eigen::Vector2d p : outline) {
    if (mirrored) p.y() = -p.y();
    // Exact quarter turns: no rounding from cos and sin.
    Eigen::Vector2d q = p;
    if (r == 90) q = {-p.y(), p.x()};
    if (r == 180) q = {-p.x(), -p.y()};
    if (r == 270) q = {p.y(), -p.x()};
    out.push_back(q);
  }
  if (mirrored) std::reverse(out.begin(), out.end());  // keep the orientation of the outline
  return out;
}

bool polygons_overlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b, double tol) {
  auto orient = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
  };
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j) {
      const Eigen::Vector2d &p = a[i], &q = a[(i + 1) % a.size()], &r = b[j], &s = b[(j + 1) % b.size()];
      const double sc = tol * std::max((q - p).norm(), (s - r).norm());
      const double o1 = orient(p, q, r), o2 = orient(p, q, s), o3 = orient(r, s, p), o4 = orient(r, s, q);
      if (((o1 > sc && o2 < -sc) || (o1 < -sc && o2 > sc)) && ((o3 > sc && o4 < -sc) || (o3 < -sc && o4 > sc))) return true;
    }
  // A vertex strictly inside the other polygon, farther than tol from its outline.
  auto inside = [&](const Eigen::Vector2d& q, const std::vector<Eigen::Vector2d>& poly) {
    bool in = false;
    double d = std::numeric_limits<double>::max();
    for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
      const Eigen::Vector2d &u = poly[i], &v = poly[j];
      if ((u.y() > q.y()) != (v.y() > q.y()) && q.x() < (v.x() - u.x()) * (q.y() - u.y()) / (v.y() - u.y()) + u.x()) in = !in;
      const Eigen::Vector2d e = v - u;
      const double t = std::clamp((q - u).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
      d = std::min(d, (u + t * e - q).norm());
    }
    return in && d > tol;
  };
  for (const auto& q : a)
    if (inside(q, b)) return true;
  for (const auto& q : b)
    if (inside(q, a)) return true;
  // Identical or nested polygons with no vertex strictly inside: their centroids.
  Eigen::Vector2d ca = Eigen::Vector2d::Zero(), cb = Eigen::Vector2d::Zero();
  for (const auto& q : a) ca += q / static_cast<double>(a.size());
  for (const auto& q : b) cb += q / static_cast<double>(b.size());
  return (ca - cb).norm() < tol && std::abs(signed_area(a)) > 0.0;
}

MarkerResult nest_marker(const MarkerPieces& input, const NestOptions& o) {
  MarkerResult result;
  result.width = o.width;
  const double res = o.resolution > 0.0 ? o.resolution : o.width / 300.0;
  result.resolution = res;
  const int rows = static_cast<int>(std::floor(o.width / res + 1e-9));
  std::vector<Shape> shapes;
  std::vector<Copy> copies;
  for (size_t pi = 0; pi < input.pieces.size(); ++pi) {
    const MarkerPiece& p = input.pieces[pi];
    const double area = std::abs(signed_area(p.outline));
    // Shapes for the plain and (for pairs) the mirrored copies.
    std::vector<int> plain_shapes, mirrored_shapes;
    for (int mirrored = 0; mirrored < (p.mirrored_pairs ? 2 : 1); ++mirrored)
      for (int rot : p.orientations) {
        std::vector<Eigen::Vector2d> q = oriented_outline(p.outline, mirrored != 0, rot);
        Eigen::Vector2d lo = q.front();
        for (const auto& v : q) lo = lo.cwiseMin(v);
        for (auto& v : q) v -= lo;
        Shape s = rasterise(q, res);
        s.piece = static_cast<int>(pi);
        s.mirrored = mirrored != 0;
        s.rotation = rot;
        s.outline = q;
        s.shift = -lo;
        if (s.h > rows) continue;  // wider than the fabric this way
        (mirrored ? mirrored_shapes : plain_shapes).push_back(static_cast<int>(shapes.size()));
        shapes.push_back(std::move(s));
      }
    if (plain_shapes.empty() || (p.mirrored_pairs && mirrored_shapes.empty()))
      throw GeometryError("piece '" + p.name + "' is wider than the fabric in every allowed orientation",
                          "fabric width " + std::to_string(o.width));
    for (int c = 0; c < p.quantity; ++c) {
      Copy copy;
      copy.piece = static_cast<int>(pi);
      copy.copy = c;
      copy.mirrored = p.mirrored_pairs && c % 2 == 1;
      copy.shapes = copy.mirrored ? mirrored_shapes : plain_shapes;
      copy.area = area;
      copies.push_back(copy);
      result.piece_area += area;
    }
  }
  // Largest first (ties by piece and copy), then the local search.
  std::vector<int> order(copies.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return copies[a].area > copies[b].area; });
  long long work = 0;
  int best = fill(copies, order, shapes, rows, std::numeric_limits<int>::max(), work, nullptr);
  result.first_length = best * res;
  result.evaluations = 1;
  std::vector<int> best_order = order;
  const long long budget = static_cast<long long>(o.budget_s * kWorkPerSecond);
  Rng rng{o.seed * 0x2545f4914f6cdd1dULL + 1};
  const int n = static_cast<int>(order.size());
  while (n > 1 && work < budget) {
    std::vector<int> trial = best_order;
    const int i = rng.below(n), j = rng.below(n);
    if (i == j) continue;
    if (rng.below(2) == 0) {
      std::swap(trial[static_cast<size_t>(i)], trial[static_cast<size_t>(j)]);
    } else {
      const int v = trial[static_cast<size_t>(i)];
      trial.erase(trial.begin() + i);
      trial.insert(trial.begin() + j, v);
    }
    const int len = fill(copies, trial, shapes, rows, best, work, nullptr);
    ++result.evaluations;
    if (len <= best) best = len, best_order = trial;
  }
  std::vector<Placed> placed;
  fill(copies, best_order, shapes, rows, std::numeric_limits<int>::max(), work, &placed);
  result.work = work;
  double length = 0.0;
  for (size_t k = 0; k < placed.size(); ++k) {
    const Copy& c = copies[static_cast<size_t>(best_order[k])];
    const Shape& s = shapes[static_cast<size_t>(placed[k].shape)];
    Placement p;
    p.piece = c.piece;
    p.copy = c.copy;
    p.mirrored = s.mirrored;
    p.rotation = s.rotation;
    const Eigen::Vector2d at(placed[k].x * res, placed[k].y * res);
    p.offset = s.shift + at;
    for (const auto& v : s.outline) {
      p.outline.push_back(v + at);
      length = std::max(length, v.x() + at.x());
    }
    result.placements.push_back(std::move(p));
  }
  result.length = length;
  result.utilisation = length > 0.0 ? result.piece_area / (o.width * length) : 0.0;
  return result;
}

}  // namespace gp
