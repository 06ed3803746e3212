#include "collision/body_collider.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>

#include <CGAL/Intersections_3/Bbox_3_Triangle_3.h>
#include <CGAL/Simple_cartesian.h>
#include <Eigen/Dense>

#include "collision/triangle_bvh.h"
#include "core/error.h"
#include "core/math.h"
#include "core/stopwatch.h"
#include "mesh/barycentric.h"
#include "mesh/point_triangle.h"
#include "mesh/topology.h"

namespace gp::collision {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;

Point to_point(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }

// Distance along the ray o + t d (d unit) to triangle (a, b, c), or infinity
// (Moeller & Trumbore 1997, "Fast, minimum storage ray-triangle intersection").
double ray_triangle_distance(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, h = d.cross(e2);
  const double det = e1.dot(h);
  const double scale = e1.norm() * e2.norm();
  if (!(std::abs(det) > 1e-14 * scale)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(h) / det;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  const double t = e2.dot(q) / det;
  if (u < 0.0 || v < 0.0 || u + v > 1.0 || t < 0.0) return std::numeric_limits<double>::infinity();
  return t;
}

// Start of a gap ray above the surface [m], so that the faces around the closest
// point are not hit at distance zero.
constexpr double kGapRayLift = 1e-6;
// Two contact directions whose cosine is below this belong to different sides of
// a crease (about 25 degrees apart): a vertex near both gets both as contacts.
constexpr double kCreaseCosine = 0.9;
// A cached gap stays valid while the closest point moves less than this [m] on
// an unchanged body and face.
constexpr double kGapReuseDistance = 1e-3;
// Candidate faces of a vertex on a body standing still (see cached_query):
// they answer its queries while it stays within this distance [m] of where
// they were collected, and are collected from its third query on a body frame
// set at the previous frame's positions on (a key pose). On a moving body a
// frame is queried twice per step (contacts, then resolve), more when a step
// is retried in halves, too few times to repay a collection (4 times a query):
// the shirt's moving steps cost 47 against 35 ms of collisions with them.
// Shirt (3,829 vertices) T -> A with settling: 5.4 ms of collisions per step
// at 2 mm against 5.5 at 1 mm (collected more often) and 6.3 at 4 mm (twice
// the faces to search).
constexpr double kCandidateSlack = 2e-3;
constexpr int kCandidateQueries = 3;

struct VertexCache {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  double distance = 0.0;  // unsigned distance at the last query
  double travel = 0.0;    // body travel counter at the last query
  int face = -1;
  bool valid = false;
  bool outside = false;
  // The whole answer of the last query, valid for exactly the same point on the
  // same body frame (version).
  Proximity answer;
  long answer_version = -1;
  // Gap in front of the closest point (see BodyCollider::gap), for reuse.
  int gap_face = -1;
  long gap_version = -1;
  Eigen::Vector3d gap_point = Eigen::Vector3d::Zero();
  double gap = 0.0;
  // Queries on the current body frame (frame_version), and the candidate
  // faces (body ids, ascending) collected around candidate_center on body
  // frame candidate_version (see cached_query).
  long frame_version = -1;
  int frame_queries = 0;
  std::vector<int> candidates;
  Eigen::Vector3d candidate_center = Eigen::Vector3d::Zero();
  long candidate_version = -1;
  // Crease contacts (see contacts()): the closest face of the previous
  // contacts() or resolve() answer and its outward direction, and the face
  // held as the second side of a crease (-1: none).
  int seen_face = -1;
  Eigen::Vector3d seen_outward = Eigen::Vector3d::Zero();
  int crease_face = -1;
};

}  // namespace

std::vector<int> reachable_body_faces(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                                      const Eigen::MatrixXd& V_garment, double reach) {
  if (!(reach >= 0.0)) throw UsageError("reach must be non-negative");
  if (!V_garment.allFinite()) throw UsageError("garment positions must be finite");
  // Garment vertices bucketed in a grid of cells of size `reach`: the cubes that
  // can meet a face belong to vertices in the cells its bounding box, grown by
  // reach, overlaps. A query of the body tree per garment vertex listed the
  // same faces thousands of times over (1.8 s for the 3,829-vertex shirt).
  // Cells no smaller than a mean body face, so that a face spans few of them
  // even with a reach of zero.
  std::vector<Eigen::Vector3d> lows(F_body.rows()), highs(F_body.rows());
  double mean_extent = 0.0;
  for (int f = 0; f < F_body.rows(); ++f) {
    lows[f] = highs[f] = V_body.row(F_body(f, 0)).transpose();
    for (int k = 1; k < 3; ++k) {
      lows[f] = lows[f].cwiseMin(V_body.row(F_body(f, k)).transpose());
      highs[f] = highs[f].cwiseMax(V_body.row(F_body(f, k)).transpose());
    }
    mean_extent += (highs[f] - lows[f]).maxCoeff() / std::max<Eigen::Index>(1, F_body.rows());
  }
  if (!std::isfinite(mean_extent)) throw UsageError("body positions must be finite");
  const double cell = std::max({reach, mean_extent, 1e-12});
  auto cell_of = [cell](double x) { return static_cast<long>(std::floor(x / cell)); };
  struct Entry {
    long x, y, z;
    int vertex;
  };
  std::vector<Entry> entries(V_garment.rows());
  for (int v = 0; v < V_garment.rows(); ++v) {
    entries[v] = {cell_of(V_garment(v, 0)), cell_of(V_garment(v, 1)), cell_of(V_garment(v, 2)), v};
  }
  auto key_less = [](const Entry& a, const Entry& b) {
    return std::tie(a.x, a.y, a.z, a.vertex) < std::tie(b.x, b.y, b.z, b.vertex);
  };
  std::sort(entries.begin(), entries.end(), key_less);
  std::vector<int> ids;
  for (int f = 0; f < F_body.rows(); ++f) {
    const Eigen::Vector3d& lo = lows[f];
    const Eigen::Vector3d& hi = highs[f];
    const Triangle triangle(to_point(V_body.row(F_body(f, 0))), to_point(V_body.row(F_body(f, 1))),
                            to_point(V_body.row(F_body(f, 2))));
    bool reached = false;
    for (long x = cell_of(lo.x() - reach); x <= cell_of(hi.x() + reach) && !reached; ++x) {
      for (long y = cell_of(lo.y() - reach); y <= cell_of(hi.y() + reach) && !reached; ++y) {
        for (long z = cell_of(lo.z() - reach); z <= cell_of(hi.z() + reach) && !reached; ++z) {
          auto it = std::lower_bound(entries.begin(), entries.end(), Entry{x, y, z, -1}, key_less);
          for (; it != entries.end() && it->x == x && it->y == y && it->z == z && !reached; ++it) {
            const Eigen::Vector3d p = V_garment.row(it->vertex);
            // The face meets the vertex's cube (exactly, as the tree did); the
            // box test first rejects most candidates cheaply.
            if ((p - hi).maxCoeff() > reach || (lo - p).maxCoeff() > reach) continue;
            const CGAL::Bbox_3 box(p.x() - reach, p.y() - reach, p.z() - reach, p.x() + reach, p.y() + reach,
                                   p.z() + reach);
            reached = CGAL::do_intersect(triangle, box);
          }
        }
      }
    }
    if (reached) ids.push_back(f);
  }
  return ids;
}

struct BodyCollider::Impl {
  Eigen::MatrixXi F;
  std::vector<int> faces;          // culled faces (full ids)
  std::vector<int> local_of_face;  // #Fb: index into faces or -1
  Eigen::MatrixXi adjacency;       // triangle_adjacency of the full body
  std::vector<std::vector<int>> incident;  // per body vertex: incident faces (only culled vertices filled)
  std::vector<int> culled_vertices;
  std::vector<int> normal_faces;   // faces whose normals the pseudo-normals need

