#include "collision/crossings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <Eigen/Geometry>

#include "collision/body_collider.h"
#include "collision/triangle_tree.h"
#include "core/error.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp::collision {
namespace {

void check_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::string& name) {
  if (V.cols() != 3 || F.cols() != 3) throw UsageError(name + " positions and faces must have 3 columns");
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!V.row(v).allFinite()) throw GeometryError("non-finite " + name + " vertex", name + " vertex " + std::to_string(v));
  }
  if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows())) {
    throw UsageError(name + " face indices out of range");
  }
}

// Bounding boxes are Eigen's (empty when constructed); `margin` widens the
// box on every side.
using Box = Eigen::AlignedBox3d;
bool contains(const Box& box, const Eigen::Vector3d& p, double margin) {
  return (p.array() >= box.min().array() - margin).all() && (p.array() <= box.max().array() + margin).all();
}
bool overlaps(const Box& box, const Box& o, double margin) {
  return (o.max().array() >= box.min().array() - margin).all() && (o.min().array() <= box.max().array() + margin).all();
}

// Every (edge of E over positions V, face of `tree`) pair that meets, in
// (a, b, face) order.
std::vector<EdgeFaceHit> edge_hits(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E, const TriangleTree& tree,
                                   const Box& region) {
  std::vector<EdgeFaceHit> hits;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Eigen::Vector3d a = V.row(E(e, 0)), b = V.row(E(e, 1));
    Box box;
    box.extend(a);
    box.extend(b);
    if (!overlaps(region, box, 0.0)) continue;
    for (int f : tree.segment_faces(a, b)) hits.push_back({E(e, 0), E(e, 1), f});
  }
  return hits;
}

}  // namespace

