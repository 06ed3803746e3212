#include "garment/body_clearance.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <numeric>
#include <Eigen/Geometry>

#include "collision/body_collider.h"
#include "collision/ccd.h"
#include "collision/triangle_tree.h"
#include "core/error.h"
#include "core/union_find.h"
#include "geometry/winding_number.h"
#include "mesh/graph_paths.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {

using Eigen::Vector3d;

// A point of the garment that must move: a combination of up to three
// garment vertices, with the garment's normal there.
struct Sample {
  std::array<int, 3> vertex{{-1, -1, -1}};
  std::array<double, 3> weight{{0.0, 0.0, 0.0}};
  Vector3d point = Vector3d::Zero();
  Vector3d normal = Vector3d::Zero();  // unit, the weights' combination of the garment's vertex normals
  int anchor = -1;                     // body vertex nearest the point
  // Where the point may go along the normal, in metres from where it is
  // (see free_interval), on its part's side.
  double low = 0.0, high = 0.0;
  bool room = false;                   // the interval reaches the clearance
  bool way = false;                    // there is an interval at all
};


}  // namespace

BodyClearanceResult clear_body(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_body,
                               const Eigen::MatrixXi& F_body, const std::vector<char>& fixed,
                               const BodyClearanceOptions& options) {
  const int nv = static_cast<int>(V.rows());
  const int nb = static_cast<int>(V_body.rows());
  if (!fixed.empty() && fixed.size() != static_cast<size_t>(nv)) throw UsageError("one fixed flag per garment vertex");
  if (!(options.offset >= 0.0) || !(options.min_clearance > 0.0) || !(options.search > 0.0) ||
      !(options.search_step > 0.0) || !(options.spread > 0.0) || options.membrane_iterations < 0 ||
      !(options.part_radius >= 0.0) || options.max_rounds < 0) {
    throw UsageError("clearance options out of range");
  }
  BodyClearanceResult result;
  result.before = collision::find_crossings(V_body, F_body, V, F);
  const double clearance = std::max(options.offset, options.min_clearance);
  const double threshold = std::max(clearance - options.tolerance, 0.5 * clearance);
  auto is_fixed = [&fixed](int v) { return !fixed.empty() && fixed[static_cast<size_t>(v)]; };

  collision::BodyCollider body(F_body);
  body.set_body(V_body);
  auto signed_distance = [&body](const Vector3d& p, int& hint) {
    const collision::Proximity q = body.query(p, hint);
    hint = q.face;
    return q.signed_distance;
  };
  auto nearest_body_vertex = [&](const Vector3d& p) {
    const collision::Proximity q = body.query(p);
    int best = F_body(q.face, 0);
    for (int k = 1; k < 3; ++k) {
      if ((V_body.row(F_body(q.face, k)).transpose() - q.closest).norm() <
          (V_body.row(best).transpose() - q.closest).norm()) {
        best = F_body(q.face, k);
      }
    }
    return best;
  };
  // Where p may go along unit d: out of the body part it is in (or near),
  // never through a second one. From inside, sphere tracing to the first exit
  // (no exit is nearer than the depth); outside, steps of search_step. The
  // answer is the stretch [low, high] of distances along d with at least the
  // clearance to the body, no longer than the clearance (room), or, where
  // another body part comes first (the distance falls again: a gap narrower
  // than twice the clearance), the middle of the gap alone (no room). `way`
  // is false when the point does not get out within `search` or leaves its
  // own part (`region` labels, inside the body), only finds a gap narrower
  // than twice min_clearance, or finds no room while it has min_clearance
  // already.
  std::vector<int> region(static_cast<size_t>(nb), -1);
  auto free_interval = [&](const Vector3d& p, const Vector3d& d, int part, double& low, double& high, bool& room,
                           bool& way) {
    int hint = -1;
    const double start_sd = signed_distance(p, hint);
    double sd = start_sd;
    double t = 0.0, best_t = -1.0, best_sd = -std::numeric_limits<double>::infinity();
    bool out = sd >= 0.0;
    room = way = false;
    low = high = 0.0;
    if (sd >= clearance) return;  // free where it is
    while (t < options.search) {
      t += sd < 0.0 ? std::max(options.search_step, -sd) : options.search_step;
      sd = signed_distance(p + t * d, hint);
      if (!out) {
        if (sd < 0.0) {
          bool own = false;
          for (int k = 0; k < 3; ++k) own = own || region[static_cast<size_t>(F_body(hint, k))] == part;
          if (!own) return;
          continue;
        }
        out = true;
      }
      // Room, unless a point with some clearance already would travel more
      // than twice its lack of clearance to find it (along a crease, as in
      // an armpit; a point touching the body may leave at a grazing angle).
      if (sd >= clearance &&
          (start_sd < options.min_clearance || t <= 2.0 * (clearance - start_sd) + options.search_step)) {
        room = way = true;
        // At most one clearance further: a point is not to overshoot the
        // nearest free place (the membrane's projections would otherwise
        // leave points asked from several sides far beyond it).
        low = high = t;
        while (high < t + clearance) {
          const double next = high + options.search_step;
          if (signed_distance(p + next * d, hint) < clearance) break;
          high = next;
        }
        return;
      }
      // The best point of a gap: the first within a quarter step of the
      // largest distance (a walk along a narrow channel gains little more).
      if (sd > best_sd + 0.25 * options.search_step || best_t < 0.0) {
        best_sd = sd;
        best_t = t;
      } else if (sd < 0.0 || sd < best_sd - 0.5 * options.search_step) {
        break;  // past the middle of a gap
      }
    }
    // No room: only a point nearer than min_clearance goes to the middle of
    // the gap (one with more clearance stays where it is, as make-garment
    // left it in an armpit).
    way = best_t >= 0.0 && best_sd >= options.min_clearance && start_sd < options.min_clearance;
    if (way) low = high = best_t;
  };

  const std::vector<std::vector<int>> neighbors = vertex_neighbors(F, nv);
  const std::vector<std::vector<int>> body_neighbors = vertex_neighbors(F_body, nb);
  const Eigen::MatrixXi E = unique_edges(F);
  const double mean_edge = E.rows() ? edge_lengths(V, E).mean() : 0.0;
  const Eigen::MatrixXd V_start = V;
  collision::CrossingOptions all_hits;
  all_hits.max_examples = INT_MAX;
  all_hits.depth_reach = 0.0;  // crossings and vertices inside only

  // Per body vertex: the place (index into result.places) whose body part it
  // belongs to, once met; the place keeps its side in every later round.
  std::vector<int> body_place(static_cast<size_t>(nb), -1);
  std::vector<char> met;  // per place: a crossing or a push there (else it is not reported)
  std::vector<double> body_dist(static_cast<size_t>(nb), std::numeric_limits<double>::infinity());
  std::vector<int> reached;

  // Orientation of the garment: +1 when its normals point away from the body
  // (make-garment's and extend-boundary's convention), from the majority of
  // its vertices.
  double facing = 0.0;
  {
    const Eigen::MatrixXd N0 = vertex_normals(V, F);
    int h = -1;
    for (int v = 0; v < nv; ++v) {
      const collision::Proximity q = body.query(V.row(v).transpose(), h);
      h = q.face;
      facing += N0.row(v).dot(q.outward) > 0.0 ? 1.0 : -1.0;
    }
  }
  const int orientation = facing >= 0.0 ? 1 : -1;

  long best_score = result.before.crossings() + result.before.cloth_vertices_inside;
  const int rounds = options.improve_clear || best_score > 0 ? options.max_rounds : 0;
  Eigen::MatrixXd V_best = V;
  // Pushes follow the normals of the garment as given, in every round: the
  // garment's own normals turn sideways on the walls of a dent or a bulge
  // made by the first rounds, and a push along them would run along a finger.
  const Eigen::MatrixXd N = vertex_normals(V, F);
  for (int round = 0; round < rounds; ++round) {
    std::vector<Sample> samples;
    Eigen::VectorXd sd(nv);
    int hint = -1;
    for (int v = 0; v < nv; ++v) {
      sd(v) = signed_distance(V.row(v).transpose(), hint);
      if (is_fixed(v) || !(sd(v) < threshold)) continue;
      Sample s;
      s.vertex = {v, -1, -1};
      s.weight = {1.0, 0.0, 0.0};
      s.point = V.row(v).transpose();
      s.normal = N.row(v).transpose();
      samples.push_back(s);
    }
    // The points where the surfaces pass through each other.
    const collision::CrossingReport hits = collision::find_crossings(V_body, F_body, V, F, all_hits);
    for (const collision::EdgeFaceHit& h : hits.body_edge_examples) {
      const Vector3d a = V_body.row(h.a), b = V_body.row(h.b);
      const Vector3d p = V.row(F(h.face, 0)), q = V.row(F(h.face, 1)), r = V.row(F(h.face, 2));
      const Vector3d x = a + collision::segment_plane_parameter(a, b, p, q, r) * (b - a);
      const Vector3d w = collision::closest_triangle_weights(x, p, q, r);
      Sample s;
      s.vertex = {F(h.face, 0), F(h.face, 1), F(h.face, 2)};
      s.weight = {w(0), w(1), w(2)};
      s.point = x;
      s.normal = (w(0) * N.row(F(h.face, 0)) + w(1) * N.row(F(h.face, 1)) + w(2) * N.row(F(h.face, 2))).transpose();
      s.anchor = (x - a).norm() <= (x - b).norm() ? h.a : h.b;
      samples.push_back(s);
    }
    for (const collision::EdgeFaceHit& h : hits.cloth_edge_examples) {
      const Vector3d a = V.row(h.a), b = V.row(h.b);
      const double t = collision::segment_plane_parameter(a, b, V_body.row(F_body(h.face, 0)),
                                                          V_body.row(F_body(h.face, 1)), V_body.row(F_body(h.face, 2)));
      Sample s;
      s.vertex = {h.a, h.b, -1};
      s.weight = {1.0 - t, t, 0.0};
      s.point = a + t * (b - a);
      s.normal = ((1.0 - t) * N.row(h.a) + t * N.row(h.b)).transpose();
      samples.push_back(s);
    }
    // Samples that cannot move (every vertex fixed) or have no direction stay.
    samples.erase(std::remove_if(samples.begin(), samples.end(),
                                 [&](Sample& s) {
                                   bool movable = false;
                                   for (int k = 0; k < 3; ++k) {
                                     movable = movable || (s.vertex[k] >= 0 && s.weight[k] > 0.0 && !is_fixed(s.vertex[k]));
                                   }
                                   const double len = s.normal.norm();
                                   if (len > 0.0) s.normal /= len;
                                   return !movable || !(len > 0.0);
                                 }),
                  samples.end());
    if (samples.empty()) break;
    ++result.rounds;

    // Body parts met: samples whose nearest body vertices lie within
    // part_radius of each other along the body belong together (the fingers
    // and the palm of a hand; not a hand and the hip beside it, which are far
    // apart along the body), and with a place met in an earlier round.
    std::vector<char> anchored(static_cast<size_t>(nb), 0);
    std::vector<int> anchors;
    for (Sample& s : samples) {
      if (s.anchor < 0) s.anchor = nearest_body_vertex(s.point);
      if (!anchored[static_cast<size_t>(s.anchor)]) anchors.push_back(s.anchor);
      anchored[static_cast<size_t>(s.anchor)] = 1;
    }
    std::sort(anchors.begin(), anchors.end());
    UnionFind sets(static_cast<size_t>(nb));
    auto join = [&sets](int a, int b) { sets.unite(a, b); };
    std::vector<std::vector<int>> disc_of(anchors.size());
    std::vector<int> known_place(static_cast<size_t>(nb), -1);  // per root: an earlier place
    for (size_t i = 0; i < anchors.size(); ++i) {
      edge_distances(V_body, body_neighbors, {anchors[i]}, options.part_radius, body_dist, reached);
      for (int w : reached) {
        if (anchored[static_cast<size_t>(w)]) join(anchors[i], w);
        body_dist[static_cast<size_t>(w)] = std::numeric_limits<double>::infinity();
      }
      disc_of[i] = reached;
    }
    for (size_t i = 0; i < anchors.size(); ++i) {
      const int root = sets.find(anchors[i]);
      for (int w : disc_of[i]) {
        const int place = body_place[static_cast<size_t>(w)];
        if (place >= 0 && (known_place[static_cast<size_t>(root)] < 0 || place < known_place[static_cast<size_t>(root)])) {
          known_place[static_cast<size_t>(root)] = place;
        }
      }
    }
    // Each part's region: its body vertices within twice part_radius of its
    // points (for the pushes, and the vote below).
    std::vector<std::vector<int>> voters(static_cast<size_t>(nb));
    std::fill(region.begin(), region.end(), -1);
    for (size_t i = 0; i < anchors.size(); ++i) {
      const int root = sets.find(anchors[i]);
      edge_distances(V_body, body_neighbors, {anchors[i]}, 2.0 * options.part_radius, body_dist, reached);
      for (int w : reached) {
        voters[static_cast<size_t>(root)].push_back(w);
        if (region[static_cast<size_t>(w)] < 0) region[static_cast<size_t>(w)] = root;
        body_dist[static_cast<size_t>(w)] = std::numeric_limits<double>::infinity();
      }
    }
    // Free stretches both ways, and their costs for choosing a side: the
    // distance to the stretch, one search length more without room for the
    // clearance, two without a way out.
    struct Both {
      double low[2], high[2];
      bool room[2], way[2];
    };
    std::vector<Both> both(samples.size());
    std::vector<double> cost_plus(static_cast<size_t>(nb), 0.0), cost_minus(static_cast<size_t>(nb), 0.0);
    for (size_t i = 0; i < samples.size(); ++i) {
      const Sample& s = samples[i];
      const int root = sets.find(s.anchor);
      Both& b = both[i];
      free_interval(s.point, s.normal, root, b.low[0], b.high[0], b.room[0], b.way[0]);
      free_interval(s.point, -s.normal, root, b.low[1], b.high[1], b.room[1], b.way[1]);
      auto cost = [&](int k) {
        return !b.way[k] ? 2.0 * options.search : b.low[k] + (b.room[k] ? 0.0 : options.search);
      };
      cost_plus[static_cast<size_t>(root)] += cost(0);
      cost_minus[static_cast<size_t>(root)] += cost(1);
    }
    // A part met before keeps its side. A new part keeps to the side of the
    // garment where most of it lies: inside (the hips in a skirt) pushes the
    // garment outwards, outside (a hand beside it) inwards, by the winding
    // number of the garment at up to 64 of its region's body vertices;
    // undecided (between 0.35 and 0.65), the side of the smaller total cost.
    std::vector<int> place_of(static_cast<size_t>(nb), -1);
    for (int a : anchors) {
      const int root = sets.find(a);
      if (place_of[static_cast<size_t>(root)] >= 0) continue;
      int place = known_place[static_cast<size_t>(root)];
      if (place < 0) {
        std::vector<int>& vote = voters[static_cast<size_t>(root)];
        std::sort(vote.begin(), vote.end());
        vote.erase(std::unique(vote.begin(), vote.end()), vote.end());
        const size_t stride = std::max<size_t>(1, vote.size() / 64);
        double inside = 0.0;
        int count = 0;
        for (size_t k = 0; k < vote.size(); k += stride, ++count) {
          inside += orientation * winding_number(V, F, V_body.row(vote[k]).transpose());
        }
        inside /= std::max(count, 1);
        ClearancePlace p;
        if (inside > 0.65) p.side = orientation;
        else if (inside < 0.35) p.side = -orientation;
        else p.side = cost_minus[static_cast<size_t>(root)] < cost_plus[static_cast<size_t>(root)] ? -1 : 1;
        p.body_vertex = root;
        place = static_cast<int>(result.places.size());
        result.places.push_back(p);
      }
      place_of[static_cast<size_t>(root)] = place;
    }
    for (size_t i = 0; i < anchors.size(); ++i) {
      const int place = place_of[static_cast<size_t>(sets.find(anchors[i]))];
      for (int w : disc_of[i]) {
        if (body_place[static_cast<size_t>(w)] < 0) body_place[static_cast<size_t>(w)] = place;
      }
    }
    // Each sample's constraint on its part's side: its displacement along the
    // normal, sum_k w_k s_k (s per garment vertex), within [low, high].
    double round_push = 0.0;
    met.resize(result.places.size(), 0);
    for (size_t i = 0; i < samples.size(); ++i) {
      Sample& s = samples[i];
      ClearancePlace& place = result.places[static_cast<size_t>(place_of[static_cast<size_t>(sets.find(s.anchor))])];
      const int k = place.side > 0 ? 0 : 1;
      s.way = both[i].way[k];
      s.room = both[i].room[k];
      place.room = place.room && s.room;
      // A vertex with some clearance and no room here only stays as it is.
      const bool through = s.vertex[1] >= 0 || sd(s.vertex[0]) < options.min_clearance;
      if (s.way || through) met[static_cast<size_t>(place_of[static_cast<size_t>(sets.find(s.anchor))])] = 1;
      if (!s.way) continue;  // no way out on this side: left for the report
      s.low = place.side > 0 ? both[i].low[0] : -both[i].high[1];
      s.high = place.side > 0 ? both[i].high[0] : -both[i].low[1];
      place.largest_push = std::max(place.largest_push, std::min(std::abs(s.low), std::abs(s.high)));
      round_push = std::max(round_push, std::min(std::abs(s.low), std::abs(s.high)));
    }
    // The displacement s along the vertex normals: a membrane over the garment
    // (Jacobi steps s_i <- sum_j s_j / (deg_i + mu_i), which decay away from
    // the constraints over a length l, mu_i = deg_i (edge / l)^2) with every
    // constraint projected after each step, each moving its vertices by their
    // weight over the sum of squared weights (as a contact response), fixed
    // vertices held at zero. l is `spread`, or one and a half times the
    // round's largest push where that is more, so that a deep dent (a skirt
    // taken through a hand) gets walls no steeper than about 35 degrees.
    Eigen::VectorXd disp = Eigen::VectorXd::Zero(nv), next(nv);
    const double length = std::max(options.spread, 1.5 * round_push);
    const double decay = (mean_edge / length) * (mean_edge / length);
    std::vector<char> active(static_cast<size_t>(nv), 0);  // within reach of a constraint
    for (const Sample& s : samples) {
      if (!s.way) continue;
      for (int k = 0; k < 3; ++k) {
        if (s.vertex[k] >= 0) active[static_cast<size_t>(s.vertex[k])] = 1;
      }
    }
    {
      // Reach: garment vertices within two decay lengths of a constrained one.
      std::vector<int> sources, reached_garment;
      for (int v = 0; v < nv; ++v) {
        if (active[static_cast<size_t>(v)]) sources.push_back(v);
      }
      std::vector<double> reach(static_cast<size_t>(nv), std::numeric_limits<double>::infinity());
      edge_distances(V, neighbors, sources, 2.0 * length, reach, reached_garment);
      for (int v : reached_garment) active[static_cast<size_t>(v)] = 1;
    }
    for (int it = 0; it < options.membrane_iterations; ++it) {
      next = disp;
      for (int v = 0; v < nv; ++v) {
        if (!active[static_cast<size_t>(v)] || is_fixed(v)) continue;
        const auto& ring = neighbors[static_cast<size_t>(v)];
        double sum = 0.0;
        for (int w : ring) sum += disp(w);
        next(v) = sum / (static_cast<double>(ring.size()) * (1.0 + decay));
      }
      disp.swap(next);
      for (const Sample& s : samples) {
        if (!s.way) continue;
        double value = 0.0, free_weight = 0.0;
        for (int k = 0; k < 3; ++k) {
          if (s.vertex[k] < 0) continue;
          value += s.weight[k] * disp(s.vertex[k]);
          if (!is_fixed(s.vertex[k])) free_weight += s.weight[k] * s.weight[k];
        }
        const double target = std::clamp(value, s.low, s.high);
        if (target == value || !(free_weight > 0.0)) continue;
        for (int k = 0; k < 3; ++k) {
          const int v = s.vertex[k];
          if (v >= 0 && !is_fixed(v)) disp(v) += s.weight[k] * (target - value) / free_weight;
        }
      }
    }
    // Vertices no point asked to move only follow as far as they do not come
    // closer to the body than they were (or than the clearance): in an
    // armpit next to a dent the normals turn, and the fading displacement
    // would carry them into the arm. Their move is halved up to three times,
    // then dropped.
    std::vector<char> asked(static_cast<size_t>(nv), 0);
    for (const Sample& s : samples) {
      for (int k = 0; k < 3; ++k) {
        if (s.way && s.vertex[k] >= 0 && s.weight[k] > 0.0) asked[static_cast<size_t>(s.vertex[k])] = 1;
      }
    }
    hint = -1;
    for (int v = 0; v < nv; ++v) {
      if (is_fixed(v) || disp(v) == 0.0) continue;
      double m = disp(v);
      if (!asked[static_cast<size_t>(v)]) {
        const double keep = std::min(sd(v), clearance);
        for (int halvings = 0; halvings < 4; ++halvings) {
          if (signed_distance(V.row(v).transpose() + m * N.row(v).transpose(), hint) >= keep) break;
          m = halvings < 3 ? 0.5 * m : 0.0;
        }
      }
      V.row(v) += m * N.row(v);
    }
    // The best state so far (fewest crossings plus vertices inside) is what
    // is returned, should a round make things worse; the first clear one ends
    // the rounds.
    const collision::CrossingReport now = collision::find_crossings(V_body, F_body, V, F, all_hits);
    const long score = now.crossings() + now.cloth_vertices_inside;
    if (score < best_score || score == 0) {
      best_score = score;
      V_best = V;
    }
    if (score == 0) break;  // clear: what is left is closer than the offset without room
  }
  V = V_best;

  // Places: centre and size from the body vertices of their part.
  std::vector<int> members(result.places.size(), 0);
  for (int b = 0; b < nb; ++b) {
    const int place = body_place[static_cast<size_t>(b)];
    if (place < 0) continue;
    result.places[static_cast<size_t>(place)].center += V_body.row(b).transpose();
    ++members[static_cast<size_t>(place)];
  }
  std::vector<ClearancePlace> places;
  for (size_t k = 0; k < result.places.size(); ++k) {
    if (members[k] > 0) result.places[k].center /= members[k];
    if (k < met.size() && met[k]) places.push_back(result.places[k]);
  }
  result.places = std::move(places);
  result.after = collision::find_crossings(V_body, F_body, V, F);
  int hint = -1;
  result.min_distance = nv > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  for (int v = 0; v < nv; ++v) {
    const double d = signed_distance(V.row(v).transpose(), hint);
    result.min_distance = std::min(result.min_distance, d);
    if (d < threshold) ++result.tight_vertices;
    const double move = (V.row(v) - V_start.row(v)).norm();
    if (move > 0.0) ++result.moved_vertices;
    result.largest_move = std::max(result.largest_move, move);
  }
  return result;
}

OrderedJson to_json(const BodyClearanceResult& r) {
  OrderedJson places = OrderedJson::array();
  for (const ClearancePlace& p : r.places) {
    places.push_back({{"body_vertex", p.body_vertex},
                      {"center", {p.center.x(), p.center.y(), p.center.z()}},
                      {"side", p.side > 0 ? "along_normals" : "against_normals"},
                      {"largest_push_m", p.largest_push},
                      {"room", p.room}});
  }
  OrderedJson j;
  j["clear"] = r.clear();
  j["rounds"] = r.rounds;
  j["moved_vertices"] = r.moved_vertices;
  j["largest_move_m"] = r.largest_move;
  j["tight_vertices"] = r.tight_vertices;
  j["min_distance_m"] = r.min_distance;
  j["places"] = places;
  j["before"] = collision::to_json(r.before);
  j["after"] = collision::to_json(r.after);
  return j;
}

}  // namespace gp
