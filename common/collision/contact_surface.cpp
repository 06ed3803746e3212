#include "collision/contact_surface.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <Eigen/Geometry>

#include "collision/triangle_tree.h"
#include "core/error.h"
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
  std::vector<std::array<int, 3>> out;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += Eigen::Vector3d(p.x(), p.y(), p.z());
  centroid /= static_cast<double>(points.size());
  for (const auto f : hull.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (const auto h : CGAL::halfedges_around_face(hull.halfedge(f), hull)) {
      if (k == 3) throw NumericalError("a convex hull face is not a triangle");
      const Point& p = hull.point(hull.target(h));
      t[static_cast<size_t>(k++)] = id_of.at({p.x(), p.y(), p.z()});
    }
    if (k != 3) throw NumericalError("a convex hull face is not a triangle");
    // Outward: the normal points away from the centroid (inside a convex hull).
    const Eigen::Vector3d a = V.row(t[0]).transpose(), b = V.row(t[1]).transpose(), c = V.row(t[2]).transpose();
    if ((b - a).cross(c - a).dot(a - centroid) < 0.0) std::swap(t[1], t[2]);
    out.push_back(t);
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