  Eigen::MatrixXd V, V_dot;
  bool has_velocity = false;
  Eigen::MatrixXd face_normal;    // #Fb by 3 (rows of normal_faces filled)
  // Angle-weighted vertex pseudo-normals. With one thread they are computed
  // when a query first needs one in a body frame (row v valid while
  // vertex_normal_version[v] == version): few culled vertices are ever the
  // closest feature, and computing all of them (three atan2 per face) costs
  // 3.5 ms per frame on the shared body, a third of a frame's preparation.
  // With more, prepare() computes them all (on simulate-adapt's worker,
  // beside the stepping), and queries on two threads only read them.
  mutable Eigen::MatrixXd vertex_normal;  // #Vb by 3
  mutable std::vector<long> vertex_normal_version;
  bool all_vertex_normals = false;        // the current frame's are all computed
  int threads = 1;      // contacts() and resolve() split their vertices over up to two threads
  std::unique_ptr<TriangleBvh> bvh;  // over the culled faces (index k: faces[k]) of the current frame
  // Hierarchies of earlier frames, refitted by the next prepare() rather
  // than built anew (prepare() may run on another thread).
  mutable std::mutex spare_mutex;
  mutable std::vector<std::unique_ptr<TriangleBvh>> spare;
  bool built = false;
  long version = 0;     // body frames set so far
  double min_pinch_offset = 0.0;  // m, set_min_pinch_offset
  bool facing_gaps = false;       // set_facing_gaps
  double travel = 0.0;  // accumulated largest body vertex motion between frames
  bool still = false;   // the current body frame has the previous frame's positions

