#include "pattern/seam_allowance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/create_offset_polygons_2.h>

#include "core/error.h"

namespace gp {

double polygon_area(const Polygon2& polygon) {
  double a = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const auto& p = polygon[i];
    const auto& q = polygon[(i + 1) % polygon.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

double polygon_perimeter(const Polygon2& polygon) {
  double s = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) s += (polygon[(i + 1) % polygon.size()] - polygon[i]).norm();
  return s;
}

Polygon2 simplify_polygon(const Polygon2& polygon, double tolerance) {
  const size_t n = polygon.size();
  if (n <= 3 || tolerance <= 0.0) return polygon;
  // Split the closed polygon at vertex 0 and the vertex farthest from it,
  // then simplify both chains (Douglas and Peucker 1973).
  size_t far = 0;
  for (size_t i = 1; i < n; ++i)
    if ((polygon[i] - polygon[0]).squaredNorm() > (polygon[far] - polygon[0]).squaredNorm()) far = i;
  std::vector<char> keep(n, 0);
  keep[0] = keep[far] = 1;
  auto segment_distance = [](const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d ab = b - a;
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return (a + t * ab - p).norm();
  };
  std::vector<std::pair<size_t, size_t>> stack{{0, far}, {far, n}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j <= i + 1) continue;
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j % n];
    double best = -1.0;
    size_t best_k = i;
    for (size_t k = i + 1; k < j; ++k) {
      const double d = segment_distance(polygon[k], a, b);
      if (d > best) best = d, best_k = k;
    }
    if (best > tolerance) {
      keep[best_k] = 1;
      stack.push_back({i, best_k});
      stack.push_back({best_k, j});
    }
  }
  Polygon2 out;
  for (size_t i = 0; i < n; ++i)
    if (keep[i]) out.push_back(polygon[i]);
  if (out.size() < 3) return polygon;
  return out;
}

namespace {

// First pair of non-adjacent segments (i, i+1) and (j, j+1), i < j, that
// cross or touch, and the crossing point; false if the polygon is simple.
bool first_crossing(const Polygon2& P, size_t& si, size_t& sj, Eigen::Vector2d& x) {
  const size_t n = P.size();
  auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      const Eigen::Vector2d a = P[i], b = P[(i + 1) % n], c = P[j], d = P[(j + 1) % n];
      const Eigen::Vector2d r = b - a, q = d - c;
      const double den = cross(r, q);
      if (std::abs(den) <= 1e-300) {
        // Parallel: touching only if collinear and overlapping.
        if (std::abs(cross(c - a, r)) > 1e-18) continue;
        const double rr = r.squaredNorm();
        if (rr <= 0.0) continue;
        const double t0 = (c - a).dot(r) / rr, t1 = (d - a).dot(r) / rr;
        if (std::max(t0, t1) < 0.0 || std::min(t0, t1) > 1.0) continue;
        x = a + std::clamp(std::max(std::min(t0, t1), 0.0), 0.0, 1.0) * r;
      } else {
        const double t = cross(c - a, q) / den, u = cross(c - a, r) / den;
        if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) continue;
        x = a + t * r;
      }
      si = i;
      sj = j;
      return true;
    }
  return false;
}

// Cuts off the loops of a self-crossing outline (each time the part with
// less area goes), which removes dart sides that cross or touch.
Polygon2 remove_loops(Polygon2 P) {
  size_t i = 0, j = 0;
  Eigen::Vector2d x;
  for (int guard = 0; guard < 1000 && P.size() > 3 && first_crossing(P, i, j, x); ++guard) {
    Polygon2 inner{x}, outer;
    for (size_t k = i + 1; k <= j; ++k) inner.push_back(P[k]);
    for (size_t k = 0; k <= i; ++k) outer.push_back(P[k]);
    outer.push_back(x);
    for (size_t k = j + 1; k < P.size(); ++k) outer.push_back(P[k]);
    P = std::abs(polygon_area(inner)) > std::abs(polygon_area(outer)) ? inner : outer;
    // Drop repeated points left by the cut.
    Polygon2 clean;
    for (const auto& p : P)
      if (clean.empty() || (p - clean.back()).norm() > 1e-12) clean.push_back(p);
    while (clean.size() > 1 && (clean.front() - clean.back()).norm() <= 1e-12) clean.pop_back();
    P = clean;
  }
  return P;
}

}  // namespace

