#include "collision/triangle_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <string>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Geometry>

#include "core/error.h"

namespace gp::collision {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point to_point(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }

// Closed segments, either possibly a point, exactly.
bool segments_meet(const Point& a, const Point& b, const Point& c, const Point& d) {
  const bool first_point = a == b, second_point = c == d;
  if (first_point && second_point) return a == c;
  if (first_point) return Segment(c, d).has_on(a);
  if (second_point) return Segment(a, b).has_on(c);
  return CGAL::do_intersect(Segment(a, b), Segment(c, d));
}

bool meets(const Point& a, const Point& b, const Point& p, const Point& q, const Point& r) {
  if (CGAL::collinear(p, q, r)) {
    // The triangle is a segment (or a point): the union of its three sides.
    return segments_meet(a, b, p, q) || segments_meet(a, b, q, r) || segments_meet(a, b, r, p);
  }
  const Triangle t(p, q, r);
  if (a == b) return t.has_on(a);
  return CGAL::do_intersect(t, Segment(a, b));
}

}  // namespace

bool segment_meets_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                            const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  if (!a.allFinite() || !b.allFinite() || !p.allFinite() || !q.allFinite() || !r.allFinite()) {
    throw UsageError("segment_meets_triangle needs finite coordinates");
  }
  return meets(to_point(a), to_point(b), to_point(p), to_point(q), to_point(r));
}

double segment_plane_parameter(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p,
                               const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const Eigen::Vector3d n = (q - p).cross(r - p);
  const double da = n.dot(a - p), db = n.dot(b - p);
  if (!(std::abs(da - db) > 0.0)) return 0.0;
  return std::clamp(da / (da - db), 0.0, 1.0);
}

struct TriangleTree::Impl {
  std::vector<int> ids;             // face id per triangle of `triangles`
  std::vector<Triangle> triangles;  // non-degenerate ones, in the tree
  std::vector<int> degenerate_ids;  // face ids of degenerate triangles
  std::vector<std::array<Point, 3>> degenerate;
  Tree tree;
  int count = 0;

  int face_of(const Primitive::Id& id) const { return ids[static_cast<size_t>(id - triangles.cbegin())]; }
};

TriangleTree::TriangleTree(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& face_ids)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  std::vector<int> faces = face_ids;
  if (faces.empty()) {
    faces.resize(static_cast<size_t>(F.rows()));
    for (int f = 0; f < F.rows(); ++f) faces[static_cast<size_t>(f)] = f;
  }
  for (int f : faces) {
    if (f < 0 || f >= F.rows()) throw UsageError("face id " + std::to_string(f) + " out of range");
    Point corner[3];
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      if (v < 0 || v >= V.rows()) throw UsageError("vertex id out of range", "face " + std::to_string(f));
      if (!V.row(v).allFinite()) throw GeometryError("non-finite vertex coordinates", "vertex " + std::to_string(v));
      corner[k] = Point(V(v, 0), V(v, 1), V(v, 2));
    }
    if (CGAL::collinear(corner[0], corner[1], corner[2])) {
      s.degenerate_ids.push_back(f);
      s.degenerate.push_back({corner[0], corner[1], corner[2]});
    } else {
      s.ids.push_back(f);
      s.triangles.emplace_back(corner[0], corner[1], corner[2]);
    }
  }
  s.count = static_cast<int>(faces.size());
  s.tree.rebuild(s.triangles.cbegin(), s.triangles.cend());
}

TriangleTree::~TriangleTree() = default;
TriangleTree::TriangleTree(TriangleTree&&) noexcept = default;
TriangleTree& TriangleTree::operator=(TriangleTree&&) noexcept = default;

int TriangleTree::size() const { return impl_->count; }

std::vector<int> TriangleTree::segment_faces(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  if (!a.allFinite() || !b.allFinite()) throw UsageError("segment query with non-finite coordinates");
  const Impl& s = *impl_;
  const Point pa = to_point(a), pb = to_point(b);
  std::vector<int> out;
  if (!s.triangles.empty()) {
    std::vector<Primitive::Id> hits;
    if (pa == pb) {
      // A point: candidates by its box, then the exact test.
      s.tree.all_intersected_primitives(pa.bbox(), std::back_inserter(hits));
      for (const auto& id : hits) {
        if (id->has_on(pa)) out.push_back(s.face_of(id));
      }
    } else {
      // The tree's own traversal tests the segment against boxes and then
      // against each (non-degenerate) triangle with the kernel's exact predicate.
      s.tree.all_intersected_primitives(Segment(pa, pb), std::back_inserter(hits));
      for (const auto& id : hits) out.push_back(s.face_of(id));
    }
  }
  for (size_t k = 0; k < s.degenerate.size(); ++k) {
    const auto& t = s.degenerate[k];
    if (meets(pa, pb, t[0], t[1], t[2])) out.push_back(s.degenerate_ids[k]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> TriangleTree::box_faces(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
  const Impl& s = *impl_;
  const CGAL::Bbox_3 box(lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
  std::vector<int> out;
  if (!s.triangles.empty()) {
    std::vector<Primitive::Id> hits;
    s.tree.all_intersected_primitives(box, std::back_inserter(hits));
    for (const auto& id : hits) out.push_back(s.face_of(id));
  }
  for (size_t k = 0; k < s.degenerate.size(); ++k) {
    const auto& t = s.degenerate[k];
    if (CGAL::do_overlap(box, t[0].bbox() + t[1].bbox() + t[2].bbox())) out.push_back(s.degenerate_ids[k]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace gp::collision