  std::vector<VertexCache> cache;
  CollisionStats stats;

  Eigen::Vector3d corner(int f, int k) const { return V.row(F(f, k)).transpose(); }

  Eigen::Vector3d pseudo_normal(int f, TriangleFeature feature) const {
    if (feature == TriangleFeature::interior) return face_normal.row(f).transpose();
    if (is_edge(feature)) {
      const int g = adjacency(f, feature_index(feature));
      Eigen::Vector3d n = face_normal.row(f).transpose();
      if (g >= 0) n += face_normal.row(g).transpose();
      return n;
    }
    return vertex_pseudo_normal(F(f, feature_index(feature)));
  }

  // Baerentzen & Aanaes 2005, eq. 3: the incident faces' normals weighted by
  // their angles at v, for positions Vb and face normals N.
  Eigen::Vector3d angle_weighted_normal(int v, const Eigen::MatrixXd& Vb, const Eigen::MatrixXd& N) const {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (int f : incident[v]) {
      int k = 0;
      while (F(f, k) != v) ++k;
      const Eigen::Vector3d x = Vb.row(F(f, k)).transpose();
      const Eigen::Vector3d e1 = Vb.row(F(f, (k + 1) % 3)).transpose() - x;
      const Eigen::Vector3d e2 = Vb.row(F(f, (k + 2) % 3)).transpose() - x;
      const double angle = gp::math::atan2(e1.cross(e2).norm(), e1.dot(e2));
      n += angle * N.row(f).transpose();
    }
    return n;
  }

  Eigen::Vector3d vertex_pseudo_normal(int v) const {
    if (all_vertex_normals || vertex_normal_version[v] == version) return vertex_normal.row(v).transpose();
    const Eigen::Vector3d n = angle_weighted_normal(v, V, face_normal);
    vertex_normal.row(v) = n.transpose();
    vertex_normal_version[v] = version;
    return n;
  }

  // A closest point on an edge or a corner is shared by every face around that
  // feature, but each face computes it with its own rounding, so their
  // distances may differ in the last bits, and which face wins would depend on
  // which faces are culled: answers differing in the last bits were amplified
  // by adaptation to centimetres over a motion (make bench). The face with the
  // lowest id among those around the feature within a relative 1e-12 of the
  // closest distance is taken instead, so the answer depends on the body alone.
  void resolve_tie(const Eigen::Vector3d& p, int& f, TriangleClosestPoint& c) const {
    if (c.feature == TriangleFeature::interior) return;
    const double d = (p - c.point).squaredNorm();
    const double tolerance = 1e-12 * std::max(d, 1e-24);
    auto consider = [&](int g) {
      if (g < 0 || g >= f || local_of_face[g] < 0) return;
      const TriangleClosestPoint cg = closest_point_on_triangle(p, corner(g, 0), corner(g, 1), corner(g, 2));
      if (std::abs((p - cg.point).squaredNorm() - d) <= tolerance) {
        f = g;
        c = cg;
      }
    };
    const int f0 = f;
    if (is_edge(c.feature)) {
      consider(adjacency(f0, feature_index(c.feature)));
    } else {
      for (int g : incident[F(f0, feature_index(c.feature))]) consider(g);
    }
  }

  // The closest culled face: exact distances, the lowest id among equal
  // ones (TriangleBvh), then the tie rule above.
  Proximity query(const Eigen::Vector3d& p, int hint_face) const {
    if (!built) throw UsageError("BodyCollider::query before set_body");
    const int hint_local = (hint_face >= 0 && hint_face < static_cast<int>(local_of_face.size()))
                               ? local_of_face[hint_face]
                               : -1;
    return proximity_on(p, faces[bvh->closest(p, hint_local).triangle]);
  }

  // The answer for p whose closest body face is f (before the tie rule).
  Proximity proximity_on(const Eigen::Vector3d& p, int f) const {
    TriangleClosestPoint c = closest_point_on_triangle(p, corner(f, 0), corner(f, 1), corner(f, 2));
    resolve_tie(p, f, c);
    const Eigen::Vector3d n = pseudo_normal(f, c.feature);
    const Eigen::Vector3d d = p - c.point;
    const double dist = d.norm();
    Proximity out;
    out.face = f;
    out.closest = c.point;
    const bool inside = d.dot(n) < 0.0;
    out.signed_distance = inside ? -dist : dist;
    const double scale = std::max(1.0, p.cwiseAbs().maxCoeff());
    if (dist > 1e-12 * scale) {
      out.outward = inside ? Eigen::Vector3d(-d / dist) : Eigen::Vector3d(d / dist);
    } else {
      const double len = n.norm();
      out.outward = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitY();
    }
    return out;
  }

