#pragma once
// Exact segment queries against fixed triangles, for checks that must not
// miss or invent an intersection (crossings.h): a CGAL AABB tree culls, and
// CGAL's Epick predicates decide. Closed sets, so touching counts; degenerate
// triangles and segments are decided as the segments or points they are.
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

// Whether the closed segment [a, b] meets the closed triangle (p, q, r),
// exactly. Any of them may be degenerate. Inputs must be finite.
bool segment_meets_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                            const Eigen::Vector3d& q, const Eigen::Vector3d& r);

// Parameter t in [0, 1] of a point a + t (b - a) where the segment meets the
// plane of triangle (p, q, r) (rounded; 0 when the segment lies in the plane
// or the triangle is degenerate). For measuring depths, not for deciding.
double segment_plane_parameter(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                               const Eigen::Vector3d& q, const Eigen::Vector3d& r);

class TriangleTree {
 public:
  // Triangles `face_ids` (rows of F, empty: all) of the mesh V (#V by 3),
  // F (#F by 3). Throws GeometryError naming the vertex for non-finite
  // coordinates of a used vertex, UsageError for ids out of range.
  TriangleTree(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& face_ids = {});
  ~TriangleTree();
  TriangleTree(TriangleTree&&) noexcept;
  TriangleTree& operator=(TriangleTree&&) noexcept;

  // Face ids (ascending) whose triangle meets the closed segment [a, b].
  // a and b must be finite (UsageError otherwise).
  std::vector<int> segment_faces(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;

  // Face ids (ascending) whose triangle meets the box [lo, hi] (a degenerate
  // triangle: whose bounding box does).
  std::vector<int> box_faces(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;

  // Number of triangles held (degenerate ones included).
  int size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::collision
