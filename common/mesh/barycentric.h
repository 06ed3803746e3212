#pragma once
// Barycentric coordinates of a point in the plane of a triangle: in space, and in the plane
// (clamped into the triangle), with the plane's orientation predicate they rest on.
#include <Eigen/Core>

namespace gp {

// The coordinates (wa, wb, wc), summing to 1, of x projected into the plane
// of the triangle a, b, c (least squares over the triangle's two edges;
// Ericson, "Real-Time Collision Detection", 2005, section 3.4). A degenerate
// triangle (its Gram determinant not positive) gives (1, 0, 0): its first
// corner.
inline Eigen::Vector3d barycentric(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, d = x - a;
  const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
  const double d1 = e1.dot(d), d2 = e2.dot(d);
  const double det = d11 * d22 - d12 * d12;
  if (!(det > 0.0)) return Eigen::Vector3d(1.0, 0.0, 0.0);
  const double u = (d22 * d1 - d12 * d2) / det;
  const double v = (d11 * d2 - d12 * d1) / det;
  return Eigen::Vector3d(1.0 - u - v, u, v);
}

// Twice the signed area of the plane triangle a, b, c: positive counter-clockwise, 0 where the
// three are collinear (the orientation predicate, in floating point).
inline double orient_2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}

// The coordinates (wa, wb, wc) of a point q of the plane against the triangle a, b, c of the plane,
// clamped into the triangle (negative ones set to 0, then normalised): the ratios of the signed
// areas of the sub-triangles q b c, a q c, a b q to a b c's. A degenerate triangle (zero area) uses
// the sub-triangles' areas unscaled; where all vanish, the centroid (1/3, 1/3, 1/3).
inline Eigen::Vector3d clamped_barycentric_2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                              const Eigen::Vector2d& c, const Eigen::Vector2d& q) {
  const double area = orient_2d(a, b, c);
  Eigen::Vector3d w(orient_2d(b, c, q), orient_2d(c, a, q), orient_2d(a, b, q));
  if (area != 0.0) w /= area;
  w = w.cwiseMax(0.0);
  const double s = w.sum();
  return s > 0.0 ? Eigen::Vector3d(w / s) : Eigen::Vector3d(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
}

}  // namespace gp