  double gap(const Proximity& q) const {
    if (!built) throw UsageError("BodyCollider::gap before set_body");
    const Eigen::Vector3d origin = q.closest + kGapRayLift * q.outward;
    const int skip_local = q.face >= 0 ? local_of_face[q.face] : -1;
    const TriangleBvh::Hit hit = bvh->first_hit(origin, q.outward, skip_local);
    if (hit.triangle < 0) return std::numeric_limits<double>::infinity();
    const int f = faces[hit.triangle];
    return kGapRayLift + ray_triangle_distance(origin, q.outward, corner(f, 0), corner(f, 1), corner(f, 2));
  }

  double facing_distance_of(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double radius) const {
    double best = std::numeric_limits<double>::infinity();
    for (int f : faces_within(p, radius)) {
      const Eigen::Vector3d a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
      if (!((b - a).cross(c - a).dot(n) < 0.0)) continue;
      const Eigen::Vector3d y = closest_point_on_triangle(p, a, b, c).point;
      if (!((y - p).dot(n) > 0.0)) continue;
      best = std::min(best, (y - p).norm());
    }
    return best <= radius ? best : std::numeric_limits<double>::infinity();
  }

  // The offset vertex i may use at its closest point q: `offset`, at most half
  // the gap in front of q. Rays are cast for vertices within the offset only,
  // and reused while the body, the face and (within kGapReuseDistance) the
  // closest point stay the same.
  double usable_offset(int i, const Proximity& q, double offset, CollisionStats& st) {
    if (!(offset > 0.0)) return offset;
    VertexCache& c = cache[i];
    if (!(c.gap_version == version && c.gap_face == q.face && (c.gap_point - q.closest).norm() < kGapReuseDistance)) {
      c.gap = gap(q);
      if (facing_gaps) c.gap = std::min(c.gap, facing_distance_of(q.closest, q.outward, 2.0 * offset));
      c.gap_version = version;
      c.gap_face = q.face;
      c.gap_point = q.closest;
      ++st.gap_rays;
    }
    if (0.5 * c.gap < offset) {
      ++st.pinched;
      return std::max(0.5 * c.gap, std::min(min_pinch_offset, offset));
    }
    return offset;
  }

  Eigen::Vector3d body_velocity_at(const Proximity& q) const {
    Eigen::Vector3d v_body = Eigen::Vector3d::Zero();
    if (!has_velocity) return v_body;
    const int f = q.face;
    const Eigen::Vector3d w = barycentric(q.closest, corner(f, 0), corner(f, 1), corner(f, 2));
    for (int k = 0; k < 3; ++k) v_body += w(k) * V_dot.row(F(f, k)).transpose();
    return v_body;
  }
  // Culled faces (body ids, ascending) within `radius` of p.
  std::vector<int> faces_within(const Eigen::Vector3d& p, double radius) const {
    std::vector<int> ids = bvh->within(p, radius);
    for (int& k : ids) k = faces[k];  // faces ascend, so the ids do
    return ids;
  }

