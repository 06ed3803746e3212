#pragma once
// Body proximity and collision response for cloth against a moving body mesh
// (no cloth-cloth collisions, as in Wolff et al. 2023).
//
// The body (V_body #Vb by 3 metres, F_body #Fb by 3, closed and outward
// oriented) is culled once per motion to the faces the garment can reach
// (reachable_body_faces). One bounding volume hierarchy over those faces
// (triangle_bvh.h, Embree) is refitted to each body frame (set_body). Queries
// return the exact closest body point and a signed distance whose sign comes
// from the angle-weighted pseudo-normal of the closest feature (face, edge or
// vertex; Baerentzen & Aanaes 2005, "Signed distance computation using the
// angle weighted pseudonormal"), which is robust at edges and vertices where
// the face normal alone gives the wrong sign.
//
// Answers depend on the body and the query point alone (not on the culling,
// the hierarchy, the thread count or the CPU): among faces at exactly the same
// distance the lowest face id wins, and among the faces around a shared edge
// or corner whose distances differ only by rounding (within a relative 1e-12)
// also the lowest id.
//
// resolve() is the collision response of one cloth step: every cloth vertex
// closer than the comfort offset (or inside the body) is moved to the offset
// along the direction away from its closest body point, and its velocity
// component towards the body (relative to the body's own velocity there) is
// removed. Queries are warm-started from each vertex's previous closest face,
// and vertices that provably cannot have come within the offset since their last
// query (distance minus their own motion minus the body's largest motion since)
// are skipped. A vertex that has not moved since its last query on the same body
// frame gets that answer again: while the body stands still, every vertex the
// step's resolve() left in place is asked again by the next step's contacts().
// While the body stands still (settling at a key pose), a vertex queried a
// third time on the same body frame collects the faces that can hold its
// closest point while it stays within a few millimetres, and later queries
// search only those (exactly, see cached_query). None of this changes an
// answer; the README has the measured gains.
//
// Pinches: where two body parts come closer than twice the comfort offset
// (armpit, between the legs, an arm against the torso) the two offset shells
// overlap, and a vertex pushed out to the offset of one part lands inside the
// offset of the other and is pushed back on the next step. The usable offset at
// a closest point c with outward direction n is therefore limited to half the
// gap, the distance from c along n to the next body surface (a ray cast through
// the hierarchy): the vertex is pushed to the middle of the gap, which both
// parts agree on (README: the armpit's stretch).
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

// Body faces within `reach` [m] of any garment vertex (conservatively: faces
// meeting the axis-aligned cube of half-size `reach` around a garment vertex),
// ascending ids. Because pinned garments follow the body, this set computed in
// the first frame of a motion stays valid for the whole motion.
std::vector<int> reachable_body_faces(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                                      const Eigen::MatrixXd& V_garment, double reach);

struct Proximity {
  double signed_distance = 0.0;        // m, negative inside the body
  Eigen::Vector3d closest = Eigen::Vector3d::Zero();  // closest body point
  Eigen::Vector3d outward = Eigen::Vector3d::Zero();  // unit direction from the body towards the query point's free side
  int face = -1;                       // body face id (full body numbering)
};

// A cloth vertex in contact: within the comfort offset plus a band.
struct Contact {
  int vertex = -1;                     // cloth vertex id
  double signed_distance = 0.0;        // m, negative inside the body
  Eigen::Vector3d outward = Eigen::Vector3d::UnitY();  // unit, away from the body
  double body_normal_speed = 0.0;      // body velocity at the closest point along outward [m/s]
  double offset = 0.0;                 // offset used [m]: the vertex's offset, at most half the gap there
};

// One body frame's geometry made ready for BodyCollider::set_body: positions,
// velocities, face normals and the refitted hierarchy (see BodyCollider::prepare).
class BodyFrame {
 public:
  BodyFrame();  // empty: set_body rejects it
  ~BodyFrame();
  BodyFrame(BodyFrame&&) noexcept;
  BodyFrame& operator=(BodyFrame&&) noexcept;

 private:
  friend class BodyCollider;
  struct Data;
  std::unique_ptr<Data> data_;
};

