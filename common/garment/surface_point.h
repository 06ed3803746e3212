#pragma once
// Points on a triangle mesh stored as face id + barycentric coordinates, so
// that the same body point can be evaluated in every registered pose, and a
// closest-point locator (CGAL AABB tree) that snaps 3D points to a mesh.
#include <memory>
#include <Eigen/Core>

namespace gp {

// A point on face `face` of a mesh: sum_k bary[k] * V.row(F(face, k)).
// bary sums to 1 and is non-negative for points inside the triangle.
struct SurfacePoint {
  int face = -1;
  Eigen::Vector3d bary = Eigen::Vector3d::Zero();
};

// Position of `p` on the mesh (V #V by 3, F #F by 3).
Eigen::Vector3d evaluate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const SurfacePoint& p);

// Unit normal at `p` interpolated from per-vertex normals N (#V by 3, e.g.
// gp::vertex_normals): the "body normal field" used for comfort offsets and
// for evaluating boundary bindings.
Eigen::Vector3d evaluate_normal(const Eigen::MatrixXd& N, const Eigen::MatrixXi& F,
                                const SurfacePoint& p);

// Barycentric coordinates of the projection of `x` onto the plane of face
// `face`, clamped to the triangle (closest point of the triangle to x; a
// degenerate face answers with its closest edge).
SurfacePoint closest_point_in_face(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int face,
                                   const Eigen::Vector3d& x);

// Closest points on a fixed triangle mesh (CGAL AABB tree over its faces).
// Built once, queried many times; queries are thread-safe and deterministic.
class SurfaceLocator {
 public:
  struct Hit {
    SurfacePoint at;             // closest point as face + barycentric coordinates
    Eigen::Vector3d point;       // its position (metres)
    double distance = 0.0;       // |x - point|
  };
  // Keeps copies of V (#V by 3) and F (#F by 3). F must not be empty.
  SurfaceLocator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);
  ~SurfaceLocator();
  SurfaceLocator(const SurfaceLocator&) = delete;
  SurfaceLocator& operator=(const SurfaceLocator&) = delete;

  Hit closest(const Eigen::Vector3d& x) const;
  const Eigen::MatrixXd& V() const;
  const Eigen::MatrixXi& F() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp
