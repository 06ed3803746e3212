#pragma once
// Intersection-free cloth against a moving body, in both directions: body vertices against cloth
// triangles, body edges against cloth edges, cloth vertices against body triangles. The comfort
// offset stays with body_collider.h; this keeps the surfaces from passing through each other
// between its queries, and a finger through a triangle or an elbow across an edge.
//
// The body is kinematic and moves linearly over the step. enforce() finds every contact between the
// step's start (free of intersections, by induction) and end by continuous collision detection
// (ccd.h), plus every pair closer than `thickness` at the end, and moves the cloth point of each to
// `thickness` from the body (Bridson, Fedkiw & Anderson 2002, sec. 7.1, each vertex by its weight
// over the sum of squared weights); rounds repeat for passages until none is left or `max_rounds`,
// then the remaining cloth vertices move with their body points (the fail-safe of rigid impact
// zones). Pinned vertices never move. Details in collision/README.md, "Continuous contact".
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

struct ContinuousContactOptions {
  // Separation [m] kept between the cloth and body features, and to which a cloth vertex that
  // crossed a body triangle is put back: below the comfort offset, above the detection's rounding.
  double thickness = 1e-3;
  double tolerance = 1e-7;   // m: contact distance of the continuous detection (absorbs rounding)
  int max_rounds = 6;        // detection and response rounds per enforce() before the fail-safe
};

struct ContinuousContactStats {
  long calls = 0;
  long rounds = 0;                 // detection rounds (at least one per call)
  long candidates = 0;             // (cloth feature, body feature) pairs whose swept boxes were compared
  long overlaps = 0;               // of which met in boxes
  long narrow = 0;                 // of which met along the features' normals too: continuous tests
  long body_vertex_contacts = 0;   // body vertex through or nearer than thickness to a cloth triangle
  long edge_contacts = 0;          // body edge through or nearer than thickness to a cloth edge
  long cloth_vertex_contacts = 0;  // cloth vertex through a body triangle from outside
  long crossings = 0;              // of all these, actual passages through (the rest: closer than thickness)
  long fail_safe_calls = 0;        // calls that ended in the fail-safe
  long fail_safe_vertices = 0;     // cloth vertices it moved with the body
  long unresolved = 0;             // contacts left after the fail-safe
  double seconds = 0.0;
};

class ContinuousContact {
 public:
  // F_cloth #Fc by 3; F_body #Fb by 3, of which body_face_ids (empty: all) take part, e.g.
  // reachable_body_faces().
  ContinuousContact(const Eigen::MatrixXi& F_cloth, const Eigen::MatrixXi& F_body, std::vector<int> body_face_ids = {},
                    const ContinuousContactOptions& options = {});
  ~ContinuousContact();
  ContinuousContact(ContinuousContact&&) noexcept;
  ContinuousContact& operator=(ContinuousContact&&) noexcept;

  // Cloth vertices that are never moved (pins).
  void set_pinned(const std::vector<int>& ids);
  // Threads for the detection: 2 or more query the second half of the cloth features on another
  // thread. The answers do not depend on it.
  void set_threads(int threads);
  // The body at the end of the next step (#Vb by 3); the one given before becomes its start (the
  // first call sets both). Throws GeometryError for non-finite positions of a used vertex,
  // UsageError for a size mismatch.
  void set_body(const Eigen::MatrixXd& V_body);

  // X_start, X_end: cloth positions (#Vc by 3) at the start and end of the part [s_start, s_end] of
  // the step (fractions of it: a halved substep is [0, 0.5] then [0.5, 1]); moves vertices of X_end
  // as described above. X_start must be free of intersections with the body at s_start.
  void enforce(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start = 0.0, double s_end = 1.0);

  const ContinuousContactOptions& options() const;
  const ContinuousContactStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::collision
