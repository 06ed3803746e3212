#pragma once
// Barycentric coordinates of a point in the plane of a triangle.
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

}  // namespace gp
