#include "pattern/curve_insertion.h"

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include <Eigen/Geometry>

#include <CGAL/Constrained_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include "core/error.h"
#include "mesh/topology.h"

namespace gp {
namespace {

// Exact constructions: a point computed on a face's edge lies exactly on it,
// so that no sliver flap can form between an edge and its points.
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// A constrained triangulation without Delaunay flips: its combinatorics
// depend on orientation tests only, which a tiny move of the points does not
// change (in-circle tests would flip nearly cocircular quads). Constraints
// that cross throw instead of being split: two curves must not cross inside
// a face.
using Cdt = CGAL::Constrained_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;

using EdgeKey = std::pair<int, int>;  // (smaller, larger) vertex id

EdgeKey edge_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// A point on an edge, measured from the edge's smaller vertex.
struct EdgePoint {
  double t = 0.0;
  int id = -1;
};

// A point on an edge's end is that vertex; a point of a face on its edge or
// corner is that edge point or vertex. Such points would otherwise be new
// vertices on top of the mesh's own (on a corner) or, inside a face's
// triangulation, split its rim where the neighbouring face does not.
CurvePoint snapped(const Eigen::MatrixXi& F, const CurvePoint& p) {
  if (p.is_edge()) {
    if (p.t <= 0.0) return CurvePoint::at_vertex(p.a);
    if (p.t >= 1.0) return CurvePoint::at_vertex(p.b);
    return p;
  }
  if (!p.is_face() || p.face < 0 || p.face >= F.rows()) return p;
  int positive = 0;
  for (int k = 0; k < 3; ++k) positive += p.bary[k] > 0.0 ? 1 : 0;
  if (positive == 3) return p;
  if (positive <= 1) {
    int best = 0;
    for (int k = 1; k < 3; ++k)
      if (p.bary[k] > p.bary[best]) best = k;
    return CurvePoint::at_vertex(F(p.face, best));
  }
  int i = -1, j = -1;
  for (int k = 0; k < 3; ++k)
    if (p.bary[k] > 0.0) (i < 0 ? i : j) = k;
  return CurvePoint::on_edge(F(p.face, i), F(p.face, j), p.bary[j] / (p.bary[i] + p.bary[j]));
}

// insert_curves' phases, in order, over the state they share: the curve
// points registered on edges and in faces, the new vertices, each curve's
// path and chords, then each face retriangulated and the vertices renumbered.
class CurveInserter {
 public:
  CurveInserter(const Eigen::MatrixXd& V_in, const Eigen::MatrixXi& F_in, const std::vector<SurfaceCurve>& input_curves)
      : V(V_in), F(F_in), n(static_cast<int>(V_in.rows())), m(static_cast<int>(F_in.rows())), curves(input_curves) {}

  RefinedMesh run(const std::vector<std::vector<int>>& carried) {
    register_points();
    add_vertices();
    trace_curves();
    carry_paths(carried);
    triangulate_faces();
    renumber();
    return std::move(out);
  }

 private:
  const Eigen::MatrixXd& V;
  const Eigen::MatrixXi& F;
  const int n;
  const int m;
  std::vector<SurfaceCurve> curves;
  std::map<EdgeKey, std::vector<int>> edge_faces;  // faces of every edge
  std::vector<std::vector<int>> vf;
  // New points: edge points keyed by (edge, t), then face points.
  std::map<EdgeKey, std::vector<double>> edge_t;
  std::vector<std::pair<int, Eigen::Vector3d>> face_points;  // (face, bary), in curve order
  RefinedMesh out;
  std::vector<Eigen::Vector3d> positions;
  std::vector<SurfacePoint> origin;
  std::map<EdgeKey, std::vector<EdgePoint>> on_edge;  // sorted by t, from the smaller vertex
  std::map<std::pair<int, size_t>, int> face_point_id;  // (face, index in face_points) -> id
  std::vector<std::vector<int>> points_in_face;
  std::vector<std::vector<std::pair<int, int>>> constraints;  // per face: chords
  // alias[id]: the point a new point coincides with (merged), else -1.
  std::vector<int> alias;
  std::vector<Eigen::Vector3i> faces;
  std::vector<int> parent;