CrossingReport find_crossings(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                              const Eigen::MatrixXd& V_cloth, const Eigen::MatrixXi& F_cloth,
                              const CrossingOptions& options) {
  check_mesh(V_body, F_body, "body");
  check_mesh(V_cloth, F_cloth, "cloth");
  if (!(options.depth_reach >= 0.0) || options.max_examples < 0) {
    throw UsageError("depth_reach and max_examples must be non-negative");
  }
  CrossingReport report;
  if (F_cloth.rows() == 0 || F_body.rows() == 0) return report;
  const size_t max_examples = static_cast<size_t>(options.max_examples);

  Box cloth_box;
  for (Eigen::Index v = 0; v < V_cloth.rows(); ++v) cloth_box.extend(V_cloth.row(v).transpose());
  // Body faces that can meet the cloth: those whose box meets the cloth's.
  // The inward rays of body vertices reach depth_reach further.
  std::vector<int> near_faces;
  for (int f = 0; f < F_body.rows(); ++f) {
    Box box;
    for (int k = 0; k < 3; ++k) box.extend(V_body.row(F_body(f, k)).transpose());
    if (overlaps(cloth_box, box, options.depth_reach)) near_faces.push_back(f);
  }
  report.body_faces_tested = static_cast<int>(near_faces.size());
  if (near_faces.empty()) return report;

  const TriangleTree cloth_tree(V_cloth, F_cloth);
  const TriangleTree body_tree(V_body, F_body, near_faces);

  // Body edges through cloth triangles, cloth edges through body triangles.
  std::vector<EdgeFaceHit> body_hits = edge_hits(V_body, unique_edges(F_body), cloth_tree, cloth_box);
  Box body_near_box;
  for (int f : near_faces) {
    for (int k = 0; k < 3; ++k) body_near_box.extend(V_body.row(F_body(f, k)).transpose());
  }
  std::vector<EdgeFaceHit> cloth_hits = edge_hits(V_cloth, unique_edges(F_cloth), body_tree, body_near_box);
  report.body_edge_crossings = static_cast<long>(body_hits.size());
  report.cloth_edge_crossings = static_cast<long>(cloth_hits.size());
  body_hits.resize(std::min(body_hits.size(), max_examples));
  cloth_hits.resize(std::min(cloth_hits.size(), max_examples));
  report.body_edge_examples = std::move(body_hits);
  report.cloth_edge_examples = std::move(cloth_hits);

  // Cloth vertices inside the body: signed distance to the whole body (a
  // culled body could give a deep vertex a wrong closest face and sign).
  BodyCollider body(F_body);
  body.set_body(V_body);
  int hint = -1;
  for (int v = 0; v < V_cloth.rows(); ++v) {
    const Proximity q = body.query(V_cloth.row(v).transpose(), hint);
    hint = q.face;
    if (!(q.signed_distance < 0.0)) continue;
    ++report.cloth_vertices_inside;
    if (report.cloth_vertex_examples.size() < max_examples) report.cloth_vertex_examples.push_back(v);
    if (-q.signed_distance > report.deepest_cloth_vertex) {
      report.deepest_cloth_vertex = -q.signed_distance;
      report.deepest_cloth_vertex_id = v;
    }
  }

  // Body vertices behind the cloth: the inward segment of length depth_reach
  // meets the cloth before any body face but the vertex's own.
  if (options.depth_reach > 0.0) {
    const Eigen::MatrixXd N = vertex_normals(V_body, F_body);
    const std::vector<std::vector<int>> incident = vertex_faces(F_body, static_cast<int>(V_body.rows()));
    std::vector<char> near_vertex(static_cast<size_t>(V_body.rows()), 0);
    for (int f : near_faces) {
      for (int k = 0; k < 3; ++k) near_vertex[static_cast<size_t>(F_body(f, k))] = 1;
    }
    for (int v = 0; v < V_body.rows(); ++v) {
      if (!near_vertex[static_cast<size_t>(v)]) continue;
      const Eigen::Vector3d b = V_body.row(v).transpose();
      const Eigen::Vector3d n = N.row(v).transpose();
      if (!contains(cloth_box, b, options.depth_reach) || !(n.norm() > 0.0)) continue;
      const Eigen::Vector3d end = b - options.depth_reach * n;
      const std::vector<int> cloth_faces = cloth_tree.segment_faces(b, end);
      if (cloth_faces.empty()) continue;
      // The nearest cloth triangle on the ray, met from its outer side.
      double t_cloth = std::numeric_limits<double>::infinity();
      bool from_outside = false;
      for (int f : cloth_faces) {
        const Eigen::Vector3d p = V_cloth.row(F_cloth(f, 0)), q = V_cloth.row(F_cloth(f, 1)),
                              r = V_cloth.row(F_cloth(f, 2));
        const double t = segment_plane_parameter(b, end, p, q, r);
        if (t < t_cloth) {
          t_cloth = t;
          from_outside = (q - p).cross(r - p).dot(n) > 0.0;
        }
      }
      if (!from_outside) continue;
      double t_body = std::numeric_limits<double>::infinity();
      const std::vector<int>& own = incident[static_cast<size_t>(v)];
      for (int f : body_tree.segment_faces(b, end)) {
        if (std::binary_search(own.begin(), own.end(), f)) continue;
        t_body = std::min(t_body, segment_plane_parameter(b, end, V_body.row(F_body(f, 0)), V_body.row(F_body(f, 1)),
                                                          V_body.row(F_body(f, 2))));
      }
      if (!(t_cloth <= t_body)) continue;
      const double depth = t_cloth * options.depth_reach;
      ++report.body_vertices_behind;
      if (report.body_vertex_examples.size() < max_examples) report.body_vertex_examples.push_back(v);
      if (report.deepest_body_vertex_id < 0 || depth > report.deepest_body_vertex) {
        report.deepest_body_vertex = depth;
        report.deepest_body_vertex_id = v;
      }
    }
  }
  return report;
}

OrderedJson to_json(const CrossingReport& r) {
  auto hits = [](const std::vector<EdgeFaceHit>& list) {
    OrderedJson a = OrderedJson::array();
    for (const EdgeFaceHit& h : list) a.push_back({{"edge", {h.a, h.b}}, {"face", h.face}});
    return a;
  };
  OrderedJson j;
  j["intersection_free"] = r.intersection_free();
  j["body_edge_crossings"] = r.body_edge_crossings;
  j["cloth_edge_crossings"] = r.cloth_edge_crossings;
  j["cloth_vertices_inside"] = r.cloth_vertices_inside;
  j["deepest_cloth_vertex_m"] = r.deepest_cloth_vertex;
  j["deepest_cloth_vertex_id"] = r.deepest_cloth_vertex_id;
  j["body_vertices_behind"] = r.body_vertices_behind;
  j["deepest_body_vertex_m"] = r.deepest_body_vertex;
  j["deepest_body_vertex_id"] = r.deepest_body_vertex_id;
  j["body_edge_examples"] = hits(r.body_edge_examples);
  j["cloth_edge_examples"] = hits(r.cloth_edge_examples);
  j["cloth_vertex_examples"] = r.cloth_vertex_examples;
  j["body_vertex_examples"] = r.body_vertex_examples;
  return j;
}

}  // namespace gp::collision
