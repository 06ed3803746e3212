#pragma once
// The body as the cloth meets it: the body's own surface plus, around each
// thin extremity (the fingers and palm of a hand), its convex hull.
//
// A cloth triangle is 1-2 cm across; the gaps between fingers, and between
// the thumb and the palm, are as wide. Cloth that falls into such a gap is
// held on both sides and, when the hand moves, dragged along: a skirt caught
// on a hand is hitched up by it. Over the convex hull of the hand the cloth
// can only be pushed, never hooked, as a real hand's fingers close against
// fabric. The hull is a separate closed surface, over copies of the body
// vertices that span it, so that it moves with the hand through every pose
// and the body's own surface stays manifold for the signed distance; the
// cloth collides with both.
//
// Thin parts: a body vertex belongs to one when the body, along its inward
// normal, is thinner than `thin` (a segment from just inside the vertex to
// `thin` deep meets another face; exact, collision/triangle_tree.h). Thin
// vertices joined by body edges form parts; a part whose bounding box
// diagonal is at least `min_extent` (a hand) gets a hull, smaller ones (ears,
// the nose, a crease of skin) keep their shape.
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

struct ContactSurfaceOptions {
  bool hulls = true;          // false: the body's own surface only
  // m: thinner than this along the inward normal is a thin part: fingers
  // are 1-2 cm thick, a palm 2-3 cm, a wrist 4-5 cm.
  double thin = 0.03;
  double min_extent = 0.10;   // m: bounding box diagonal of a part that gets a hull (a hand is about 0.18)
};

struct ContactSurface {
  // #Fb body faces (rows 0..#Fb-1, as given), then the hulls' faces, which
  // index the appended vertex rows #Vb.. (outward oriented).
  Eigen::MatrixXi F;
  std::vector<int> sources;    // body vertex copied by each appended vertex row #Vb + k
  int body_vertex_count = 0;   // #Vb
  int body_face_count = 0;     // #Fb
  int hull_count = 0;
  // Per hull: its face count, the thin part's vertex count and the part's
  // centroid in the pose it was taken in [m] (for reports).
  std::vector<int> hull_faces;
  std::vector<int> part_vertices;
  std::vector<Eigen::Vector3d> part_centroids;

  // The surface's vertices for a body frame V_body (#Vb by 3): the body's
  // rows, then the copies. UsageError for a row count other than #Vb.
  Eigen::MatrixXd positions(const Eigen::MatrixXd& V_body) const;
  // Faces of the surface that belong to the hulls (ids >= #Fb).
  bool is_hull_face(int f) const { return f >= body_face_count; }
};

// The contact surface of the body (V #Vb by 3 metres, F #Fb by 3, closed and
// outward oriented) in the pose V; the hulls are taken in this pose and
// follow the body in others. Throws GeometryError for non-finite
// coordinates, UsageError for bad options.
ContactSurface contact_surface(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const ContactSurfaceOptions& options = {});

}  // namespace gp::collision