  // The closest of the candidate faces to p (the lowest id among equally
  // close ones), answered as query() answers its face.
  Proximity closest_candidate(const Eigen::Vector3d& p, const std::vector<int>& candidates) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int f : candidates) {
      const double d2 = (p - closest_point_on_triangle(p, corner(f, 0), corner(f, 1), corner(f, 2)).point).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = f;
      }
    }
    return proximity_on(p, best);
  }

  // The closest body point to vertex i at x, or nothing when the cached
  // query proves the vertex farther than `reach`: the cached distance can have
  // shrunk at most by the vertex's own motion plus the body's largest motion
  // since that query. Updates the cache and warm-starts from its face.
  std::optional<Proximity> cached_query(int i, const Eigen::Vector3d& x, double reach, int& previous_face,
                                       CollisionStats& st) {
    // A non-finite position (a diverged solve, which the step's own checks
    // reject and retry) has no closest point; the vertex is left alone.
    if (!x.allFinite()) return std::nullopt;
    VertexCache& c = cache[i];
    if (c.valid && c.outside && c.distance - (x - c.x).norm() - (travel - c.travel) > reach) {
      ++st.skipped;
      return std::nullopt;
    }
    if (c.answer_version == version && c.x == x) {
      // The vertex has not moved since its last query on this body frame (a
      // vertex the step left in place, queried again by the next step's
      // contacts): the answer is the same.
      ++st.reused;
      previous_face = c.answer.face;
      c.seen_face = c.answer.face;
      c.seen_outward = c.answer.outward;
      return c.answer;
    }
    // On a body standing still a vertex's queries are answered from the faces
    // near it: if the closest body point of c was at distance d, every face
    // within d + s of a point x with |x - c| <= s lies within d + 2 s of c,
    // so the faces within d + 2 s of c, collected once, hold x's closest face
    // (the same body frame). A tree query verifies its answer against every
    // box within reach from the root; the candidates are a dozen triangles.
    if (c.frame_version != version) {
      c.frame_version = version;
      c.frame_queries = 0;
    }
    ++c.frame_queries;
    Proximity q;
    if (c.candidate_version == version && !c.candidates.empty() && (x - c.candidate_center).norm() <= kCandidateSlack) {
      q = closest_candidate(x, c.candidates);
      ++st.local;
    } else {
      q = query(x, c.valid ? c.face : previous_face);
      ++st.queries;
      if (still && c.frame_queries >= kCandidateQueries) {
        c.candidates = faces_within(x, std::abs(q.signed_distance) + 2.0 * kCandidateSlack);
        c.candidate_center = x;
        c.candidate_version = version;
      }
    }
    previous_face = q.face;
    c.valid = true;
    c.face = q.face;
    c.travel = travel;
    c.x = x;
    c.distance = std::abs(q.signed_distance);
    c.outside = q.signed_distance > 0.0;
    c.answer = q;
    c.answer_version = version;
    c.seen_face = q.face;
    c.seen_outward = q.outward;
    return q;
  }


  // Proximity of p to body face f alone (signed by the pseudo-normal of the
  // feature its closest point lies on).
  Proximity face_proximity(const Eigen::Vector3d& p, int f) const {
    const TriangleClosestPoint c = closest_point_on_triangle(p, corner(f, 0), corner(f, 1), corner(f, 2));
    const Eigen::Vector3d d = p - c.point;
    const double dist = d.norm();
    Proximity out;
    out.face = f;
    out.closest = c.point;
    const bool inside = d.dot(pseudo_normal(f, c.feature)) < 0.0;
    out.signed_distance = inside ? -dist : dist;
    out.outward = dist > 0.0 ? Eigen::Vector3d((inside ? -d : d) / dist) : Eigen::Vector3d::Zero();
    return out;
  }

  // Vertex i's contact with the body at q, with the offset it may use there.
  Contact contact_of(int i, const Proximity& q, double usable) const {
    Contact k;
    k.vertex = i;
    k.offset = usable;
    k.signed_distance = q.signed_distance;
    k.outward = q.outward;
    k.body_normal_speed = body_velocity_at(q).dot(q.outward);
    return k;
  }

  std::vector<Contact> contacts(const Eigen::MatrixXd& X, const double* offsets, double offset, double band) {
    const auto t0 = Clock::now();
    if (!built) throw UsageError("BodyCollider::contacts before set_body");
    if (X.cols() != 3) throw UsageError("positions must be #V by 3");
    if (cache.size() != static_cast<size_t>(X.rows())) cache.assign(X.rows(), VertexCache{});
    std::vector<Contact> out[2];
    for_halves(static_cast<int>(X.rows()), [&](int half, int begin, int end, CollisionStats& st) {
      contacts_range(X, offsets, offset, band, begin, end, out[half], st);
    });
    out[0].insert(out[0].end(), out[1].begin(), out[1].end());
    stats.query_seconds += seconds_since(t0);
    return std::move(out[0]);
  }

  // contacts() of the vertices [begin, end), appended to out in order.
  void contacts_range(const Eigen::MatrixXd& X, const double* offsets, double offset, double band, int begin, int end,
                      std::vector<Contact>& out, CollisionStats& st) {
    int previous_face = -1;
    for (int i = begin; i < end; ++i) {
      const double reach = (offsets ? offsets[i] : offset) + band;
      const Eigen::Vector3d x = X.row(i).transpose();
      VertexCache& c = cache[i];
      const int face_before = c.seen_face;
      const Eigen::Vector3d outward_before = c.seen_outward;
      const std::optional<Proximity> found = cached_query(i, x, reach, previous_face, st);
      if (!found) {
        c.seen_face = c.crease_face = -1;
        continue;
      }
      const Proximity& q = *found;
      if (!(q.signed_distance < reach)) {
        c.crease_face = -1;
        continue;
      }
      const double usable = usable_offset(i, q, offsets ? offsets[i] : offset, st);
      if (!(q.signed_distance < usable + band)) {
        c.crease_face = -1;
        continue;
      }
      out.push_back(contact_of(i, q, usable));
      // A crease of the offset surface (a concave corner: the back of an
      // armpit, where arm and torso meet): the closest point jumps between the
      // two sides from step to step, and one contact direction at a time let
      // the vertex slide along one side into the other's offset, to be pushed
      // back along the other normal the next step, without end. The side seen
      // by the previous contacts() or resolve() (or held from earlier) becomes
      // a second contact while the vertex is within its offset plus the band
      // (Baraff & Witkin 1998, sec. 5.3: a vertex constrained in two directions).
      const int candidate = c.crease_face >= 0                                  ? c.crease_face
                            : (face_before >= 0 && face_before != q.face &&
                               q.outward.dot(outward_before) < kCreaseCosine) ? face_before
                                                                              : -1;
      c.crease_face = -1;
      if (candidate < 0 || candidate == q.face) continue;
      const Proximity side = face_proximity(x, candidate);
      if (!(side.signed_distance < usable + band) || !(side.outward.dot(q.outward) < kCreaseCosine) ||
          side.outward.isZero()) {
        continue;
      }
      c.crease_face = candidate;
      out.push_back(contact_of(i, side, usable));
      ++st.creases;
    }
  }

  void resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, const double* offsets, double offset) {
    const auto t0 = Clock::now();
    if (!built) throw UsageError("BodyCollider::resolve before set_body");
    if (Vel.rows() != X.rows() || X.cols() != 3 || Vel.cols() != 3) {
      throw UsageError("positions and velocities must both be #V by 3");
    }
    if (cache.size() != static_cast<size_t>(X.rows())) cache.assign(X.rows(), VertexCache{});
    for_halves(static_cast<int>(X.rows()), [&](int, int begin, int end, CollisionStats& st) {
      resolve_range(X, Vel, offsets, offset, begin, end, st);
    });
    stats.query_seconds += seconds_since(t0);
  }

  // resolve() of the vertices [begin, end).
  void resolve_range(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, const double* offsets, double offset, int begin,
                     int end, CollisionStats& st) {
    int previous_face = -1;
    for (int i = begin; i < end; ++i) {
      const double off = offsets ? offsets[i] : offset;
      const std::optional<Proximity> found = cached_query(i, X.row(i).transpose(), off, previous_face, st);
      if (!found) continue;
      const Proximity& q = *found;
      if (!(q.signed_distance < off)) continue;
      if (q.signed_distance < 0.0) st.deepest_penetration = std::max(st.deepest_penetration, -q.signed_distance);
      const double usable = usable_offset(i, q, off, st);
      if (!(q.signed_distance < usable)) continue;
      const Eigen::Vector3d x_new = q.closest + usable * q.outward;
      X.row(i) = x_new.transpose();
      const Eigen::Vector3d v_body = body_velocity_at(q);
      const Eigen::Vector3d v = Vel.row(i).transpose();
      const double vn = (v - v_body).dot(q.outward);
      if (vn < 0.0) Vel.row(i) = (v - vn * q.outward).transpose();
      VertexCache& c = cache[i];
      c.x = x_new;
      c.distance = std::abs(usable);
      c.outside = usable > 0.0;
      c.answer_version = -1;
      ++st.projected;
    }
  }

  // Runs range(half, begin, end, stats) on the vertices [0, n/2) and
  // [n/2, n), the second half on another thread when threads > 1, and adds
  // the halves' counts to stats. The halves are the same for any thread count
  // (a vertex's first query is warm-started from the previous vertex of its
  // half), so the answers are too.
  template <class Range>
  void for_halves(int n, Range range) {
    CollisionStats half_stats[2];
    const int middle = n / 2;
    if (threads > 1 && middle > 0) {
      auto second = std::async(std::launch::async, [&] { range(1, middle, n, half_stats[1]); });
      range(0, 0, middle, half_stats[0]);
      second.get();
    } else {
      range(0, 0, middle, half_stats[0]);
      range(1, middle, n, half_stats[1]);
    }
    for (const CollisionStats& h : half_stats) {
      stats.queries += h.queries;
      stats.local += h.local;
      stats.skipped += h.skipped;
      stats.reused += h.reused;
      stats.projected += h.projected;
      stats.gap_rays += h.gap_rays;
      stats.pinched += h.pinched;
      stats.creases += h.creases;
      stats.deepest_penetration = std::max(stats.deepest_penetration, h.deepest_penetration);
    }
  }
};

