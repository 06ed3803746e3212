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


// Free stretches along a sample's normal both ways ([0] along, [1] against).
struct Both {
  double low[2], high[2];
  bool room[2], way[2];
};

// The body parts one round met: samples grouped by their anchors (union-find
// over the body's vertices), each group's place in result.places.
struct RoundParts {
  std::vector<int> anchors;                 // sorted, distinct anchor body vertices
  UnionFind sets{0};                        // over the body's vertices
  std::vector<std::vector<int>> disc_of;    // per anchor: body vertices within part_radius
  std::vector<int> known_place;             // per root: a place of an earlier round, -1
  std::vector<std::vector<int>> voters;     // per root: body vertices within twice part_radius
  std::vector<int> place_of;                // per root: its place
  int place(const Sample& s) { return place_of[static_cast<size_t>(sets.find(s.anchor))]; }
};

// One call of clear_body: the body, the garment's fixed data, and what the
// rounds share (the places met, per body vertex).
class Clearance {
 public:
  Clearance(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
            const std::vector<char>& fixed, const BodyClearanceOptions& options, BodyClearanceResult& result)
      : V_(V), F_(F), V_body_(V_body), F_body_(F_body), fixed_(fixed), o_(options), result_(result),
        nv_(static_cast<int>(V.rows())), nb_(static_cast<int>(V_body.rows())), body_(F_body) {
    clearance_ = std::max(options.offset, options.min_clearance);
    threshold_ = std::max(clearance_ - options.tolerance, 0.5 * clearance_);
    body_.set_body(V_body);
    region_.assign(static_cast<size_t>(nb_), -1);
    neighbors_ = vertex_neighbors(F, nv_);
    body_neighbors_ = vertex_neighbors(F_body, nb_);
    const Eigen::MatrixXi E = unique_edges(F);
    mean_edge_ = E.rows() ? edge_lengths(V, E).mean() : 0.0;
    V_start_ = V;
    all_hits_.max_examples = INT_MAX;
    all_hits_.depth_reach = 0.0;  // crossings and vertices inside only
    body_place_.assign(static_cast<size_t>(nb_), -1);
    body_dist_.assign(static_cast<size_t>(nb_), std::numeric_limits<double>::infinity());
    // Pushes follow the normals of the garment as given, in every round: the
    // garment's own normals turn sideways on the walls of a dent or a bulge
    // made by the first rounds, and a push along them would run along a finger.
    N_ = vertex_normals(V, F);
  }

  // The rounds, up to max_rounds; V ends as the best round's garment.
  void run() {
    const int orientation = garment_orientation();
    long best_score = result_.before.crossings() + result_.before.cloth_vertices_inside;
    const int rounds = o_.improve_clear || best_score > 0 ? o_.max_rounds : 0;
    Eigen::MatrixXd V_best = V_;
    for (int round = 0; round < rounds; ++round) {
      Eigen::VectorXd sd(nv_);
      std::vector<Sample> samples = round_samples(sd);
      if (samples.empty()) break;
      ++result_.rounds;
      RoundParts parts = group_parts(samples);
      mark_regions(parts);
      std::vector<Both> both(samples.size());
      choose_sides(samples, orientation, parts, both);
      const double round_push = constrain(samples, both, sd, parts);
      const Eigen::VectorXd disp = membrane(samples, round_push);
      move(samples, sd, disp);
      // The best state so far (fewest crossings plus vertices inside) is what
      // is returned, should a round make things worse; the first clear one ends
      // the rounds.
      const collision::CrossingReport now = collision::find_crossings(V_body_, F_body_, V_, F_, all_hits_);
      const long score = now.crossings() + now.cloth_vertices_inside;
      if (score < best_score || score == 0) {
        best_score = score;
        V_best = V_;
      }
      if (score == 0) break;  // clear: what is left is closer than the offset without room
    }
    V_ = V_best;
  }

