#include "garment/surface_point.h"

#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "core/error.h"

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
  // Closest point of a triangle by region classification (Ericson, Real-Time
  // Collision Detection, 5.1.5), returned as barycentric coordinates.
  const Eigen::Vector3d a = V.row(F(face, 0)), b = V.row(F(face, 1)), c = V.row(F(face, 2));
  SurfacePoint sp;
  sp.face = face;
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = x - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) { sp.bary = {1, 0, 0}; return sp; }
  const Eigen::Vector3d bp = x - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) { sp.bary = {0, 1, 0}; return sp; }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    sp.bary = {1 - v, v, 0};
    return sp;
  }
  const Eigen::Vector3d cp = x - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) { sp.bary = {0, 0, 1}; return sp; }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    sp.bary = {1 - w, 0, w};
    return sp;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    sp.bary = {0, 1 - w, w};
    return sp;
  }
  const double denom = va + vb + vc;
  if (!(denom > 0)) {  // degenerate triangle: fall back to its first corner
    sp.bary = {1, 0, 0};
    return sp;
  }
  const double v = vb / denom, w = vc / denom;
  sp.bary = {1 - v - w, v, w};
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