  const std::vector<int>& faces_of_edge(int a, int b) const {
    static const std::vector<int> none;
    const auto it = edge_faces.find(edge_key(a, b));
    return it == edge_faces.end() ? none : it->second;
  }

  // The curves' points snapped, the mesh's edge faces, and the points to add
  // on edges and in faces.
  void register_points() {
    for (SurfaceCurve& c : curves)
      for (CurvePoint& p : c) p = snapped(F, p);
    for (int f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) edge_faces[edge_key(F(f, k), F(f, (k + 1) % 3))].push_back(f);
    vf = vertex_faces(F, n);
    for (const SurfaceCurve& c : curves)
      for (const CurvePoint& p : c) {
        if (p.is_edge()) {
          if (faces_of_edge(p.a, p.b).empty())
            throw GeometryError("a curve point lies on " + std::to_string(p.a) + "-" + std::to_string(p.b) +
                                ", which is not an edge of the mesh");
          edge_t[edge_key(p.a, p.b)].push_back(p.t);
        } else if (p.is_face()) {
          if (p.face < 0 || p.face >= m) throw GeometryError("a curve point lies in a face that does not exist");
          face_points.emplace_back(p.face, p.bary);
        } else if (p.vertex >= n) {
          throw GeometryError("a curve point is a vertex that does not exist");
        }
      }
  }

  // The vertices: the input's, then the edge points by edge and t, then the
  // face points; each with its origin on the input.
  void add_vertices() {
    for (int v = 0; v < n; ++v) {
      positions.push_back(V.row(v).transpose());
      SurfacePoint s;
      if (!vf[static_cast<size_t>(v)].empty()) {
        s.face = vf[static_cast<size_t>(v)].front();
        for (int k = 0; k < 3; ++k) s.bary[k] = F(s.face, k) == v ? 1.0 : 0.0;
      }
      origin.push_back(s);
    }
    for (auto& [key, ts] : edge_t) {
      std::sort(ts.begin(), ts.end());
      ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
      for (double t : ts) {
        const int id = static_cast<int>(positions.size());
        positions.push_back((1.0 - t) * V.row(key.first).transpose() + t * V.row(key.second).transpose());
        SurfacePoint s;
        s.face = faces_of_edge(key.first, key.second).front();
        for (int k = 0; k < 3; ++k)
          s.bary[k] = F(s.face, k) == key.first ? 1.0 - t : F(s.face, k) == key.second ? t : 0.0;
        origin.push_back(s);
        on_edge[key].push_back({t, id});
      }
    }
    points_in_face.assign(static_cast<size_t>(m), {});
    for (size_t i = 0; i < face_points.size(); ++i) {
      const auto& [f, b] = face_points[i];
      const int id = static_cast<int>(positions.size());
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) x += b[k] * V.row(F(f, k)).transpose();
      positions.push_back(x);
      origin.push_back({f, b});
      face_point_id[{f, i}] = id;
      points_in_face[static_cast<size_t>(f)].push_back(id);
    }
  }

  int edge_point_id(int a, int b, double t) const {
    const EdgeKey key = edge_key(a, b);
    const double tt = a < b ? t : 1.0 - t;
    for (const EdgePoint& e : on_edge.at(key))
      if (e.t == tt) return e.id;
    throw GeometryError("internal: an edge point was not registered");
  }

  std::vector<int> faces_of_point(const CurvePoint& p) const {
    std::vector<int> fs;
    if (p.is_vertex()) fs = vf[static_cast<size_t>(p.vertex)];
    else if (p.is_edge()) fs = faces_of_edge(p.a, p.b);
    else fs = {p.face};
    std::sort(fs.begin(), fs.end());
    return fs;
  }