  // The places' centres and the figures of the garment returned.
  void finish() {
    // Places: centre and size from the body vertices of their part.
    std::vector<int> members(result_.places.size(), 0);
    for (int b = 0; b < nb_; ++b) {
      const int place = body_place_[static_cast<size_t>(b)];
      if (place < 0) continue;
      result_.places[static_cast<size_t>(place)].center += V_body_.row(b).transpose();
      ++members[static_cast<size_t>(place)];
    }
    std::vector<ClearancePlace> places;
    for (size_t k = 0; k < result_.places.size(); ++k) {
      if (members[k] > 0) result_.places[k].center /= members[k];
      if (k < met_.size() && met_[k]) places.push_back(result_.places[k]);
    }
    result_.places = std::move(places);
    result_.after = collision::find_crossings(V_body_, F_body_, V_, F_);
    int hint = -1;
    result_.min_distance = nv_ > 0 ? std::numeric_limits<double>::infinity() : 0.0;
    for (int v = 0; v < nv_; ++v) {
      const double d = signed_distance(V_.row(v).transpose(), hint);
      result_.min_distance = std::min(result_.min_distance, d);
      if (d < threshold_) ++result_.tight_vertices;
      const double move = (V_.row(v) - V_start_.row(v)).norm();
      if (move > 0.0) ++result_.moved_vertices;
      result_.largest_move = std::max(result_.largest_move, move);
    }
  }

 private:
  bool is_fixed(int v) const { return !fixed_.empty() && fixed_[static_cast<size_t>(v)]; }

  double signed_distance(const Vector3d& p, int& hint) const {
    const collision::Proximity q = body_.query(p, hint);
    hint = q.face;
    return q.signed_distance;
  }

  int nearest_body_vertex(const Vector3d& p) const {
    const collision::Proximity q = body_.query(p);
    int best = F_body_(q.face, 0);
    for (int k = 1; k < 3; ++k) {
      if ((V_body_.row(F_body_(q.face, k)).transpose() - q.closest).norm() <
          (V_body_.row(best).transpose() - q.closest).norm()) {
        best = F_body_(q.face, k);
      }
    }
    return best;
  }

  // Orientation of the garment: +1 when its normals point away from the body
  // (make-garment's and extend-boundary's convention), from the majority of
  // its vertices.
  int garment_orientation() const {
    double facing = 0.0;
    const Eigen::MatrixXd N0 = vertex_normals(V_, F_);
    int h = -1;
    for (int v = 0; v < nv_; ++v) {
      const collision::Proximity q = body_.query(V_.row(v).transpose(), h);
      h = q.face;
      facing += N0.row(v).dot(q.outward) > 0.0 ? 1.0 : -1.0;
    }
    return facing >= 0.0 ? 1 : -1;
  }

  // Where p may go along unit d: out of the body part it is in (or near),
  // never through a second one. From inside, sphere tracing to the first exit
  // (no exit is nearer than the depth); outside, steps of search_step. The
  // answer is the stretch [low, high] of distances along d with at least the
  // clearance to the body, no longer than the clearance (room), or, where
  // another body part comes first (the distance falls again: a gap narrower
  // than twice the clearance), the middle of the gap alone (no room). `way`
  // is false when the point does not get out within `search` or leaves its
  // own part (`region_` labels, inside the body), only finds a gap narrower
  // than twice min_clearance, or finds no room while it has min_clearance
  // already.
  void free_interval(const Vector3d& p, const Vector3d& d, int part, double& low, double& high, bool& room,
                     bool& way) const {
    int hint = -1;
    const double start_sd = signed_distance(p, hint);
    double sd = start_sd;
    double t = 0.0, best_t = -1.0, best_sd = -std::numeric_limits<double>::infinity();
    bool out = sd >= 0.0;
    room = way = false;
    low = high = 0.0;
    if (sd >= clearance_) return;  // free where it is
    while (t < o_.search) {
      t += sd < 0.0 ? std::max(o_.search_step, -sd) : o_.search_step;
      sd = signed_distance(p + t * d, hint);
      if (!out) {
        if (sd < 0.0) {
          bool own = false;
          for (int k = 0; k < 3; ++k) own = own || region_[static_cast<size_t>(F_body_(hint, k))] == part;
          if (!own) return;
          continue;
        }
        out = true;
      }
      // Room, unless a point with some clearance already would travel more
      // than twice its lack of clearance to find it (along a crease, as in
      // an armpit; a point touching the body may leave at a grazing angle).
      if (sd >= clearance_ &&
          (start_sd < o_.min_clearance || t <= 2.0 * (clearance_ - start_sd) + o_.search_step)) {
        room = way = true;
        // At most one clearance further: a point is not to overshoot the
        // nearest free place (the membrane's projections would otherwise
        // leave points asked from several sides far beyond it).
        low = high = t;
        while (high < t + clearance_) {
          const double next = high + o_.search_step;
          if (signed_distance(p + next * d, hint) < clearance_) break;
          high = next;
        }
        return;
      }
      // The best point of a gap: the first within a quarter step of the
      // largest distance (a walk along a narrow channel gains little more).
      if (sd > best_sd + 0.25 * o_.search_step || best_t < 0.0) {
        best_sd = sd;
        best_t = t;
      } else if (sd < 0.0 || sd < best_sd - 0.5 * o_.search_step) {
        break;  // past the middle of a gap
      }
    }
    // No room: only a point nearer than min_clearance goes to the middle of
    // the gap (one with more clearance stays where it is, as make-garment
    // left it in an armpit).
    way = best_t >= 0.0 && best_sd >= o_.min_clearance && start_sd < o_.min_clearance;
    if (way) low = high = best_t;
  }

