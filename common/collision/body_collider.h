#pragma once
// Body proximity and collision response for cloth against a moving body mesh (no cloth-cloth
// collisions, as in Wolff et al. 2023).
//
// The body (V_body #Vb by 3 metres, F_body #Fb by 3, closed and outward oriented) is culled once
// per motion to the faces the garment can reach (reachable_body_faces); one hierarchy over them
// (triangle_bvh.h) is refitted to each body frame (set_body). A query returns the exact closest
// body point and a signed distance whose sign comes from the angle-weighted pseudo-normal of the
// closest feature (Baerentzen & Aanaes 2005, "Signed distance computation using the angle weighted
// pseudonormal"), robust at edges and vertices. Answers depend on the body and the query point
// alone: ties, exact or within a relative 1e-12, go to the lowest face id (collision/README.md,
// "The body's query engine").
//
// resolve() is the collision response of one cloth step: a cloth vertex closer than the comfort
// offset (or inside) is moved to the offset away from its closest body point, and its velocity
// towards the body (relative to the body's own) is removed. Warm starts, a motion bound, reused
// answers and candidate faces on a still body save queries without changing an answer; in a pinch
// (two body parts closer than twice the offset) the offset is at most half the gap, so both parts
// agree on where the vertex goes (collision/README.md, "Caches and pinches").
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace gp::collision {

// Body faces within `reach` [m] of any garment vertex (conservatively: faces meeting the
// axis-aligned cube of half-size `reach` around a garment vertex), ascending ids. Pinned garments
// follow the body, but other body parts come to them: a hand 29 cm from a skirt in the first frame
// rests on it at a later key pose, so the fit keeps the union of this set over the first frame and
// every key pose (adapt/garment_motion.cpp).
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

// One body frame's geometry made ready for BodyCollider::set_body: positions, velocities, face
// normals and the refitted hierarchy (see BodyCollider::prepare).
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

  // Body positions of the current frame (#Vb by 3) and, optionally, the body velocities [m/s] (#Vb
  // by 3; zero when omitted). Refits the hierarchy. Throws UsageError on a size mismatch,
  // GeometryError on non-finite positions.
  void set_body(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd* body_velocity = nullptr);
  // The same in two halves. prepare() builds a frame's normals and hierarchy from nothing but the
  // culling, so it may run on another thread while this collider answers queries (the next frame
  // during a step); it throws as set_body. set_body(frame) makes a frame prepared by this collider
  // current (UsageError for an empty frame or one of another collider).
  BodyFrame prepare(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd* body_velocity = nullptr) const;
  void set_body(BodyFrame frame);

  // Closest point and signed distance of p (finite; NumericalError otherwise); `hint_face` (a
  // culled face id or -1) warm-starts the search.
  Proximity query(const Eigen::Vector3d& p, int hint_face = -1) const;

  // Distance [m] from the closest point of q along q.outward to the next body surface (infinity
  // when the ray leaves the culled body).
  double gap(const Proximity& q) const;

  // The room in front of a body point p with outward normal n (unit): the distance [m] to the
  // nearest point within `radius` of a culled face that faces it (its normal against n by more
  // than 90 degrees, the point on n's side of p): the other side of a gap whatever its direction,
  // where gap() looks along n only (a hand beside the thigh rather than in front of it). Infinity
  // when no such face is within the radius.
  double facing_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double radius) const;

  // For every culled face whose closest point to p (finite) lies within `radius` [m], in ascending
  // face order, the feature it lies on (the face's interior, an edge or a corner): the body as a set
  // of triangles, each an obstacle of its own. The static solve's barrier sums over them, which is
  // smooth where the closest face changes (a feature shared by several faces counts once per face;
  // counted once, the sum would jump where a face's closest point moves off the shared feature).
  struct NearFeature {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the feature's closest point to p
    int kind = 0;                                     // 0 the face's interior, 1 an edge, 2 a corner
    Eigen::Vector3d edge = Eigen::Vector3d::Zero();   // an edge's unit direction
  };
  std::vector<NearFeature> closest_features_within(const Eigen::Vector3d& p, double radius) const;

  // Collision response for cloth positions X and velocities Vel (#V by 3; row i is cloth vertex i
  // across calls, for warm starts). offset [m] >= 0; in a pinch at most half the gap (see above).
  // Vertices at non-finite positions (a diverged solve, rejected by the step's own checks) are left
  // alone, here and in contacts().
  void resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, double offset);
  // Same with a per-vertex offset (#V) [m]; an offset may be negative: the vertex may then be that
  // deep inside the body (used to push a garment that starts inside the body out gradually instead
  // of in one jump).
  void resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, const Eigen::VectorXd& offsets);

  // Cloth vertices of X (#V by 3) closer to the body than offset + band [m], in ascending vertex
  // order, with the body's normal velocity at their closest points (for velocity constraints in the
  // implicit solve). Shares the warm starts and the motion bound of resolve(). A vertex in a crease
  // of the offset surface (its closest point moved to a face whose direction differs by more than
  // about 25 degrees since the previous call, while it stays within reach of both) is listed twice
  // in a row: the closest side first, then the other, as long as it stays near both.
  std::vector<Contact> contacts(const Eigen::MatrixXd& X, double offset, double band);
  // Same with a per-vertex offset (#V) [m], which may be negative as in resolve().
  std::vector<Contact> contacts(const Eigen::MatrixXd& X, const Eigen::VectorXd& offsets, double band);

  // The least offset a pinch leaves [m] (default 0): where half the gap is less, the vertex keeps
  // this much (at most its own offset) from the closer part, as cloth of that thickness would.
  void set_min_pinch_offset(double thickness);
  // The gap of a pinch also counts the nearest surface facing the closest point within twice the
  // offset in any direction (facing_distance), not only the one along its normal (default off): the
  // offset then shrinks smoothly towards a gap's rim instead of jumping where the ray leaves it.
  void set_facing_gaps(bool on);

  // Threads for contacts() and resolve(): 2 or more query the second half of the cloth vertices on
  // another thread, and prepare() then computes every vertex pseudo-normal up front (one thread: as
  // queries first need them). Answers do not depend on it. Call it before preparing frames.
  void set_threads(int threads);

  const std::vector<int>& face_ids() const;
  const CollisionStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::collision