  // Points of an edge strictly between two of its points (ids, in order from a to b).
  std::vector<int> between_on_edge(int a, int b, int from_id, int to_id) const {
    // Positions along a -> b of every point of the edge, with the vertices at 0 and 1.
    std::vector<std::pair<double, int>> along{{0.0, a}, {1.0, b}};
    const auto it = on_edge.find(edge_key(a, b));
    if (it != on_edge.end())
      for (const EdgePoint& e : it->second) along.push_back({a < b ? e.t : 1.0 - e.t, e.id});
    std::sort(along.begin(), along.end());
    double s0 = -1.0, s1 = -1.0;
    for (const auto& [s, id] : along) {
      if (id == from_id) s0 = s;
      if (id == to_id) s1 = s;
    }
    std::vector<int> ids;
    if (s0 < 0.0 || s1 < 0.0) return ids;
    if (s0 < s1) {
      for (const auto& [s, id] : along)
        if (s > s0 && s < s1) ids.push_back(id);
    } else {
      for (auto r = along.rbegin(); r != along.rend(); ++r)
        if (r->first < s0 && r->first > s1) ids.push_back(r->second);
    }
    return ids;
  }

  // The mesh edge two points both lie on (vertex or edge points), or (-1, -1).
  EdgeKey common_edge(const CurvePoint& p, const CurvePoint& q) const {
    if (p.is_edge() && q.is_edge()) return edge_key(p.a, p.b) == edge_key(q.a, q.b) ? edge_key(p.a, p.b) : EdgeKey{-1, -1};
    if (p.is_vertex() && q.is_vertex()) {
      const auto& fs = faces_of_edge(p.vertex, q.vertex);
      return fs.empty() ? EdgeKey{-1, -1} : edge_key(p.vertex, q.vertex);
    }
    if (p.is_vertex() && q.is_edge() && (q.a == p.vertex || q.b == p.vertex)) return edge_key(q.a, q.b);
    if (q.is_vertex() && p.is_edge() && (p.a == q.vertex || p.b == q.vertex)) return edge_key(p.a, p.b);
    return {-1, -1};
  }

  // Vertex ids of every curve's points, its path, and the face of each chord.
  void trace_curves() {
    constraints.assign(static_cast<size_t>(m), {});
    size_t face_point_cursor = 0;
    std::vector<std::vector<int>> curve_ids(curves.size());
    for (size_t c = 0; c < curves.size(); ++c) {
      const SurfaceCurve& curve = curves[c];
      std::vector<int>& ids = curve_ids[c];
      for (const CurvePoint& p : curve) {
        if (p.is_vertex()) ids.push_back(p.vertex);
        else if (p.is_edge()) ids.push_back(edge_point_id(p.a, p.b, p.t));
        else ids.push_back(face_point_id.at({p.face, face_point_cursor++}));
      }
      std::vector<int>& path = out.paths.emplace_back();
      for (size_t i = 0; i < curve.size(); ++i) {
        if (i == 0) {
          path.push_back(ids[0]);
          continue;
        }
        const CurvePoint &p = curve[i - 1], &q = curve[i];
        const EdgeKey along = common_edge(p, q);
        if (along.first >= 0) {
          // The chord runs along a mesh edge: no constraint, but the path takes
          // every point that splits the edge between its ends.
          for (int id : between_on_edge(along.first, along.second, ids[i - 1], ids[i])) path.push_back(id);
          path.push_back(ids[i]);
          continue;
        }
        const auto fp = faces_of_point(p), fq = faces_of_point(q);
        std::vector<int> common;
        std::set_intersection(fp.begin(), fp.end(), fq.begin(), fq.end(), std::back_inserter(common));
        if (common.empty())
          throw GeometryError("curve " + std::to_string(c) + " leaves the mesh between its points " +
                              std::to_string(i - 1) + " and " + std::to_string(i) + " (they share no face)");
        constraints[static_cast<size_t>(common.front())].push_back({ids[i - 1], ids[i]});
        path.push_back(ids[i]);
      }
    }
  }