BodyCollider::BodyCollider(const Eigen::MatrixXi& F_body, std::vector<int> face_ids)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.F = F_body;
  if (face_ids.empty()) {
    face_ids.resize(F_body.rows());
    for (int f = 0; f < F_body.rows(); ++f) face_ids[f] = f;
  }
  std::sort(face_ids.begin(), face_ids.end());
  face_ids.erase(std::unique(face_ids.begin(), face_ids.end()), face_ids.end());
  for (int f : face_ids) {
    if (f < 0 || f >= F_body.rows()) throw UsageError("body face id out of range");
  }
  if (face_ids.empty()) throw UsageError("no body faces to collide with");
  s.faces = std::move(face_ids);
  s.local_of_face.assign(F_body.rows(), -1);
  for (size_t k = 0; k < s.faces.size(); ++k) s.local_of_face[s.faces[k]] = static_cast<int>(k);
  s.adjacency = triangle_adjacency(F_body);
  const int nv = F_body.size() ? F_body.maxCoeff() + 1 : 0;
  const std::vector<std::vector<int>> all_incident = vertex_faces(F_body, nv);
  s.incident.assign(nv, {});
  std::vector<char> vertex_used(nv, 0), face_used(F_body.rows(), 0);
  for (int f : s.faces) {
    for (int k = 0; k < 3; ++k) vertex_used[F_body(f, k)] = 1;
  }
  for (int v = 0; v < nv; ++v) {
    if (!vertex_used[v]) continue;
    s.culled_vertices.push_back(v);
    s.incident[v] = all_incident[v];
    for (int f : all_incident[v]) face_used[f] = 1;
  }
  for (int f = 0; f < F_body.rows(); ++f) {
    if (face_used[f]) s.normal_faces.push_back(f);
  }
  s.vertex_normal.resize(nv, 3);
  s.vertex_normal_version.assign(nv, -1);
}

