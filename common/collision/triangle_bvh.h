#pragma once
// A bounding volume hierarchy over a fixed list of moving triangles (the body's culled faces, see
// body_collider.h): exact closest points, first hits of rays and the triangles within a ball.
//
// The hierarchy is Embree's (Wald et al. 2014, "Embree: a kernel framework for efficient CPU ray
// tracing") over user primitives: it only culls conservatively grown boxes in single precision;
// distances and hits are computed in double precision by closest_point_on_triangle
// (mesh/point_triangle.h) and CGAL's ray-triangle intersection. The first set_corners() builds the
// tree, later ones refit its boxes. Answers depend on the triangles and the query alone: among
// exactly equal distances (or ray parameters) the lowest triangle index wins (collision/README.md,
// "The body's query engine").
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

class TriangleBvh {
 public:
  // A hierarchy over `triangles` triangles (at least one), indexed 0..triangles-1.
  explicit TriangleBvh(int triangles);
  ~TriangleBvh();
  TriangleBvh(const TriangleBvh&) = delete;
  TriangleBvh& operator=(const TriangleBvh&) = delete;

  // Corners of every triangle: #T by 9 (a, b, c; metres), finite. Builds the hierarchy the first
  // time, refits it after. Throws UsageError on a size mismatch, GeometryError on non-finite
  // corners.
  void set_corners(const Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>& corners);

  struct Closest {
    int triangle = -1;             // -1 only for an empty answer
    double squared_distance = 0.0;  // m^2, as closest_point_on_triangle gives it
  };
  // The triangle closest to p (finite; NumericalError otherwise): the smallest squared distance,
  // the lowest index among equal ones. `hint` (an index or -1) only speeds the search up.
  Closest closest(const Eigen::Vector3d& p, int hint = -1) const;

  struct Hit {
    int triangle = -1;  // -1: the ray leaves without a hit
    double t = 0.0;     // ray parameter of the first intersection point (CGAL's Ray_3/Triangle_3 intersection)
  };
  // The first triangle (smallest parameter, then lowest index) hit by the ray origin + t direction,
  // t >= 0, ignoring triangle `skip` (or -1) and triangles of zero area. Origin and direction
  // finite, direction non-zero (NumericalError otherwise).
  Hit first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, int skip = -1) const;

  // Indices (ascending) of the triangles within `radius` [m] of p.
  std::vector<int> within(const Eigen::Vector3d& p, double radius) const;

  int size() const;
  // Corners of triangle i (row i of the last set_corners).
  Eigen::Vector3d corner(int i, int k) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::collision