  void carry_paths(const std::vector<std::vector<int>>& carried) {
    for (const auto& path : carried) {
      std::vector<int>& next = out.carried.emplace_back();
      for (size_t i = 0; i < path.size(); ++i) {
        if (i > 0)
          for (int id : between_on_edge(path[i - 1], path[i], path[i - 1], path[i])) next.push_back(id);
        next.push_back(path[i]);
      }
    }
  }

  // Faces: unchanged ones copied, the others triangulated in their plane.
  void triangulate_faces() {
    alias.assign(positions.size(), -1);
    for (int f = 0; f < m; ++f) {
      bool split = !constraints[static_cast<size_t>(f)].empty() || !points_in_face[static_cast<size_t>(f)].empty();
      for (int k = 0; k < 3 && !split; ++k) split = on_edge.count(edge_key(F(f, k), F(f, (k + 1) % 3))) > 0;
      if (!split) {
        faces.push_back(F.row(f).transpose());
        parent.push_back(f);
        continue;
      }
      for (const auto& t : triangulate_face(f)) {
        faces.push_back(t);
        parent.push_back(f);
      }
    }
  }

  // Face f's points in its plane, constrained-triangulated with its rim and
  // chords; the triangles inside the rim, in a canonical order.
  std::vector<Eigen::Vector3i> triangulate_face(int f) {
    const Eigen::Vector3d p0 = V.row(F(f, 0)), p1 = V.row(F(f, 1)), p2 = V.row(F(f, 2));
    const Eigen::Vector3d e1 = p1 - p0, normal = e1.cross(p2 - p0);
    if (!(e1.norm() > 0.0) || !(normal.norm() > 1e-14 * e1.squaredNorm()))
      throw GeometryError("a curve crosses the degenerate face " + std::to_string(f));
    const Eigen::Vector3d x = e1.normalized(), y = normal.normalized().cross(x);
    Kernel::Point_2 corner[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d d = V.row(F(f, k)).transpose() - p0;
      corner[k] = Kernel::Point_2(d.dot(x), d.dot(y));
    }
    std::map<int, Kernel::Point_2> local;  // vertex id -> coordinates in the face's plane
    for (int k = 0; k < 3; ++k) local[F(f, k)] = corner[k];
    std::vector<std::pair<int, int>> rim;  // boundary chain of the face
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      std::vector<int> chain{a};
      for (int id : between_on_edge(a, b, a, b)) {
        // Position along a -> b of the point, from its registered t.
        const auto& list = on_edge.at(edge_key(a, b));
        double t = 0.0;
        for (const EdgePoint& e : list)
          if (e.id == id) t = a < b ? e.t : 1.0 - e.t;
        local[id] = corner[k] + (corner[(k + 1) % 3] - corner[k]) * Kernel::FT(t);
        chain.push_back(id);
      }
      chain.push_back(b);
      for (size_t i = 0; i + 1 < chain.size(); ++i) rim.push_back({chain[i], chain[i + 1]});
    }
    for (int id : points_in_face[static_cast<size_t>(f)]) {
      const Eigen::Vector3d& b = origin[static_cast<size_t>(id)].bary;
      local[id] = corner[0] + (corner[1] - corner[0]) * Kernel::FT(b[1]) + (corner[2] - corner[0]) * Kernel::FT(b[2]);
    }
    Cdt cdt;
    std::map<int, Cdt::Vertex_handle> handle;
    for (const auto& [id, q] : local) {
      const size_t before = cdt.number_of_vertices();
      const auto h = cdt.insert(q);
      if (cdt.number_of_vertices() == before) {
        // A point that coincides exactly with one inserted before (a lower
        // id: a corner, or an edge point before a face point) is that point:
        // two curves through the same point inside a face, or a point that
        // the smoothing put on an edge or a corner.
        alias[static_cast<size_t>(id)] = h->info();
        handle[id] = h;
        continue;
      }
      h->info() = id;
      handle[id] = h;
    }
    std::set<std::pair<int, int>> rim_edges;
    try {
      for (const auto& [a, b] : rim) {
        if (handle.at(a) == handle.at(b)) continue;
        cdt.insert_constraint(handle.at(a), handle.at(b));
        rim_edges.insert(edge_key(handle.at(a)->info(), handle.at(b)->info()));
      }
      for (const auto& [a, b] : constraints[static_cast<size_t>(f)])
        if (handle.at(a) != handle.at(b)) cdt.insert_constraint(handle.at(a), handle.at(b));
    } catch (const Cdt::Intersection_of_constraints_exception&) {
      throw GeometryError("two curves cross inside face " + std::to_string(f));
    }
    return inside_rim(cdt, rim_edges);
  }