BodyCollider::~BodyCollider() = default;
BodyCollider::BodyCollider(BodyCollider&&) noexcept = default;
BodyCollider& BodyCollider::operator=(BodyCollider&&) noexcept = default;

struct BodyFrame::Data {
  const void* owner = nullptr;  // the collider (its Impl) whose culling built it
  Eigen::MatrixXd V, V_dot;
  bool has_velocity = false;
  Eigen::MatrixXd face_normal;  // #Fb by 3 (rows of the collider's normal_faces filled)
  Eigen::MatrixXd vertex_normal;  // #Vb by 3 (rows of the collider's culled_vertices filled)
  std::unique_ptr<TriangleBvh> bvh;  // over the collider's culled faces at V
  double seconds = 0.0;         // wall time of prepare()
};

BodyFrame::BodyFrame() = default;
BodyFrame::~BodyFrame() = default;
BodyFrame::BodyFrame(BodyFrame&&) noexcept = default;
BodyFrame& BodyFrame::operator=(BodyFrame&&) noexcept = default;

BodyFrame BodyCollider::prepare(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd* body_velocity) const {
  const auto t0 = Clock::now();
  const Impl& s = *impl_;
  const int nv = static_cast<int>(s.incident.size());
  if (V_body.rows() < nv || V_body.cols() != 3) throw UsageError("body positions do not match the body faces");
  if (body_velocity && (body_velocity->rows() != V_body.rows() || body_velocity->cols() != 3)) {
    throw UsageError("body velocities must be #Vb by 3");
  }
  for (int v : s.culled_vertices) {
    if (!V_body.row(v).allFinite()) throw GeometryError("non-finite body vertex", "body vertex " + std::to_string(v));
  }
  BodyFrame frame;
  frame.data_ = std::make_unique<BodyFrame::Data>();
  BodyFrame::Data& d = *frame.data_;
  d.owner = &s;
  d.V = V_body;
  d.has_velocity = body_velocity != nullptr;
  if (d.has_velocity) d.V_dot = *body_velocity;
  auto corner = [&](int f, int k) -> Eigen::Vector3d { return V_body.row(s.F(f, k)).transpose(); };
  d.face_normal.resize(s.F.rows(), 3);
  for (int f : s.normal_faces) {
    const Eigen::Vector3d n = (corner(f, 1) - corner(f, 0)).cross(corner(f, 2) - corner(f, 0));
    const double len = n.norm();
    d.face_normal.row(f) = len > 0.0 ? Eigen::RowVector3d((n / len).transpose()) : Eigen::RowVector3d::Zero();
  }
  if (s.threads > 1) {
    d.vertex_normal.resize(V_body.rows(), 3);
    for (int v : s.culled_vertices) d.vertex_normal.row(v) = s.angle_weighted_normal(v, V_body, d.face_normal).transpose();
  }
  {
    std::lock_guard<std::mutex> lock(s.spare_mutex);
    if (!s.spare.empty()) {
      d.bvh = std::move(s.spare.back());
      s.spare.pop_back();
    }
  }
  if (!d.bvh) d.bvh = std::make_unique<TriangleBvh>(static_cast<int>(s.faces.size()));
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> corners(s.faces.size(), 9);
  for (size_t k = 0; k < s.faces.size(); ++k) {
    for (int c = 0; c < 3; ++c) corners.row(k).segment<3>(3 * c) = V_body.row(s.F(s.faces[k], c));
  }
  d.bvh->set_corners(corners);
  d.seconds = seconds_since(t0);
  return frame;
}

