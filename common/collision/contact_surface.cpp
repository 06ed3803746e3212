#include "collision/contact_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Geometry>

#include "collision/triangle_tree.h"
#include "core/error.h"
#include "core/union_find.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp::collision {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using HullMesh = CGAL::Surface_mesh<Point>;

// Whether the body is thinner than `thin` along the inward normal of each
// vertex: the segment from just inside the vertex to `thin` deep meets a face
// that does not hold the vertex.
std::vector<char> thin_vertices(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double thin) {
  const Eigen::MatrixXd N = vertex_normals(V, F);
  const TriangleTree tree(V, F);
  // The segment starts a little inside, so that the vertex's own faces are
  // not met at its start; a thousandth of the depth is far below any
  // thickness that matters and far above rounding.
  const double start = 1e-3 * thin;
  std::vector<char> is_thin(static_cast<size_t>(V.rows()), 0);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d n = N.row(v).transpose();
    if (!(n.norm() > 0.5)) continue;  // an unused or degenerate vertex
    const Eigen::Vector3d x = V.row(v).transpose();
    for (int f : tree.segment_faces(x - start * n, x - thin * n)) {
      if (F(f, 0) != v && F(f, 1) != v && F(f, 2) != v) {
        is_thin[static_cast<size_t>(v)] = 1;
        break;
      }
    }
  }
  return is_thin;
}

// Components of the thin vertices over body edges, each ascending, in the
// order of their smallest vertex.
std::vector<std::vector<int>> thin_parts(const std::vector<char>& is_thin, const Eigen::MatrixXi& F, int n) {
  const std::vector<std::vector<int>> neighbors = vertex_neighbors(F, n);
  std::vector<int> part(static_cast<size_t>(n), -1);
  std::vector<std::vector<int>> parts;
  for (int seed = 0; seed < n; ++seed) {
    if (!is_thin[static_cast<size_t>(seed)] || part[static_cast<size_t>(seed)] >= 0) continue;
    const int id = static_cast<int>(parts.size());
    parts.emplace_back();
    std::vector<int> stack{seed};
    part[static_cast<size_t>(seed)] = id;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      parts.back().push_back(v);
      for (int u : neighbors[static_cast<size_t>(v)]) {
        if (is_thin[static_cast<size_t>(u)] && part[static_cast<size_t>(u)] < 0) {
          part[static_cast<size_t>(u)] = id;
          stack.push_back(u);
        }
      }
    }
    std::sort(parts.back().begin(), parts.back().end());
  }
  return parts;
}

