#include "mesh/point_triangle.h"

#include <algorithm>
#include <cmath>

namespace gp {
namespace {

using Feature = TriangleFeature;

TriangleClosestPoint at_corner(const Eigen::Vector3d& x, int k) {
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  bary(k) = 1.0;
  return {x, bary, static_cast<Feature>(k)};
}

// The point is computed from the edge's start (as the collision code has always
// done), the barycentric coordinates from the parameter t.
TriangleClosestPoint on_edge(const Eigen::Vector3d& x, double t, int k) {
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
  bary(k) = 1.0 - t;
  bary((k + 1) % 3) = t;
  return {x, bary, static_cast<Feature>(3 + k)};
}

// Closest point of the segment from corner k (at a) to corner k + 1 (at b).
TriangleClosestPoint closest_on_edge(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                     const Eigen::Vector3d& b, int k) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(ab.dot(p - a) / len2, 0.0, 1.0) : 0.0;
  if (t <= 0.0) return at_corner(a, k);
  if (t >= 1.0) return at_corner(b, (k + 1) % 3);
  return on_edge(a + t * ab, t, k);
}

}  // namespace

TriangleClosestPoint closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return at_corner(a, 0);
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return at_corner(b, 1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return on_edge(a + v * ab, v, 0);
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return at_corner(c, 2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);  // from a towards c
    return {a + w * ac, Eigen::Vector3d(1.0 - w, 0.0, w), Feature::edge2};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return on_edge(b + w * (c - b), w, 1);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0) || !std::isfinite(sum)) {
    // No interior: the closest of the three edges.
    TriangleClosestPoint best = closest_on_edge(p, a, b, 0);
    for (const TriangleClosestPoint& e : {closest_on_edge(p, b, c, 1), closest_on_edge(p, c, a, 2)})
      if ((p - e.point).squaredNorm() < (p - best.point).squaredNorm()) best = e;
    return best;
  }
  const double inverse = 1.0 / sum;
  const double v = vb / sum, w = vc / sum;
  return {a + ab * (vb * inverse) + ac * (vc * inverse), Eigen::Vector3d(1.0 - v - w, v, w),
          Feature::interior};
}

}  // namespace gp
