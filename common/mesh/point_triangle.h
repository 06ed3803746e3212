#pragma once
// The closest point of a triangle to a point, with the feature it lies on
// (Ericson, "Real-Time Collision Detection", 2005, section 5.1.5: the point's
// Voronoi region among the corners, edges and interior of the triangle).
#include <Eigen/Core>

namespace gp {

// Corners k = 0, 1, 2 are a, b, c; edge k runs from corner k to corner k + 1
// (mod 3): edge0 = ab, edge1 = bc, edge2 = ca.
enum class TriangleFeature { corner0, corner1, corner2, edge0, edge1, edge2, interior };

inline bool is_corner(TriangleFeature f) { return f <= TriangleFeature::corner2; }
inline bool is_edge(TriangleFeature f) { return f >= TriangleFeature::edge0 && f <= TriangleFeature::edge2; }
// k of corner k or edge k (0..2); meaningless for the interior.
inline int feature_index(TriangleFeature f) { return static_cast<int>(f) % 3; }

struct TriangleClosestPoint {
  Eigen::Vector3d point;  // the closest point (units of the input)
  Eigen::Vector3d bary;   // its barycentric coordinates: non-negative, summing to 1
  TriangleFeature feature;
};

// A degenerate triangle (collinear or coincident corners; no interior) answers
// with the closest point of its three edges, the first edge among equal ones.
// Non-finite input gives non-finite coordinates.
TriangleClosestPoint closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace gp