  // The points of the garment that must move this round: vertices closer
  // than the threshold, and the points where the surfaces pass through each
  // other; sd gets every vertex's signed distance.
  std::vector<Sample> round_samples(Eigen::VectorXd& sd) const {
    std::vector<Sample> samples;
    int hint = -1;
    for (int v = 0; v < nv_; ++v) {
      sd(v) = signed_distance(V_.row(v).transpose(), hint);
      if (is_fixed(v) || !(sd(v) < threshold_)) continue;
      Sample s;
      s.vertex = {v, -1, -1};
      s.weight = {1.0, 0.0, 0.0};
      s.point = V_.row(v).transpose();
      s.normal = N_.row(v).transpose();
      samples.push_back(s);
    }
    const collision::CrossingReport hits = collision::find_crossings(V_body_, F_body_, V_, F_, all_hits_);
    for (const collision::EdgeFaceHit& h : hits.body_edge_examples) {
      const Vector3d a = V_body_.row(h.a), b = V_body_.row(h.b);
      const Vector3d p = V_.row(F_(h.face, 0)), q = V_.row(F_(h.face, 1)), r = V_.row(F_(h.face, 2));
      const Vector3d x = a + collision::segment_plane_parameter(a, b, p, q, r) * (b - a);
      const Vector3d w = collision::closest_triangle_weights(x, p, q, r);
      Sample s;
      s.vertex = {F_(h.face, 0), F_(h.face, 1), F_(h.face, 2)};
      s.weight = {w(0), w(1), w(2)};
      s.point = x;
      s.normal = (w(0) * N_.row(F_(h.face, 0)) + w(1) * N_.row(F_(h.face, 1)) + w(2) * N_.row(F_(h.face, 2))).transpose();
      s.anchor = (x - a).norm() <= (x - b).norm() ? h.a : h.b;
      samples.push_back(s);
    }
    for (const collision::EdgeFaceHit& h : hits.cloth_edge_examples) {
      const Vector3d a = V_.row(h.a), b = V_.row(h.b);
      const double t = collision::segment_plane_parameter(a, b, V_body_.row(F_body_(h.face, 0)),
                                                          V_body_.row(F_body_(h.face, 1)), V_body_.row(F_body_(h.face, 2)));
      Sample s;
      s.vertex = {h.a, h.b, -1};
      s.weight = {1.0 - t, t, 0.0};
      s.point = a + t * (b - a);
      s.normal = ((1.0 - t) * N_.row(h.a) + t * N_.row(h.b)).transpose();
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
    return samples;
  }

  // Body parts met: samples whose nearest body vertices lie within
  // part_radius of each other along the body belong together (the fingers
  // and the palm of a hand; not a hand and the hip beside it, which are far
  // apart along the body), and with a place met in an earlier round.
  RoundParts group_parts(std::vector<Sample>& samples) {
    RoundParts parts;
    std::vector<char> anchored(static_cast<size_t>(nb_), 0);
    for (Sample& s : samples) {
      if (s.anchor < 0) s.anchor = nearest_body_vertex(s.point);
      if (!anchored[static_cast<size_t>(s.anchor)]) parts.anchors.push_back(s.anchor);
      anchored[static_cast<size_t>(s.anchor)] = 1;
    }
    std::vector<int>& anchors = parts.anchors;
    std::sort(anchors.begin(), anchors.end());
    parts.sets = UnionFind(static_cast<size_t>(nb_));
    parts.disc_of.resize(anchors.size());
    parts.known_place.assign(static_cast<size_t>(nb_), -1);
    for (size_t i = 0; i < anchors.size(); ++i) {
      edge_distances(V_body_, body_neighbors_, {anchors[i]}, o_.part_radius, body_dist_, reached_);
      for (int w : reached_) {
        if (anchored[static_cast<size_t>(w)]) parts.sets.unite(anchors[i], w);
        body_dist_[static_cast<size_t>(w)] = std::numeric_limits<double>::infinity();
      }
      parts.disc_of[i] = reached_;
    }
    for (size_t i = 0; i < anchors.size(); ++i) {
      const int root = parts.sets.find(anchors[i]);
      for (int w : parts.disc_of[i]) {
        const int place = body_place_[static_cast<size_t>(w)];
        int& known = parts.known_place[static_cast<size_t>(root)];
        if (place >= 0 && (known < 0 || place < known)) known = place;
      }
    }
    return parts;
  }

  // Each part's region: its body vertices within twice part_radius of its
  // points (for the pushes, and the vote of choose_sides).
  void mark_regions(RoundParts& parts) {
    parts.voters.assign(static_cast<size_t>(nb_), {});
    std::fill(region_.begin(), region_.end(), -1);
    for (size_t i = 0; i < parts.anchors.size(); ++i) {
      const int root = parts.sets.find(parts.anchors[i]);
      edge_distances(V_body_, body_neighbors_, {parts.anchors[i]}, 2.0 * o_.part_radius, body_dist_, reached_);
      for (int w : reached_) {
        parts.voters[static_cast<size_t>(root)].push_back(w);
        if (region_[static_cast<size_t>(w)] < 0) region_[static_cast<size_t>(w)] = root;
        body_dist_[static_cast<size_t>(w)] = std::numeric_limits<double>::infinity();
      }
    }
  }

  // Free stretches both ways (into `both`), and the side of each part. A part
  // met before keeps its side. A new part keeps to the side of the garment
  // where most of it lies: inside (the hips in a skirt) pushes the garment
  // outwards, outside (a hand beside it) inwards, by the winding number of
  // the garment at up to 64 of its region's body vertices; undecided
  // (between 0.35 and 0.65), the side of the smaller total cost: the distance
  // to the stretch, one search length more without room for the clearance,
  // two without a way out.
  void choose_sides(const std::vector<Sample>& samples, int orientation, RoundParts& parts, std::vector<Both>& both) {
    std::vector<double> cost_plus(static_cast<size_t>(nb_), 0.0), cost_minus(static_cast<size_t>(nb_), 0.0);
    for (size_t i = 0; i < samples.size(); ++i) {
      const Sample& s = samples[i];
      const int root = parts.sets.find(s.anchor);
      Both& b = both[i];
      free_interval(s.point, s.normal, root, b.low[0], b.high[0], b.room[0], b.way[0]);
      free_interval(s.point, -s.normal, root, b.low[1], b.high[1], b.room[1], b.way[1]);
      auto cost = [&](int k) { return !b.way[k] ? 2.0 * o_.search : b.low[k] + (b.room[k] ? 0.0 : o_.search); };
      cost_plus[static_cast<size_t>(root)] += cost(0);
      cost_minus[static_cast<size_t>(root)] += cost(1);
    }
    parts.place_of.assign(static_cast<size_t>(nb_), -1);
    for (int a : parts.anchors) {
      const int root = parts.sets.find(a);
      if (parts.place_of[static_cast<size_t>(root)] >= 0) continue;
      int place = parts.known_place[static_cast<size_t>(root)];
      if (place < 0) {
        std::vector<int>& vote = parts.voters[static_cast<size_t>(root)];
        std::sort(vote.begin(), vote.end());
        vote.erase(std::unique(vote.begin(), vote.end()), vote.end());
        const size_t stride = std::max<size_t>(1, vote.size() / 64);
        double inside = 0.0;
        int count = 0;
        for (size_t k = 0; k < vote.size(); k += stride, ++count) {
          inside += orientation * winding_number(V_, F_, V_body_.row(vote[k]).transpose());
        }
        inside /= std::max(count, 1);
        ClearancePlace p;
        if (inside > 0.65) p.side = orientation;
        else if (inside < 0.35) p.side = -orientation;
        else p.side = cost_minus[static_cast<size_t>(root)] < cost_plus[static_cast<size_t>(root)] ? -1 : 1;
        p.body_vertex = root;
        place = static_cast<int>(result_.places.size());
        result_.places.push_back(p);
      }
      parts.place_of[static_cast<size_t>(root)] = place;
    }
    for (size_t i = 0; i < parts.anchors.size(); ++i) {
      const int place = parts.place_of[static_cast<size_t>(parts.sets.find(parts.anchors[i]))];
      for (int w : parts.disc_of[i]) {
        if (body_place_[static_cast<size_t>(w)] < 0) body_place_[static_cast<size_t>(w)] = place;
      }
    }
  }

  // Each sample's constraint on its part's side: its displacement along the
  // normal, sum_k w_k s_k (s per garment vertex), within [low, high].
  // Returns the round's largest push.
  double constrain(std::vector<Sample>& samples, const std::vector<Both>& both, const Eigen::VectorXd& sd,
                   RoundParts& parts) {
    double round_push = 0.0;
    met_.resize(result_.places.size(), 0);
    for (size_t i = 0; i < samples.size(); ++i) {
      Sample& s = samples[i];
      const int place_index = parts.place(s);
      ClearancePlace& place = result_.places[static_cast<size_t>(place_index)];
      const int k = place.side > 0 ? 0 : 1;
      s.way = both[i].way[k];
      s.room = both[i].room[k];
      place.room = place.room && s.room;
      // A vertex with some clearance and no room here only stays as it is.
      const bool through = s.vertex[1] >= 0 || sd(s.vertex[0]) < o_.min_clearance;
      if (s.way || through) met_[static_cast<size_t>(place_index)] = 1;
      if (!s.way) continue;  // no way out on this side: left for the report
      s.low = place.side > 0 ? both[i].low[0] : -both[i].high[1];
      s.high = place.side > 0 ? both[i].high[0] : -both[i].low[1];
      place.largest_push = std::max(place.largest_push, std::min(std::abs(s.low), std::abs(s.high)));
      round_push = std::max(round_push, std::min(std::abs(s.low), std::abs(s.high)));
    }
    return round_push;
  }

  // The displacement s along the vertex normals: a membrane over the garment
  // (Jacobi steps s_i <- sum_j s_j / (deg_i + mu_i), which decay away from
  // the constraints over a length l, mu_i = deg_i (edge / l)^2) with every
  // constraint projected after each step, each moving its vertices by their
  // weight over the sum of squared weights (as a contact response), fixed
  // vertices held at zero. l is `spread`, or one and a half times the
  // round's largest push where that is more, so that a deep dent (a skirt
  // taken through a hand) gets walls no steeper than about 35 degrees.
  Eigen::VectorXd membrane(const std::vector<Sample>& samples, double round_push) const {
    Eigen::VectorXd disp = Eigen::VectorXd::Zero(nv_), next(nv_);
    const double length = std::max(o_.spread, 1.5 * round_push);
    const double decay = (mean_edge_ / length) * (mean_edge_ / length);
    std::vector<char> active(static_cast<size_t>(nv_), 0);  // within reach of a constraint
    for (const Sample& s : samples) {
      if (!s.way) continue;
      for (int k = 0; k < 3; ++k) {
        if (s.vertex[k] >= 0) active[static_cast<size_t>(s.vertex[k])] = 1;
      }
    }
    {
      // Reach: garment vertices within two decay lengths of a constrained one.
      std::vector<int> sources, reached_garment;
      for (int v = 0; v < nv_; ++v) {
        if (active[static_cast<size_t>(v)]) sources.push_back(v);
      }
      std::vector<double> reach(static_cast<size_t>(nv_), std::numeric_limits<double>::infinity());
      edge_distances(V_, neighbors_, sources, 2.0 * length, reach, reached_garment);
      for (int v : reached_garment) active[static_cast<size_t>(v)] = 1;
    }
    for (int it = 0; it < o_.membrane_iterations; ++it) {
      next = disp;
      for (int v = 0; v < nv_; ++v) {
        if (!active[static_cast<size_t>(v)] || is_fixed(v)) continue;
        const auto& ring = neighbors_[static_cast<size_t>(v)];
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
    return disp;
  }

  // Moves the garment by disp along the normals. Vertices no point asked to
  // move only follow as far as they do not come closer to the body than they
  // were (or than the clearance): in an armpit next to a dent the normals
  // turn, and the fading displacement would carry them into the arm. Their
  // move is halved up to three times, then dropped.
  void move(const std::vector<Sample>& samples, const Eigen::VectorXd& sd, const Eigen::VectorXd& disp) {
    std::vector<char> asked(static_cast<size_t>(nv_), 0);
    for (const Sample& s : samples) {
      for (int k = 0; k < 3; ++k) {
        if (s.way && s.vertex[k] >= 0 && s.weight[k] > 0.0) asked[static_cast<size_t>(s.vertex[k])] = 1;
      }
    }
    int hint = -1;
    for (int v = 0; v < nv_; ++v) {
      if (is_fixed(v) || disp(v) == 0.0) continue;
      double m = disp(v);
      if (!asked[static_cast<size_t>(v)]) {
        const double keep = std::min(sd(v), clearance_);
        for (int halvings = 0; halvings < 4; ++halvings) {
          if (signed_distance(V_.row(v).transpose() + m * N_.row(v).transpose(), hint) >= keep) break;
          m = halvings < 3 ? 0.5 * m : 0.0;
        }
      }
      V_.row(v) += m * N_.row(v);
    }
  }

  Eigen::MatrixXd& V_;
  const Eigen::MatrixXi& F_;
  const Eigen::MatrixXd& V_body_;
  const Eigen::MatrixXi& F_body_;
  const std::vector<char>& fixed_;
  const BodyClearanceOptions& o_;
  BodyClearanceResult& result_;
  const int nv_, nb_;
  collision::BodyCollider body_;
  double clearance_ = 0.0, threshold_ = 0.0, mean_edge_ = 0.0;
  std::vector<int> region_;  // per body vertex: the root of the part whose region it is in, -1
  std::vector<std::vector<int>> neighbors_, body_neighbors_;
  Eigen::MatrixXd V_start_, N_;
  collision::CrossingOptions all_hits_;
  // Per body vertex: the place (index into result.places) whose body part it
  // belongs to, once met; the place keeps its side in every later round.
  std::vector<int> body_place_;
  std::vector<char> met_;  // per place: a crossing or a push there (else it is not reported)
  std::vector<double> body_dist_;
  std::vector<int> reached_;
};

}  // namespace

BodyClearanceResult clear_body(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_body,
                               const Eigen::MatrixXi& F_body, const std::vector<char>& fixed,
                               const BodyClearanceOptions& options) {
  const int nv = static_cast<int>(V.rows());
  if (!fixed.empty() && fixed.size() != static_cast<size_t>(nv)) throw UsageError("one fixed flag per garment vertex");
  if (!(options.offset >= 0.0) || !(options.min_clearance > 0.0) || !(options.search > 0.0) ||
      !(options.search_step > 0.0) || !(options.spread > 0.0) || options.membrane_iterations < 0 ||
      !(options.part_radius >= 0.0) || options.max_rounds < 0) {
    throw UsageError("clearance options out of range");
  }
  BodyClearanceResult result;
  result.before = collision::find_crossings(V_body, F_body, V, F);
  Clearance clearance(V, F, V_body, F_body, fixed, options, result);
  clearance.run();
  clearance.finish();
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