void BodyCollider::set_body(BodyFrame frame) {
  Impl& s = *impl_;
  if (!frame.data_ || frame.data_->owner != &s) throw UsageError("set_body needs a frame prepared by this collider");
  BodyFrame::Data& d = *frame.data_;
  s.still = false;
  if (s.built && s.V.rows() == d.V.rows()) {
    double largest = 0.0;
    for (int v : s.culled_vertices) largest = std::max(largest, (d.V.row(v) - s.V.row(v)).norm());
    s.travel += largest;
    s.still = largest == 0.0;
  }
  if (s.bvh) {
    std::lock_guard<std::mutex> lock(s.spare_mutex);
    s.spare.push_back(std::move(s.bvh));
  }
  s.bvh = std::move(d.bvh);
  s.V = std::move(d.V);
  s.V_dot = std::move(d.V_dot);
  s.has_velocity = d.has_velocity;
  s.face_normal = std::move(d.face_normal);
  s.all_vertex_normals = d.vertex_normal.rows() > 0;
  if (s.all_vertex_normals) s.vertex_normal = std::move(d.vertex_normal);
  s.built = true;
  ++s.version;
  s.stats.rebuild_seconds += d.seconds;
}

void BodyCollider::set_body(const Eigen::MatrixXd& V_body, const Eigen::MatrixXd* body_velocity) {
  set_body(prepare(V_body, body_velocity));
}

Proximity BodyCollider::query(const Eigen::Vector3d& p, int hint_face) const {
  return impl_->query(p, hint_face);
}

double BodyCollider::gap(const Proximity& q) const { return impl_->gap(q); }

double BodyCollider::facing_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double radius) const {
  if (!impl_->built) throw UsageError("BodyCollider::facing_distance before set_body");
  if (!p.allFinite() || !n.allFinite()) throw NumericalError("facing_distance of a non-finite point or normal");
  return impl_->facing_distance_of(p, n, radius);
}

std::vector<BodyCollider::NearFeature> BodyCollider::closest_features_within(const Eigen::Vector3d& p,
                                                                            double radius) const {
  if (!impl_->built) throw UsageError("BodyCollider::closest_features_within before set_body");
  if (!p.allFinite()) throw NumericalError("closest_features_within of a non-finite point");
  std::vector<NearFeature> features;
  for (int f : impl_->faces_within(p, radius)) {
    const TriangleClosestPoint q =
        closest_point_on_triangle(p, impl_->corner(f, 0), impl_->corner(f, 1), impl_->corner(f, 2));
    if (!((q.point - p).norm() <= radius)) continue;
    NearFeature n;
    n.point = q.point;
    const int k = feature_index(q.feature);
    if (is_corner(q.feature)) {
      n.kind = 2;
    } else if (is_edge(q.feature)) {
      n.kind = 1;
      n.edge = (impl_->corner(f, (k + 1) % 3) - impl_->corner(f, k)).normalized();
    }
    features.push_back(n);
  }
  return features;
}

void BodyCollider::set_facing_gaps(bool on) { impl_->facing_gaps = on; }

void BodyCollider::resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, double offset) {
  if (!(offset >= 0.0)) throw UsageError("comfort offset must be non-negative");
  impl_->resolve(X, Vel, nullptr, offset);
}

void BodyCollider::resolve(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel, const Eigen::VectorXd& offsets) {
  if (offsets.size() != X.rows()) throw UsageError("one offset per cloth vertex is needed");
  if (!offsets.allFinite()) throw UsageError("comfort offsets must be finite");
  impl_->resolve(X, Vel, offsets.data(), 0.0);
}

std::vector<Contact> BodyCollider::contacts(const Eigen::MatrixXd& X, double offset, double band) {
  if (!(offset >= 0.0) || !(band >= 0.0)) throw UsageError("offset and contact band must be non-negative");
  return impl_->contacts(X, nullptr, offset, band);
}

std::vector<Contact> BodyCollider::contacts(const Eigen::MatrixXd& X, const Eigen::VectorXd& offsets, double band) {
  if (offsets.size() != X.rows()) throw UsageError("one offset per cloth vertex is needed");
  if (!offsets.allFinite() || !(band >= 0.0)) throw UsageError("offsets must be finite and the band non-negative");
  return impl_->contacts(X, offsets.data(), 0.0, band);
}

void BodyCollider::set_min_pinch_offset(double thickness) {
  if (!(thickness >= 0.0) || !std::isfinite(thickness)) throw UsageError("pinch offset must be finite and non-negative");
  impl_->min_pinch_offset = thickness;
}

void BodyCollider::set_threads(int threads) {
  if (threads < 1) throw UsageError("threads must be at least 1");
  impl_->threads = threads;
}

const std::vector<int>& BodyCollider::face_ids() const { return impl_->faces; }
const CollisionStats& BodyCollider::stats() const { return impl_->stats; }
}  // namespace gp::collision
