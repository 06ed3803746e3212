#pragma once
// Where a cloth and a body pass through each other: an independent check of a
// draped state, for key poses and verdicts, with exact predicates
// (triangle_tree.h). It reports
//  - body edges that meet cloth triangles and cloth edges that meet body
//    triangles: two closed triangle meshes intersect exactly when some edge of
//    one meets a triangle of the other, so both counts are zero for an
//    intersection-free state and at least one is positive otherwise (touching
//    counts);
//  - cloth vertices inside the body, with their depth (signed distance with
//    angle-weighted pseudo-normals, as body_collider.h);
//  - body vertices behind the cloth: a body vertex on the cloth's outer side
//    (where its normals point: away from the body, as make-garment and
//    extend-boundary orient a garment) whose inward ray (against its
//    area-weighted normal) meets the cloth, from that outer side, before it
//    leaves the body. The cloth then passes through the body right under the
//    vertex, which has come through it by that depth: a finger or an elbow
//    through a triangle, a hip through a skirt whose vertices all lie outside.
//    This is the body-side counterpart of a cloth vertex inside the body.
//    (The volume a garment encloses, its boundary loops capped, does not tell
//    it: the torso lies inside a shirt and the legs inside a skirt by design,
//    and a hand beside a skirt may rest on either side of it.)
//
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

// V_body #Vb by 3, F_body #Fb by 3 (closed, outward); V_cloth #Vc by 3,
// F_cloth #Fc by 3; metres. Throws GeometryError for non-finite coordinates
// (naming the mesh and vertex), UsageError for ids out of range.
CrossingReport find_crossings(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                              const Eigen::MatrixXd& V_cloth, const Eigen::MatrixXi& F_cloth,
                              const CrossingOptions& options = {});

// The report as a JSON object for stage reports: counts, depths [m] and
// example ids ("body_edge_crossings", "cloth_edge_crossings",
// "cloth_vertices_inside", "deepest_cloth_vertex_m", "body_vertices_behind",
// "deepest_body_vertex_m", "intersection_free", and the examples).
OrderedJson to_json(const CrossingReport& report);

}  // namespace gp::collision
