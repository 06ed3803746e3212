#pragma once
// The body as the cloth meets it: the body's own surface plus, around each thin extremity (the
// fingers and palm of a hand), its convex hull, over which cloth can be pushed but never hooked
// (collision/README.md, "Why the hands are hulls"). A hull is a separate closed surface over copies
// of the body vertices that span it, so it follows the hand through every pose and the body stays
// manifold for the signed distance; the cloth collides with both.
//
// A body vertex is thin when a segment from just inside it, `thin` deep along its inward normal,
// meets another face (exact, collision/triangle_tree.h). Thin vertices joined by edges form parts;
// a part whose bounding box diagonal is at least `min_extent` (a hand) gets a hull, smaller ones
// (ears, the nose, a crease of skin) keep their shape.
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

struct ContactSurfaceOptions {
  bool hulls = true;          // false: the body's own surface only
  // m: thinner than this along the inward normal is a thin part (fingers 1-2 cm, a palm 2-3 cm, a
  // wrist 4-5 cm).
  double thin = 0.03;
  double min_extent = 0.10;   // m: bounding box diagonal of a part that gets a hull (a hand is about 0.18)
};

struct ContactSurface {
  // #Fb body faces as given, then the hulls' faces (outward) over the appended vertex rows #Vb..
  Eigen::MatrixXi F;
  std::vector<int> sources;    // body vertex copied by each appended vertex row #Vb + k
  int body_vertex_count = 0;   // #Vb
  int body_face_count = 0;     // #Fb
  int hull_count = 0;
  // Per hull, for reports: face count, the thin part's vertex count, its centroid in this pose [m].
  std::vector<int> hull_faces;
  std::vector<int> part_vertices;
  std::vector<Eigen::Vector3d> part_centroids;

  // The surface's vertices for a body frame V_body (#Vb by 3): the body's rows, then the copies.
  // UsageError for a row count other than #Vb.
  Eigen::MatrixXd positions(const Eigen::MatrixXd& V_body) const;
  // Faces of the surface that belong to the hulls (ids >= #Fb).
  bool is_hull_face(int f) const { return f >= body_face_count; }
};

// The contact surface of the body (V #Vb by 3 metres, F #Fb by 3, closed and outward oriented) in
// the pose V; the hulls are taken in this pose and follow the body in others. Throws GeometryError
// for non-finite coordinates, UsageError for bad options.
ContactSurface contact_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const ContactSurfaceOptions& options = {});

}  // namespace gp::collision