struct CollisionStats {
  long queries = 0;           // exact closest-point queries of the hierarchy
  long local = 0;             // exact closest-point answers from a vertex's candidate faces (body standing still)
  long skipped = 0;           // vertices skipped by the motion bound
  long reused = 0;            // answers reused for a vertex that had not moved on an unchanged body
  long projected = 0;         // vertices moved out to the offset
  long gap_rays = 0;          // rays cast to measure the gap in front of a closest point
  long pinched = 0;           // contacts or projections whose offset was limited to half the gap
  long creases = 0;           // second contacts of vertices in a crease (see contacts())
  double deepest_penetration = 0.0;  // largest depth inside the body seen by resolve() [m], before projection
  double rebuild_seconds = 0.0;      // hierarchy refits and face normals (prepare, counted when set)
  double query_seconds = 0.0;        // resolve()
};

class BodyCollider {
 public:
  // F_body: all body faces; face_ids: the faces to collide with (empty = all).
  BodyCollider(const Eigen::MatrixXi& F_body, std::vector<int> face_ids = {});
  ~BodyCollider();
  BodyCollider(BodyCollider&&) noexcept;
  BodyCollider& operator=(BodyCollider&&) noexcept;

  // Body positions of the current frame (#Vb by 3) and, optionally, the body
  // velocities [m/s] (#Vb by 3; zero when omitted). Refits the hierarchy.
  // Throws UsageError on a size mismatch, GeometryError on non-finite positions.
  void set_body(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd* body_velocity = nullptr);
  // The same in two halves. prepare() builds a frame's normals and hierarchy and
  // reads nothing but the culling fixed at construction, so it may run on
  // another thread while this collider answers queries on its current frame
  // (simulate-adapt prepares the next frame during a step); it throws as
  // set_body. set_body(frame) makes a frame prepared by this collider current
  // (UsageError for an empty frame or one of another collider).
  BodyFrame prepare(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd* body_velocity = nullptr) const;
  void set_body(BodyFrame frame);

  // Closest point and signed distance of p (finite; NumericalError otherwise);
  // `hint_face` (a culled face id or -1) warm-starts the search.
  Proximity query(const Eigen::Vector3d& p, int hint_face = -1) const;

  // Distance [m] from the closest point of q along q.outward to the next body
  // surface (infinity when the ray leaves the culled body).
  double gap(const Proximity& q) const;

  // Collision response for cloth positions X and velocities Vel (#V by 3; row i is
  // cloth vertex i across calls, for warm starts). offset [m] >= 0; in a pinch
  // at most half the gap (see above). Vertices at non-finite positions (a
  // diverged solve, rejected by the step's own checks) are left alone, here
  // and in contacts().
  void resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, double offset);
  // Same with a per-vertex offset (#V) [m]; an offset may be negative: the vertex
  // may then be that deep inside the body (used to push a garment that starts
  // inside the body out gradually instead of in one jump).
  void resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, const Eigen::VectorXd& offsets);

  // Cloth vertices of X (#V by 3) closer to the body than offset + band [m], in
  // ascending vertex order, with the body's normal velocity at their closest
  // points (for velocity constraints in the implicit solve). Shares the warm
  // starts and the motion bound of resolve(). A vertex in a crease of the
  // offset surface (its closest point moved to a face whose direction differs
  // by more than about 25 degrees since the previous call, while it stays
  // within reach of both) is listed twice in a row: the closest side first,
  // then the other, as long as it stays near both.
  std::vector<Contact> contacts(const Eigen::MatrixXd& X, double offset, double band);
  // Same with a per-vertex offset (#V) [m], which may be negative as in resolve().
  std::vector<Contact> contacts(const Eigen::MatrixXd& X, const Eigen::VectorXd& offsets, double band);

  // Threads for contacts() and resolve(): 2 or more query the second half of
  // the cloth vertices on another thread, and prepare() then computes every
  // vertex pseudo-normal of a frame up front (with one thread they are
  // computed as queries first need them). The answers do not depend on it.
  // Call it before preparing frames.
  void set_threads(int threads);

  const std::vector<int>& face_ids() const;
  const CollisionStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::collision
