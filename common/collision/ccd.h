#pragma once
// Continuous collision detection of linearly moving primitives over one time
// step, t in [0, 1] (Provot 1997, "Collision and self-collision handling in
// cloth model dedicated to design garments"; Bridson, Fedkiw & Anderson 2002,
// "Robust treatment of collisions, contact and friction for cloth animation",
// sec. 6): a point and a triangle, or two edges, can only meet at a time when
// their four points are coplanar, a root of the cubic
//   f(t) = ((b - a) x (c - a)) . (p - a)      point p, triangle (a, b, c)
//   f(t) = ((b - a) x (d - c)) . (c - a)      edges (a, b) and (c, d)
// with every point moving as x(t) = x0 + t (x1 - x0). The roots in [0, 1] are
// isolated between the cubic's extrema and refined by bisection; at each, in
// time order, the primitives meet when their distance is at most `tolerance`
// [m] (which absorbs the rounding of the root).
//
// `side` is the sign of f just before the hit: the side of the triangle's
// plane (normal (b - a) x (c - a)) the point came from, or the side of the
// first edge's line the second came from along (b - a) x (d - c). A hit at
// t = 0 (touching at the start) has the sign of f just after it.
#include <optional>

#include <Eigen/Core>

namespace gp::collision {

struct PointTriangleHit {
  double t = 0.0;                                         // time of contact in [0, 1]
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();      // barycentric coordinates of the contact on (a, b, c)
  int side = 0;                                           // +1 / -1, see above (0: undecided, f vanishes)
};

struct EdgeEdgeHit {
  double t = 0.0;
  double s = 0.0;   // contact at a + s (b - a) on the first edge
  double u = 0.0;   // and at c + u (d - c) on the second
  int side = 0;
};

// Point p against triangle (a, b, c); suffix 0 at t = 0, 1 at t = 1.
std::optional<PointTriangleHit> point_triangle_ccd(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                                   const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                                   const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                                                   const Eigen::Vector3d& c0, const Eigen::Vector3d& c1,
                                                   double tolerance);

// Edge (a, b) against edge (c, d).
std::optional<EdgeEdgeHit> edge_edge_ccd(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                                         const Eigen::Vector3d& b0, const Eigen::Vector3d& b1,
                                         const Eigen::Vector3d& c0, const Eigen::Vector3d& c1,
                                         const Eigen::Vector3d& d0, const Eigen::Vector3d& d1, double tolerance);

// Closest point of triangle (a, b, c) to p as barycentric weights (Ericson,
// "Real-Time Collision Detection", 5.1.5); degenerate triangles allowed.
Eigen::Vector3d closest_triangle_weights(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, const Eigen::Vector3d& c);

// Closest points of segments (a, b) and (c, d): parameters s, u in [0, 1]
// (Ericson 5.1.9); degenerate segments allowed.
void closest_segment_parameters(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                const Eigen::Vector3d& d, double& s, double& u);

}  // namespace gp::collision