// The convex hull of the body vertices `ids` as triangles over those ids,
// outward oriented; empty when the points span less than a volume.
//
// The hull is unique, its triangulation is not: CGAL splits a facet with
// four or more coplanar points (common on a generated body's symmetric
// rings) in an order that follows its storage, so heap addresses. The
// coplanar triangles are joined into their convex polygon (exact
// predicates) and each polygon is fanned from its smallest vertex id, so
// that the surface, and every contact query that walks it, follows from the
// body alone.
std::vector<std::array<int, 3>> hull_triangles(const Eigen::MatrixXd& V, const std::vector<int>& ids) {
  std::vector<Point> points;
  std::map<std::array<double, 3>, int> id_of;
  for (int v : ids) {
    const std::array<double, 3> key{V(v, 0), V(v, 1), V(v, 2)};
    if (id_of.emplace(key, v).second) points.emplace_back(key[0], key[1], key[2]);
  }
  if (points.size() < 4) return {};
  HullMesh hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  if (hull.number_of_faces() < 4) return {};  // coplanar points: a polygon, not a solid
  auto body_id = [&](HullMesh::Vertex_index v) {
    const Point& p = hull.point(v);
    return id_of.at({p.x(), p.y(), p.z()});
  };
  // The hull's faces over body ids, in CGAL's consistent orientation.
  std::map<HullMesh::Face_index, int> face_number;
  std::vector<std::array<int, 3>> faces;
  for (const auto f : hull.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (const auto h : CGAL::halfedges_around_face(hull.halfedge(f), hull)) {
      if (k == 3) throw NumericalError("a convex hull face is not a triangle");
      t[static_cast<size_t>(k++)] = body_id(hull.target(h));
    }
    if (k != 3) throw NumericalError("a convex hull face is not a triangle");
    face_number.emplace(f, static_cast<int>(faces.size()));
    faces.push_back(t);
  }
  // Faces across an edge whose four points are coplanar are one polygon.
  UnionFind polygon(faces.size());
  for (const auto e : hull.edges()) {
    const auto h = hull.halfedge(e), o = hull.opposite(h);
    if (hull.is_border(h) || hull.is_border(o)) continue;
    if (CGAL::coplanar(hull.point(hull.source(h)), hull.point(hull.target(h)),
                       hull.point(hull.target(hull.next(h))), hull.point(hull.target(hull.next(o))))) {
      polygon.unite(face_number.at(hull.face(h)), face_number.at(hull.face(o)));
    }
  }
  // Each polygon's outline: its faces' directed edges whose reverse is not
  // in it, one leaving each outline vertex of a convex polygon.
  std::map<int, std::vector<int>> members;
  for (size_t f = 0; f < faces.size(); ++f) members[polygon.find(static_cast<int>(f))].push_back(static_cast<int>(f));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += Eigen::Vector3d(p.x(), p.y(), p.z());
  centroid /= static_cast<double>(points.size());
  std::vector<std::array<int, 3>> out;
  for (const auto& [root, group] : members) {
    std::set<std::pair<int, int>> edges;
    for (int f : group) {
      const std::array<int, 3>& t = faces[static_cast<size_t>(f)];
      for (size_t k = 0; k < 3; ++k) edges.emplace(t[k], t[(k + 1) % 3]);
    }
    std::map<int, int> next;
    for (const auto& [a, b] : edges) {
      if (!edges.count({b, a}) && !next.emplace(a, b).second)
        throw NumericalError("a convex hull facet's outline is not one loop");
    }
    const int first = next.begin()->first;  // the smallest outline vertex id
    std::vector<int> loop{first};
    for (int v = next.at(first); v != first; v = next.at(v)) {
      if (loop.size() > next.size()) throw NumericalError("a convex hull facet's outline is not one loop");
      loop.push_back(v);
    }
    for (size_t k = 1; k + 1 < loop.size(); ++k) {
      std::array<int, 3> t{loop[0], loop[k], loop[k + 1]};
      const Eigen::Vector3d a = V.row(t[0]).transpose(), b = V.row(t[1]).transpose(), c = V.row(t[2]).transpose();
      // Outward: the normal points away from the centroid (inside a convex hull).
      if ((b - a).cross(c - a).dot(a - centroid) < 0.0) std::swap(t[1], t[2]);
      out.push_back(t);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

Eigen::MatrixXd ContactSurface::positions(const Eigen::MatrixXd& V_body) const {
  if (V_body.rows() != body_vertex_count || V_body.cols() != 3) {
    throw UsageError("the body frame has " + std::to_string(V_body.rows()) + " vertices, the contact surface " +
                     std::to_string(body_vertex_count));
  }
  Eigen::MatrixXd X(body_vertex_count + static_cast<Eigen::Index>(sources.size()), 3);
  X.topRows(body_vertex_count) = V_body;
  for (size_t k = 0; k < sources.size(); ++k) X.row(body_vertex_count + static_cast<Eigen::Index>(k)) = V_body.row(sources[k]);
  return X;
}

ContactSurface contact_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const ContactSurfaceOptions& options) {
  if (!(options.thin > 0.0) || !(options.min_extent >= 0.0)) {
    throw UsageError("contact surface: thin must be positive and min_extent non-negative");
  }
  if (V.cols() != 3 || F.cols() != 3) throw UsageError("contact surface: V and F must have 3 columns");
  if (F.size() && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())) {
    throw UsageError("contact surface: face index out of range");
  }
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!V.row(v).allFinite()) throw GeometryError("non-finite body vertex", "body vertex " + std::to_string(v));
  }
  ContactSurface s;
  s.body_vertex_count = static_cast<int>(V.rows());
  s.body_face_count = static_cast<int>(F.rows());
  std::vector<std::array<int, 3>> faces;
  if (options.hulls && F.rows() > 0) {
    const std::vector<char> is_thin = thin_vertices(V, F, options.thin);
    for (const std::vector<int>& part : thin_parts(is_thin, F, static_cast<int>(V.rows()))) {
      Eigen::Vector3d lo = V.row(part.front()).transpose(), hi = lo;
      for (int v : part) {
        lo = lo.cwiseMin(V.row(v).transpose());
        hi = hi.cwiseMax(V.row(v).transpose());
      }
      if ((hi - lo).norm() < options.min_extent) continue;
      const std::vector<std::array<int, 3>> hull = hull_triangles(V, part);
      if (hull.empty()) continue;
      // The hull's own copies of its vertices: a separate closed surface.
      std::map<int, int> copy_of;
      for (const auto& t : hull) {
        std::array<int, 3> c{};
        for (int k = 0; k < 3; ++k) {
          auto [it, added] = copy_of.emplace(t[k], s.body_vertex_count + static_cast<int>(s.sources.size()));
          if (added) s.sources.push_back(t[k]);
          c[k] = it->second;
        }
        faces.push_back(c);
      }
      ++s.hull_count;
      s.hull_faces.push_back(static_cast<int>(hull.size()));
      s.part_vertices.push_back(static_cast<int>(part.size()));
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int v : part) centroid += V.row(v).transpose();
      s.part_centroids.push_back(centroid / static_cast<double>(part.size()));
    }
  }
  s.F.resize(F.rows() + static_cast<Eigen::Index>(faces.size()), 3);
  s.F.topRows(F.rows()) = F;
  for (size_t i = 0; i < faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) s.F(F.rows() + static_cast<Eigen::Index>(i), k) = faces[i][static_cast<size_t>(k)];
  }
  return s;
}

}  // namespace gp::collision