  // The triangles of `cdt` inside the rim, each starting at its smallest id, sorted.
  static std::vector<Eigen::Vector3i> inside_rim(const Cdt& cdt, const std::set<std::pair<int, int>>& rim_edges) {
    // Faces outside the rim (slivers where an edge point fell just outside
    // its edge in floating point) are reached from the infinite face
    // without crossing the rim.
    std::set<Cdt::Face_handle> outside;
    std::vector<Cdt::Face_handle> stack{cdt.infinite_face()};
    outside.insert(cdt.infinite_face());
    while (!stack.empty()) {
      const Cdt::Face_handle h = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const Cdt::Face_handle g = h->neighbor(k);
        if (outside.count(g)) continue;
        const int a = h->vertex(Cdt::cw(k))->info(), b = h->vertex(Cdt::ccw(k))->info();
        const bool infinite_edge = cdt.is_infinite(h->vertex(Cdt::cw(k))) || cdt.is_infinite(h->vertex(Cdt::ccw(k)));
        if (!infinite_edge && rim_edges.count(edge_key(a, b))) continue;
        outside.insert(g);
        stack.push_back(g);
      }
    }
    std::vector<Eigen::Vector3i> pieces;
    for (auto h = cdt.finite_faces_begin(); h != cdt.finite_faces_end(); ++h) {
      if (outside.count(h)) continue;
      pieces.emplace_back(h->vertex(0)->info(), h->vertex(1)->info(), h->vertex(2)->info());
    }
    // A canonical order: each triangle starting at its smallest id, sorted.
    for (auto& t : pieces) {
      int r = 0;
      for (int k = 1; k < 3; ++k)
        if (t[k] < t[r]) r = k;
      t = Eigen::Vector3i(t[r], t[(r + 1) % 3], t[(r + 2) % 3]);
    }
    std::sort(pieces.begin(), pieces.end(), [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    return pieces;
  }

  // Merged points leave the mesh; the others keep their order.
  void renumber() {
    auto canonical = [this](int id) {
      while (alias[static_cast<size_t>(id)] >= 0) id = alias[static_cast<size_t>(id)];
      return id;
    };
    std::vector<int> kept_id(positions.size(), -1);
    int kept = 0;
    for (size_t i = 0; i < positions.size(); ++i)
      if (alias[i] < 0) kept_id[i] = kept++;
    auto final_id = [&](int id) { return kept_id[static_cast<size_t>(canonical(id))]; };
    auto remap_path = [&](std::vector<int>& path) {
      std::vector<int> next;
      for (int id : path) {
        const int v = final_id(id);
        if (next.empty() || next.back() != v) next.push_back(v);
      }
      path = std::move(next);
    };
    for (auto& path : out.paths) remap_path(path);
    for (auto& path : out.carried) remap_path(path);
    out.V.resize(kept, 3);
    out.origin.clear();
    for (size_t i = 0; i < positions.size(); ++i) {
      if (kept_id[i] < 0) continue;
      out.V.row(kept_id[i]) = positions[i].transpose();
      out.origin.push_back(origin[i]);
    }
    out.F.resize(static_cast<int>(faces.size()), 3);
    for (size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) out.F(static_cast<int>(i), k) = final_id(faces[i][k]);
    out.parent_face = parent;
  }
};

}  // namespace

RefinedMesh insert_curves(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                          const std::vector<SurfaceCurve>& input_curves, const std::vector<std::vector<int>>& carried) {
  return CurveInserter(V, F, input_curves).run(carried);
}

}  // namespace gp