std::vector<Polygon2> offset_polygon(const Polygon2& polygon, double distance, double simplify_tolerance,
                                     const std::string& what) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto to_cgal = [](const Polygon2& in) {
    CGAL::Polygon_2<K> out;
    for (const auto& p : in) out.push_back(K::Point_2(p.x(), p.y()));
    return out;
  };
  // Simplification can make a narrow outline touch itself; then the outline
  // is offset as it is.
  CGAL::Polygon_2<K> poly = to_cgal(simplify_polygon(polygon, simplify_tolerance));
  if (!poly.is_simple()) poly = to_cgal(polygon);
  if (!poly.is_simple()) poly = to_cgal(simplify_polygon(remove_loops(polygon), simplify_tolerance));
  if (!poly.is_simple())
    throw GeometryError("the outline of the piece is not a simple polygon, no seam allowance can be drawn", what);
  if (poly.orientation() != CGAL::COUNTERCLOCKWISE) poly.reverse_orientation();
  const auto offsets = CGAL::create_exterior_skeleton_and_offset_polygons_2(distance, poly, K());
  // The exterior skeleton is built inside a bounding frame whose offset comes
  // back as the largest polygon; the others are the offset outlines.
  std::vector<Polygon2> result;
  double frame_area = 0.0;
  size_t frame = offsets.size();
  for (size_t i = 0; i < offsets.size(); ++i) {
    const double a = std::abs(CGAL::to_double(offsets[i]->area()));
    if (frame == offsets.size() || a > frame_area) frame_area = a, frame = i;
  }
  for (size_t i = 0; i < offsets.size(); ++i) {
    if (i == frame) continue;
    Polygon2 out;
    for (auto it = offsets[i]->vertices_begin(); it != offsets[i]->vertices_end(); ++it)
      out.emplace_back(CGAL::to_double(it->x()), CGAL::to_double(it->y()));
    if (polygon_area(out) < 0.0) std::reverse(out.begin(), out.end());
    result.push_back(out);
  }
  if (result.empty()) throw GeometryError("the seam allowance of the piece could not be built", what);
  // Mitre limit: at an acute corner the mitred offset reaches far beyond the
  // allowance (distance / sin(angle / 2)); such a corner is bevelled at twice
  // the allowance, as a tailor clips it.
  const double limit = 2.0 * distance;
  auto outline_distance = [&](const Eigen::Vector2d& q) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d a = polygon[i], b = polygon[(i + 1) % polygon.size()];
      const Eigen::Vector2d ab = b - a;
      const double l2 = ab.squaredNorm();
      const double t = l2 > 0.0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
      best = std::min(best, (a + t * ab - q).norm());
    }
    return best;
  };
  // Every run of offset vertices beyond the limit is replaced by the two
  // points where the offset enters and leaves the limit, found by bisection
  // along the run's first and last edges: the bevel lies within the limit
  // however sharp the corner (moving a far vertex part of the way towards
  // its neighbours left a spike where two far vertices followed each other).
  auto limit_point = [&](const Eigen::Vector2d& near, const Eigen::Vector2d& far) {
    double lo = 0.0, hi = 1.0;  // near + lo (far - near) is within the limit, near + hi (...) beyond it
    for (int it = 0; it < 50; ++it) {
      const double mid = 0.5 * (lo + hi);
      (outline_distance(near + mid * (far - near)) <= limit ? lo : hi) = mid;
    }
    return Eigen::Vector2d(near + lo * (far - near));
  };
  for (Polygon2& offset : result) {
    const size_t n = offset.size();
    std::vector<char> far(n, 0);
    size_t near_count = 0;
    for (size_t i = 0; i < n; ++i) {
      far[i] = outline_distance(offset[i]) > limit * 1.0001;
      near_count += far[i] ? 0 : 1;
    }
    if (near_count == 0 || near_count == n) continue;
    // Start at a near vertex, so that every run of far vertices is whole.
    size_t start = 0;
    while (far[start]) ++start;
    Polygon2 clipped;
    for (size_t k = 0; k < n; ++k) {
      const size_t i = (start + k) % n;
      if (!far[i]) {
        clipped.push_back(offset[i]);
        continue;
      }
      size_t last = i;  // the run of far vertices i .. last
      while (far[(last + 1) % n]) last = (last + 1) % n;
      const Eigen::Vector2d& before = offset[(i + n - 1) % n];
      const Eigen::Vector2d& after = offset[(last + 1) % n];
      clipped.push_back(limit_point(before, offset[i]));
      clipped.push_back(limit_point(after, offset[last]));
      k += (last + n - i) % n;
    }
    offset = clipped;
  }
  // Largest first, so that result.front() is the piece's cutting line.
  std::stable_sort(result.begin(), result.end(),
                   [](const Polygon2& a, const Polygon2& b) { return polygon_area(a) > polygon_area(b); });
  return result;
}

}  // namespace gp
