#include "garment/surface_point.h"

#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "core/error.h"
#include "mesh/point_triangle.h"

namespace gp {

Eigen::Vector3d evaluate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const SurfacePoint& p) {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) x += p.bary[k] * V.row(F(p.face, k)).transpose();
  return x;
}

Eigen::Vector3d evaluate_normal(const Eigen::MatrixXd& N, const Eigen::MatrixXi& F,
                                const SurfacePoint& p) {
  Eigen::Vector3d n = evaluate(N, F, p);
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : n;
}

SurfacePoint closest_point_in_face(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int face,
                                   const Eigen::Vector3d& x) {
  const Eigen::Vector3d a = V.row(F(face, 0)), b = V.row(F(face, 1)), c = V.row(F(face, 2));
  SurfacePoint sp;
  sp.face = face;
  sp.bary = closest_point_on_triangle(x, a, b, c).bary;
  return sp;
}

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
}  // namespace

struct SurfaceLocator::Impl {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  std::vector<Triangle> triangles;
  Tree tree;
};

SurfaceLocator::SurfaceLocator(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F)
    : impl_(std::make_unique<Impl>()) {
  if (F.rows() == 0) throw GeometryError("cannot locate points on a mesh without triangles");
  impl_->V = V;
  impl_->F = F;
  impl_->triangles.reserve(static_cast<size_t>(F.rows()));
  auto point = [&](int v) { return Kernel::Point_3(V(v, 0), V(v, 1), V(v, 2)); };
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    impl_->triangles.emplace_back(point(F(f, 0)), point(F(f, 1)), point(F(f, 2)));
  impl_->tree.insert(impl_->triangles.cbegin(), impl_->triangles.cend());
  impl_->tree.build();
  impl_->tree.accelerate_distance_queries();
}

SurfaceLocator::~SurfaceLocator() = default;

const Eigen::MatrixXd& SurfaceLocator::V() const { return impl_->V; }
const Eigen::MatrixXi& SurfaceLocator::F() const { return impl_->F; }

SurfaceLocator::Hit SurfaceLocator::closest(const Eigen::Vector3d& x) const {
  const auto result = impl_->tree.closest_point_and_primitive(Kernel::Point_3(x[0], x[1], x[2]));
  const int face = static_cast<int>(result.second - impl_->triangles.cbegin());
  // CGAL gives the point; the barycentric coordinates come from the same
  // closest-point construction on that face, which keeps them in the triangle.
  Hit hit;
  hit.at = closest_point_in_face(impl_->V, impl_->F, face, x);
  hit.point = evaluate(impl_->V, impl_->F, hit.at);
  hit.distance = (x - hit.point).norm();
  return hit;
}

}  // namespace gp
