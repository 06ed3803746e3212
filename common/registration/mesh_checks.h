#pragma once
// Per-mesh validity checks that register-check runs on every pose: finite
// coordinates, manifoldness, orientation, holes, components, degenerate and
// needle triangles, duplicate and unreferenced vertices.
#include <vector>

#include <Eigen/Core>

#include "spec/option_fields.h"

namespace gp {

struct MeshCheckOptions {
  // A triangle is degenerate when its area is below this fraction of the
  // squared bounding-box diagonal (scale-free; 1e-14 ~ a 1e-7 m wide sliver on
  // a 1.7 m body).
  double degenerate_area_fraction = 1e-14;
  // A triangle is a needle when its smallest angle is below this [degrees].
  double needle_angle_degrees = 2.0;
  // Two vertices are duplicates when closer than this fraction of the diagonal.
  double duplicate_distance_fraction = 1e-9;
  // How many offending element ids to keep per finding.
  int max_examples = 10;
};

// The options as a report records them (spec/option_fields.h).
struct MeshCheckOptionFields {
  template <class Fields>
  void operator()(MeshCheckOptions& o, Fields& f) const {
    f.number("degenerate_area_fraction", o.degenerate_area_fraction, Range::non_negative());
    f.number("needle_angle_degrees", o.needle_angle_degrees, Range::between(0.0, 60.0));
    f.number("duplicate_distance_fraction", o.duplicate_distance_fraction, Range::non_negative());
    f.integer("max_examples", o.max_examples, Range::between(0, 1e6));
  }
};

// Counts and a few example ids per finding (ids are vertices, edges as vertex
// pairs, or faces, as named).
struct MeshCheckResult {
  long long vertex_count = 0, face_count = 0;
  std::vector<int> nonfinite_vertex_ids;       // examples
  long long nonfinite_vertices = 0;
  long long nonmanifold_edges = 0;             // edges in more than two faces
  std::vector<std::pair<int, int>> nonmanifold_edge_examples;
  long long nonmanifold_vertices = 0;          // vertices whose faces form several fans
  std::vector<int> nonmanifold_vertex_ids;
  long long inconsistent_orientation_edges = 0;  // both faces run the edge the same way
  std::vector<std::pair<int, int>> inconsistent_edge_examples;
  std::vector<int> boundary_loop_sizes;        // one entry per hole, vertex count
  std::vector<int> boundary_loop_first_vertex;
  int components = 0;
  long long degenerate_faces = 0;
  std::vector<int> degenerate_face_ids;
  long long needle_faces = 0;
  std::vector<int> needle_face_ids;
  long long duplicate_vertices = 0;            // vertices coinciding with a lower id
  std::vector<std::pair<int, int>> duplicate_vertex_examples;
  long long unreferenced_vertices = 0;
  std::vector<int> unreferenced_vertex_ids;
  double bounding_box_diagonal = 0;
  double area = 0;

  bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  bool closed() const { return boundary_loop_sizes.empty(); }
};

// Runs every check. Never throws on bad geometry: it reports it.
MeshCheckResult check_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                           const MeshCheckOptions& options = {});

}  // namespace gp
