#pragma once
// Where a cloth and a body pass through each other: an independent check of a draped state, for
// key poses and verdicts, with exact predicates (triangle_tree.h). It reports
//  - body edges that meet cloth triangles and cloth edges that meet body triangles (both zero
//    exactly when the two surfaces do not intersect; touching counts);
//  - cloth vertices inside the body, with their depth (signed distance with angle-weighted
//    pseudo-normals, as body_collider.h);
//  - body vertices behind the cloth: on the cloth's outer side (where its normals point), with an
//    inward ray that meets the cloth from that side before it leaves the body; the body-side
//    counterpart of a cloth vertex inside (collision/README.md, "Crossings").
// The body must be closed and outward oriented; the cloth may be open.
#include <vector>

#include <Eigen/Core>

#include "spec/json_file.h"

namespace gp::collision {

struct CrossingOptions {
  // How far [m] a body vertex's inward ray looks for the cloth; body vertices
  // farther than this from the cloth's bounding box are not tested.
  double depth_reach = 0.1;
  int max_examples = 10;  // example ids kept per kind
};

// An edge (vertex ids a < b of one mesh) meeting a triangle of the other.
struct EdgeFaceHit {
  int a = -1, b = -1;
  int face = -1;
};

struct CrossingReport {
  long body_edge_crossings = 0;   // (body edge, cloth triangle) pairs that meet
  long cloth_edge_crossings = 0;  // (cloth edge, body triangle) pairs that meet
  std::vector<EdgeFaceHit> body_edge_examples;   // the first pairs in (a, b, face) order
  std::vector<EdgeFaceHit> cloth_edge_examples;
  long cloth_vertices_inside = 0;          // strictly inside the body
  double deepest_cloth_vertex = 0.0;       // m, 0 when none is inside
  int deepest_cloth_vertex_id = -1;
  std::vector<int> cloth_vertex_examples;  // the first ids inside, ascending
  long body_vertices_behind = 0;           // body vertices with the cloth through the body under them
  double deepest_body_vertex = 0.0;        // m, depth of the cloth under the worst one
  int deepest_body_vertex_id = -1;
  std::vector<int> body_vertex_examples;   // the first ids, ascending
  int body_faces_tested = 0;               // body faces near the cloth (the rest cannot meet it)

  long crossings() const { return body_edge_crossings + cloth_edge_crossings; }
  // No crossing, no cloth vertex inside, no body vertex behind the cloth.
  bool intersection_free() const {
    return crossings() == 0 && cloth_vertices_inside == 0 && body_vertices_behind == 0;
  }
};

// V_body #Vb by 3, F_body #Fb by 3 (closed, outward); V_cloth #Vc by 3, F_cloth #Fc by 3; metres.
// Throws GeometryError for non-finite coordinates (naming the mesh and vertex), UsageError for ids
// out of range.
CrossingReport find_crossings(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                              const Eigen::MatrixXd& V_cloth, const Eigen::MatrixXi& F_cloth,
                              const CrossingOptions& options = {});

// The report as a JSON object for stage reports: counts, depths [m] and example ids
// ("body_edge_crossings", "cloth_edge_crossings", "cloth_vertices_inside",
// "deepest_cloth_vertex_m", "body_vertices_behind", "deepest_body_vertex_m", "intersection_free",
// and the examples).
OrderedJson to_json(const CrossingReport& report);

}  // namespace gp::collision
