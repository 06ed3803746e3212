#include "pattern/auto_cut.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <queue>
#include <set>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/math.h"
#include "mesh/topology.h"

namespace gp {
namespace {

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f %%", 100.0 * x);
  return buf;
}

// Multi-source Dijkstra over the piece's edges (3D lengths); ties broken by
// vertex id through the (distance, id) order of the queue.
void dijkstra(const Eigen::MatrixXd& V, const std::vector<std::vector<int>>& neighbors,
              const std::vector<int>& sources, std::vector<double>& dist, std::vector<int>& parent,
              const std::function<bool(int)>& stop = {}, const std::vector<char>* no_pass = nullptr) {
  const size_t n = neighbors.size();
  dist.assign(n, std::numeric_limits<double>::infinity());
  parent.assign(n, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int s : sources) {
    dist[static_cast<size_t>(s)] = 0.0;
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[static_cast<size_t>(v)]) continue;
    if (stop && stop(v)) return;
    // Paths may end on, but not run through, vertices marked no_pass.
    if (no_pass && d > 0.0 && (*no_pass)[static_cast<size_t>(v)]) continue;
    for (int w : neighbors[static_cast<size_t>(v)]) {
      const double nd = d + (V.row(v) - V.row(w)).norm();
      if (nd < dist[static_cast<size_t>(w)]) {
        dist[static_cast<size_t>(w)] = nd;
        parent[static_cast<size_t>(w)] = v;
        queue.push({nd, w});
      }
    }
  }
}

std::vector<int> trace(const std::vector<int>& parent, int to) {
  std::vector<int> path;
  for (int v = to; v != -1; v = parent[static_cast<size_t>(v)]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

struct PieceTopology {
  std::vector<std::vector<int>> loops;
  int euler = 0;
};

std::vector<CutPath> cut_paths(const std::vector<PatternSeam>& seams) {
  std::vector<CutPath> paths;
  for (size_t i = 0; i < seams.size(); ++i)
    paths.push_back({static_cast<int>(i), seams[i].vertex_ids, seams[i].closed});
  return paths;
}

double path_length(const Eigen::MatrixXd& V, const std::vector<int>& path) {
  double s = 0.0;
  for (size_t k = 0; k + 1 < path.size(); ++k) s += (V.row(path[k]) - V.row(path[k + 1])).norm();
  return s;
}

// Angle defect 2 pi - sum of the corner angles at every vertex (intrinsic:
// from edge lengths only); 0 on the boundary.
std::vector<double> angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<double> defect(static_cast<size_t>(V.rows()), 2.0 * M_PI);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = V.row(F(f, (k + 1) % 3)) - V.row(F(f, k));
      const Eigen::Vector3d b = V.row(F(f, (k + 2) % 3)) - V.row(F(f, k));
      const double angle = gp::math::atan2(a.cross(b).norm(), a.dot(b));
      defect[static_cast<size_t>(F(f, k))] -= angle;
    }
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) defect[static_cast<size_t>(v)] = 0.0;
  return defect;
}

// Cuts the rest shape along the pattern's seams and extracts the pieces
// (faces, vertices, local ids); boundaries and flattenings are left empty.
void assemble_pieces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Pattern& pattern) {
  pattern.cut = cut_mesh(V, F, cut_paths(pattern.seams));
  const CutMesh& cut = pattern.cut;
  Eigen::VectorXi component;
  const int count = face_components(cut.F, component);
  pattern.pieces.assign(static_cast<size_t>(count), PatternPiece{});
  pattern.piece_of_face.assign(static_cast<size_t>(F.rows()), -1);
  pattern.local_vertex.assign(static_cast<size_t>(cut.V.rows()), -1);
  for (int f = 0; f < F.rows(); ++f) {
    const int c = component[f];
    pattern.piece_of_face[static_cast<size_t>(f)] = c;
    pattern.pieces[static_cast<size_t>(c)].face_ids.push_back(f);
  }
  for (int c = 0; c < count; ++c) {
    PatternPiece& p = pattern.pieces[static_cast<size_t>(c)];
    p.name = "P" + std::to_string(c + 1);
    std::vector<int> cut_ids;
    for (int f : p.face_ids)
      for (int k = 0; k < 3; ++k) {
        const int v = cut.F(f, k);
        if (pattern.local_vertex[static_cast<size_t>(v)] < 0) {
          pattern.local_vertex[static_cast<size_t>(v)] = static_cast<int>(cut_ids.size());
          cut_ids.push_back(v);
        }
      }
    // Local ids in ascending cut-vertex order, for a stable numbering.
    std::vector<int> sorted = cut_ids;
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size(); ++i) pattern.local_vertex[static_cast<size_t>(sorted[i])] = static_cast<int>(i);
    const int nv = static_cast<int>(sorted.size());
    p.V.resize(nv, 3);
    p.cut_vertex_ids.resize(nv);
    p.rest_vertex_ids.resize(nv);
    for (int i = 0; i < nv; ++i) {
      p.cut_vertex_ids[i] = sorted[static_cast<size_t>(i)];
      p.rest_vertex_ids[i] = cut.origin[sorted[static_cast<size_t>(i)]];
      p.V.row(i) = cut.V.row(sorted[static_cast<size_t>(i)]);
    }
    p.F.resize(static_cast<int>(p.face_ids.size()), 3);
    for (size_t i = 0; i < p.face_ids.size(); ++i)
      for (int k = 0; k < 3; ++k)
        p.F(static_cast<int>(i), k) = pattern.local_vertex[static_cast<size_t>(cut.F(p.face_ids[i], k))];
  }
}

// Cache key of piece c: its faces and the cut edges inside it (slits).
std::vector<int> piece_key(const Pattern& pattern, size_t c) {
  std::vector<int> key = pattern.pieces[c].face_ids;
  key.push_back(-1);
  for (const CutEdge& e : pattern.cut.edges)
    if (pattern.piece_of_face[static_cast<size_t>(e.left_face)] == static_cast<int>(c) &&
        pattern.piece_of_face[static_cast<size_t>(e.right_face)] == static_cast<int>(c)) {
      key.push_back(std::min(e.a, e.b));
      key.push_back(std::max(e.a, e.b));
    }
  return key;
}

// Whether the two flat sides of every seam have the same length within the
// tolerance; fills the pieces on seams that do not.
bool seam_sides_match(const Pattern& pattern, const PatternOptions& options, std::set<int>* mismatched) {
  std::vector<double> left(pattern.seams.size(), 0.0), right(pattern.seams.size(), 0.0),
      length(pattern.seams.size(), 0.0);
  for (const CutEdge& e : pattern.cut.edges) {
    length[static_cast<size_t>(e.seam)] += e.length;
    for (int side = 0; side < 2; ++side) {
      const auto& q = pattern.pieces[static_cast<size_t>(pattern.piece_of_face[static_cast<size_t>(side == 0 ? e.left_face : e.right_face)])];
      const int a = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_a : e.right_a)];
      const int b = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_b : e.right_b)];
      (side == 0 ? left : right)[static_cast<size_t>(e.seam)] += (q.flat.UV.row(a) - q.flat.UV.row(b)).norm();
    }
  }
  bool ok = true;
  for (const CutEdge& e : pattern.cut.edges) {
    const size_t i = static_cast<size_t>(e.seam);
    if (std::abs(left[i] - right[i]) <= std::max(options.seam_tolerance, options.seam_tolerance_relative * length[i]))
      continue;
    ok = false;
    if (!mismatched) return false;
    mismatched->insert(pattern.piece_of_face[static_cast<size_t>(e.left_face)]);
    mismatched->insert(pattern.piece_of_face[static_cast<size_t>(e.right_face)]);
  }
  return ok;
}

}  // namespace

bool meets_limit(const FlattenResult& flat, const PatternOptions& options) {
  return flat.stats.flipped_triangles == 0 && !flat.boundary_overlaps &&
         flat.stats.p95_error <= options.p95_limit && flat.stats.max_error <= options.max_limit;
}

Pattern make_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& user_seams,
                     const PatternOptions& options, const std::map<int, std::string>& boundary_names) {
  Pattern pattern;
  for (const auto& s : user_seams) pattern.seams.push_back({s.name, "user", "", s.vertex_ids, s.closed});
  // Flattenings of pieces that a round left unchanged are reused; the key is
  // the piece's faces and the cut edges inside it.
  std::map<std::vector<int>, FlattenResult> cache;
  std::map<std::vector<int>, double> boundary_weight;  // raised where seam sides differ
  std::set<std::vector<int>> stuck;  // pieces where no further cut can be placed
  int added_distortion_cuts = 0, topology_cuts = 0;
  const std::vector<double> defect = angle_defects(V, F);

  auto loop_name = [&](const PatternPiece& piece, const std::vector<int>& loop) {
    for (int v : loop) {
      const auto it = boundary_names.find(piece.rest_vertex_ids[v]);
      if (it != boundary_names.end()) return "'" + it->second + "'";
    }
    return std::string("through rest vertex ") + std::to_string(piece.rest_vertex_ids[loop.front()]);
  };

  for (;;) {
    assemble_pieces(V, F, pattern);

    // Topology first: every piece must be a disk before it can be flattened.
    bool added_topology = false;
    for (PatternPiece& p : pattern.pieces) {
      const auto loops = boundary_loops(p.F);
      const int euler = euler_characteristic(p.F);
      if (loops.size() == 1 && euler == 1) {
        p.boundary = loops.front();
        continue;
      }
      const int genus2 = 2 - euler - static_cast<int>(loops.size());
      if (genus2 != 0)
        throw GeometryError("piece " + p.name + " has genus " + std::to_string(genus2 / 2) +
                            " (a handle); add seams that cut through its handles");
      const auto neighbors = vertex_neighbors(p.F, static_cast<int>(p.V.rows()));
      std::vector<double> dist;
      std::vector<int> parent;
      std::vector<int> path;
      std::string reason;
      if (loops.empty()) {
        dijkstra(p.V, neighbors, {0}, dist, parent);
        int far = 0;
        for (int v = 0; v < static_cast<int>(dist.size()); ++v)
          if (dist[static_cast<size_t>(v)] > dist[static_cast<size_t>(far)]) far = v;
        dijkstra(p.V, neighbors, {far}, dist, parent);
        int other = far;
        for (int v = 0; v < static_cast<int>(dist.size()); ++v)
          if (dist[static_cast<size_t>(v)] > dist[static_cast<size_t>(other)]) other = v;
        path = trace(parent, other);
        reason = "piece " + p.name + " is closed: opened along a shortest path between its two farthest points";
      } else {
        std::vector<int> loop_of(static_cast<size_t>(p.V.rows()), -1);
        for (size_t l = 0; l < loops.size(); ++l)
          for (int v : loops[l]) loop_of[static_cast<size_t>(v)] = static_cast<int>(l);
        int reached = -1;
        dijkstra(p.V, neighbors, loops.front(), dist, parent, [&](int v) {
          if (loop_of[static_cast<size_t>(v)] > 0) {
            reached = v;
            return true;
          }
          return false;
        });
        if (reached < 0) throw GeometryError("piece " + p.name + " has boundary loops that no path joins");
        path = trace(parent, reached);
        reason = "piece " + p.name + " has " + std::to_string(loops.size()) +
                 " boundary loops and must be a disk to be flattened: joins the boundary " +
                 loop_name(p, loops.front()) + " to the boundary " +
                 loop_name(p, loops[static_cast<size_t>(loop_of[static_cast<size_t>(reached)])]) +
                 " along a shortest path";
      }
      PatternSeam seam;
      seam.name = "join" + std::to_string(++topology_cuts);
      seam.kind = "topology";
      seam.reason = reason;
      for (int v : path) seam.vertex_ids.push_back(p.rest_vertex_ids[v]);
      pattern.seams.push_back(seam);
      added_topology = true;
    }
    if (added_topology) continue;

    // Flatten every piece (or reuse an unchanged one).
    ++pattern.rounds;
    std::vector<std::vector<int>> keys(pattern.pieces.size());
    for (size_t c = 0; c < pattern.pieces.size(); ++c) {
      PatternPiece& p = pattern.pieces[c];
      std::vector<int>& key = keys[c];
      key = piece_key(pattern, c);
      auto it = cache.find(key);
      if (it == cache.end()) {
        FlattenOptions flatten = options.flatten;
        flatten.injective_fallback = false;
        const auto w = boundary_weight.find(key);
        if (w != boundary_weight.end()) flatten.boundary_weight = w->second;
        it = cache.emplace(key, flatten_piece(p.V, p.F, flatten, &p.rest_vertex_ids)).first;
        ++pattern.flattenings;
      }
      p.flat = it->second;
      p.meets_limit = meets_limit(p.flat, options);
    }

    // Seams whose two flat sides differ by more than the tolerance: the
    // pieces on them are flattened again with 4 times the boundary-length
    // weight (up to max_boundary_weight) before any further cut.
    std::set<int> mismatched;
    pattern.seams_within_tolerance = seam_sides_match(pattern, options, &mismatched);
    bool reflatten = false;
    for (int c : mismatched) {
      const auto& key = keys[static_cast<size_t>(c)];
      auto w = boundary_weight.emplace(key, options.flatten.boundary_weight).first;
      if (w->second <= 0.0 || w->second * 4.0 > options.max_boundary_weight) continue;
      w->second *= 4.0;
      cache.erase(key);
      reflatten = true;
    }
    if (reflatten) continue;
    pattern.meets_limit = std::all_of(pattern.pieces.begin(), pattern.pieces.end(),
                                      [](const PatternPiece& p) { return p.meets_limit; });
    if (pattern.meets_limit || added_distortion_cuts >= options.max_added_cuts) break;

    std::set<int> seam_vertex;
    for (const auto& seam : pattern.seams)
      if (!seam.vertex_ids.empty()) {
        seam_vertex.insert(seam.vertex_ids.front());
        seam_vertex.insert(seam.vertex_ids.back());
      }
    bool added = false;
    for (size_t c = 0; c < pattern.pieces.size() && added_distortion_cuts < options.max_added_cuts; ++c) {
      const PatternPiece& p = pattern.pieces[c];
      if (p.meets_limit || stuck.count(keys[c])) continue;
      const int nv = static_cast<int>(p.V.rows());
      std::vector<char> on_boundary(static_cast<size_t>(nv), 0);
      for (int v : p.boundary) on_boundary[static_cast<size_t>(v)] = 1;
      // Vertex error: area-weighted mean of its triangles' errors.
      const Eigen::MatrixXd S = principal_stretches(p.V, p.F, p.flat.UV);
      std::vector<double> num(static_cast<size_t>(nv), 0.0), den(static_cast<size_t>(nv), 0.0);
      std::vector<double> stretch(static_cast<size_t>(nv), 0.0), squeeze(static_cast<size_t>(nv), 0.0);
      for (int f = 0; f < p.F.rows(); ++f) {
        const Eigen::Vector3d e1 = p.V.row(p.F(f, 1)) - p.V.row(p.F(f, 0));
        const Eigen::Vector3d e2 = p.V.row(p.F(f, 2)) - p.V.row(p.F(f, 0));
        const double a = 0.5 * e1.cross(e2).norm();
        const double err = std::max(std::abs(S(f, 0) - 1.0), std::abs(S(f, 1) - 1.0));
        for (int k = 0; k < 3; ++k) {
          num[static_cast<size_t>(p.F(f, k))] += a * err;
          stretch[static_cast<size_t>(p.F(f, k))] += a * std::max(0.0, S(f, 0) - 1.0);
          squeeze[static_cast<size_t>(p.F(f, k))] += a * std::max(0.0, 1.0 - S(f, 1));
          den[static_cast<size_t>(p.F(f, k))] += a;
        }
      }
      std::string kind = "distortion";
      int worst = 0;
      double worst_err = -1.0;
      // An overlap is a cut reason of its own only when the distortion is
      // within the limit; a strongly distorted piece overlaps as a symptom.
      const bool distorted = p.flat.stats.p95_error > options.p95_limit || p.flat.stats.max_error > options.max_limit ||
                             p.flat.stats.flipped_triangles > 0;
      // A new cut does not start at an end of an existing one (two cuts from
      // one vertex leave a sliver of cloth between them that turns freely and
      // overlaps) unless no other vertex is left.
      std::vector<char> on_seam(static_cast<size_t>(nv), 0);
      for (int v = 0; v < nv; ++v) on_seam[static_cast<size_t>(v)] = seam_vertex.count(p.rest_vertex_ids[v]) ? 1 : 0;
      auto vertex_error = [&](int v) {
        return den[static_cast<size_t>(v)] > 0.0 ? num[static_cast<size_t>(v)] / den[static_cast<size_t>(v)] : 0.0;
      };
      for (int pass = 0; pass < 2 && worst_err < 0.0; ++pass)
        for (int v = 0; v < nv; ++v) {
          if (pass == 0 && on_seam[static_cast<size_t>(v)]) continue;
          if (vertex_error(v) > worst_err) worst_err = vertex_error(v), worst = v;
        }
      // Candidates in order: where the outline overlaps (first the ones not at
      // a seam end), when that is the reason; then the vertex of largest
      // error. In a comb-like piece (slits cut side by side) every split from
      // an overlap may run along existing cuts and cut nothing new; the
      // distortion rule at the worst vertex still relieves it. Measured on the
      // adapted shared-body shirt: without it the last failing piece of 63
      // was left overlapping.
      // A third fallback, where the distortion rule darts (a stretched
      // boundary vertex), is a split from the same vertex: in a small piece
      // the dart may find no tip deeper inside (the adapted shared-body dress
      // kept a 20-vertex piece at max 9.8 % so).
      enum class Rule { overlap, distortion, split };
      std::vector<std::pair<int, Rule>> candidates;
      if (!distorted && p.flat.boundary_overlaps && !p.flat.overlap_vertex_ids.empty()) {
        std::vector<int> overlaps = p.flat.overlap_vertex_ids;
        std::stable_partition(overlaps.begin(), overlaps.end(),
                              [&](int v) { return !on_seam[static_cast<size_t>(v)]; });
        for (int v : overlaps) candidates.push_back({v, Rule::overlap});
      }
      candidates.push_back({worst, Rule::distortion});
      if (on_boundary[static_cast<size_t>(worst)] &&
          !(squeeze[static_cast<size_t>(worst)] > stretch[static_cast<size_t>(worst)]))
        candidates.push_back({worst, Rule::split});
      const auto neighbors = vertex_neighbors(p.F, nv);
      // Cone points first (Gu, Gortler and Hoppe 2002, sec. 3.2; Ben-Chen,
      // Gotsman and Bunin 2008): an inner vertex with angle defect K forces a
      // stretch of about |K| / (2 pi) on its neighbourhood whatever the
      // flattening, and a cut through it lets the angle open (K > 0) or the
      // excess spread to both sides (K < 0). In order of |K|, each cone is
      // joined by a shortest path to the boundary or to a path cut for a
      // cone before it (a tree of slits: the piece stays a disk).
      if (distorted && options.cone_angle > 0.0) {
        std::vector<int> cones;
        for (int v = 0; v < nv; ++v)
          if (!on_boundary[static_cast<size_t>(v)] &&
              std::abs(defect[static_cast<size_t>(p.rest_vertex_ids[v])]) >= options.cone_angle)
            cones.push_back(v);
        auto abs_defect = [&](int v) { return std::abs(defect[static_cast<size_t>(p.rest_vertex_ids[v])]); };
        std::sort(cones.begin(), cones.end(), [&](int a, int b) {
          return abs_defect(a) > abs_defect(b) || (abs_defect(a) == abs_defect(b) && a < b);
        });
        std::vector<char> reached_by_cut = on_boundary;
        int cone_cuts = 0;
        for (int cone : cones) {
          if (reached_by_cut[static_cast<size_t>(cone)] || added_distortion_cuts >= options.max_added_cuts) continue;
          std::vector<double> cone_dist;
          std::vector<int> cone_parent;
          int reached = -1;
          dijkstra(p.V, neighbors, {cone}, cone_dist, cone_parent, [&](int v) {
            if (!reached_by_cut[static_cast<size_t>(v)]) return false;
            reached = v;
            return true;
          });
          if (reached < 0) continue;
          std::vector<int> cone_path = trace(cone_parent, reached);
          std::reverse(cone_path.begin(), cone_path.end());
          for (int v : cone_path) reached_by_cut[static_cast<size_t>(v)] = 1;
          PatternSeam seam;
          seam.name = "cut" + std::to_string(added_distortion_cuts + 1);
          seam.kind = "cone";
          for (int v : cone_path) seam.vertex_ids.push_back(p.rest_vertex_ids[v]);
          char deg[32];
          std::snprintf(deg, sizeof(deg), "%.1f", defect[static_cast<size_t>(p.rest_vertex_ids[cone])] * 180.0 / M_PI);
          seam.reason = "piece " + p.name + ": distortion p95 " + percent(p.flat.stats.p95_error) + ", max " +
                        percent(p.flat.stats.max_error) + " exceeds the limit; inner rest vertex " +
                        std::to_string(p.rest_vertex_ids[cone]) + " is a cone point (angle defect " + deg +
                        " degrees): cut from it to the boundary or an earlier cut along a shortest path (" +
                        std::to_string(path_length(p.V, cone_path)) + " m)";
          pattern.seams.push_back(seam);
          ++added_distortion_cuts;
          ++cone_cuts;
        }
        if (cone_cuts > 0) {
          added = true;
          continue;
        }
      }
      std::vector<double> depth, dist;
      std::vector<int> parent_b, parent;
      std::vector<int> path;
      std::string how;
      // Where the flat boundary is compressed (too much cloth: negative
      // curvature, or an outline that overlaps) a dart cannot help, its sides
      // would have to overlap; the piece is split instead, by the shortest
      // path from the vertex to a boundary vertex that is far from it along
      // the outline (more than three times the path's length), so that the
      // two parts can turn apart.
      // A path along edges that are already cut or on the boundary changes
      // nothing: the piece cannot be improved by this rule.
      std::set<std::pair<int, int>> boundary_edges;
      for (size_t k = 0; k < p.boundary.size(); ++k) {
        const int a = p.boundary[k], b = p.boundary[(k + 1) % p.boundary.size()];
        boundary_edges.insert({std::min(a, b), std::max(a, b)});
      }
      bool cuts_something = false;
      for (size_t ci = 0; ci < candidates.size() && !cuts_something; ++ci) {
        worst = candidates[ci].first;
        const Rule rule = candidates[ci].second;
        kind = rule == Rule::overlap ? "overlap" : "distortion";
        worst_err = vertex_error(worst);
        path.clear();
        const bool split = rule != Rule::distortion || (on_boundary[static_cast<size_t>(worst)] &&
                                                        squeeze[static_cast<size_t>(worst)] > stretch[static_cast<size_t>(worst)]);
        // Cut paths run through the inside of the piece (a path along its
        // edge would cut off slivers); only where none exists (a piece without
        // inner vertices) may they pass through boundary vertices.
        for (int strict = 1; strict >= 0 && path.size() < 2; --strict) {
          const std::vector<char>* block = strict ? &on_boundary : nullptr;
          if (split && path.size() < 2) {
            std::vector<double> arc(static_cast<size_t>(nv), 0.0);
            double perimeter = 0.0;
            for (size_t k = 0; k < p.boundary.size(); ++k) {
              arc[static_cast<size_t>(p.boundary[k])] = perimeter;
              perimeter += (p.V.row(p.boundary[k]) - p.V.row(p.boundary[(k + 1) % p.boundary.size()])).norm();
            }
            const double s0 = arc[static_cast<size_t>(worst)];
            int reached = -1;
            dijkstra(p.V, neighbors, {worst}, dist, parent, [&](int v) {
              if (v == worst || !on_boundary[static_cast<size_t>(v)]) return false;
              const double along = std::abs(arc[static_cast<size_t>(v)] - s0);
              if (std::min(along, perimeter - along) > 3.0 * dist[static_cast<size_t>(v)]) {
                reached = v;
                return true;
              }
              return false;
            }, block);
            if (reached < 0) {
              // No such vertex (a small piece): the boundary vertex that gains
              // most outline length over the path's length.
              double best = 0.0;
              for (int v : p.boundary) {
                if (v == worst) continue;
                const double along = std::abs(arc[static_cast<size_t>(v)] - s0);
                const double score = std::min(along, perimeter - along) - dist[static_cast<size_t>(v)];
                if (score > best) best = score, reached = v;
              }
            }
            if (reached >= 0) path = trace(parent, reached);
            how = rule == Rule::overlap ? "split the piece along a shortest path from it to its opposite edge"
                  : rule == Rule::split     ? "no dart from it cuts anything: split the piece along a shortest path "
                                              "from it to its opposite edge"
                                            : "the outline is compressed there: split the piece along a shortest path "
                                              "from it to its opposite edge";
          }
          if (path.size() < 2 && !on_boundary[static_cast<size_t>(worst)]) {
            int reached = -1;
            dijkstra(p.V, neighbors, {worst}, dist, parent, [&](int v) {
              if (on_boundary[static_cast<size_t>(v)]) {
                reached = v;
                return true;
              }
              return false;
            });
            if (reached >= 0) path = trace(parent, reached);
            std::reverse(path.begin(), path.end());
            how = "cut from the boundary to it along a shortest path";
          } else if (path.size() < 2) {
            dijkstra(p.V, neighbors, p.boundary, depth, parent_b);
            dijkstra(p.V, neighbors, {worst}, dist, parent, {}, block);
            int tip = worst;
            double best = 0.0;
            for (int v = 0; v < nv; ++v) {
              if (block && on_boundary[static_cast<size_t>(v)]) continue;
              const double score = depth[static_cast<size_t>(v)] - options.tip_weight * dist[static_cast<size_t>(v)];
              if (score > best) best = score, tip = v;
            }
            if (tip != worst) path = trace(parent, tip);
            how = "dart from it into the piece, to the point farthest from the piece's edges";
          }
        }
        cuts_something = false;
        for (size_t k = 0; k + 1 < path.size(); ++k)
          if (!boundary_edges.count({std::min(path[k], path[k + 1]), std::max(path[k], path[k + 1])})) cuts_something = true;
      }
      if (path.size() < 2 || !cuts_something) {
        stuck.insert(keys[c]);
        continue;
      }
      PatternSeam seam;
      seam.name = "cut" + std::to_string(added_distortion_cuts + 1);
      seam.kind = kind;
      for (int v : path) seam.vertex_ids.push_back(p.rest_vertex_ids[v]);
      const std::string where = std::string(on_boundary[static_cast<size_t>(worst)] ? "boundary" : "inner") +
                                " rest vertex " + std::to_string(p.rest_vertex_ids[worst]);
      if (kind == "overlap")
        seam.reason = "piece " + p.name + ": its flat outline overlaps itself at " + where + "; " + how;
      else if (!distorted)
        seam.reason = "piece " + p.name + ": its flat outline overlaps itself and no split from there cuts anything "
                      "new; largest distortion at " + where + " (" + percent(worst_err) + "): " + how + " (" +
                      std::to_string(path_length(p.V, path)) + " m)";
      else
        seam.reason = "piece " + p.name + ": distortion p95 " + percent(p.flat.stats.p95_error) + ", max " +
                      percent(p.flat.stats.max_error) + " exceeds the limit (" + percent(options.p95_limit) +
                      ", " + percent(options.max_limit) + "); worst at " + where + " (" + percent(worst_err) +
                      "): " + how + " (" + std::to_string(path_length(p.V, path)) + " m)";
      pattern.seams.push_back(seam);
      ++added_distortion_cuts;
      added = true;
    }
    if (!added) break;
  }
  // Scraps: the greedy cuts can leave small pieces (down to single
  // triangles where several cuts meet). Each added cut that borders a piece
  // smaller than merge_area is removed again, smallest piece first, when the
  // pieces it joins form a disk that meets the limit and every seam still
  // matches; the pieces' flattenings are reused where unchanged.
  if (options.merge_area > 0.0) {
    std::set<std::string> tried;
    for (bool merged = true; merged;) {
      merged = false;
      std::vector<std::pair<double, size_t>> candidates;  // (smaller bordering piece area, seam)
      {
        std::vector<double> smallest(pattern.seams.size(), std::numeric_limits<double>::infinity());
        std::vector<char> joins(pattern.seams.size(), 0);
        for (const CutEdge& e : pattern.cut.edges) {
          const int l = pattern.piece_of_face[static_cast<size_t>(e.left_face)];
          const int r = pattern.piece_of_face[static_cast<size_t>(e.right_face)];
          if (l == r) continue;
          joins[static_cast<size_t>(e.seam)] = 1;
          const double a = std::min(pattern.pieces[static_cast<size_t>(l)].flat.stats.area_3d,
                                    pattern.pieces[static_cast<size_t>(r)].flat.stats.area_3d);
          smallest[static_cast<size_t>(e.seam)] = std::min(smallest[static_cast<size_t>(e.seam)], a);
        }
        for (size_t i = 0; i < pattern.seams.size(); ++i)
          if (pattern.seams[i].kind != "user" && joins[i] && smallest[i] < options.merge_area &&
              !tried.count(pattern.seams[i].name))
            candidates.push_back({smallest[i], i});
        std::sort(candidates.begin(), candidates.end());
      }
      std::set<std::vector<int>> failing_keys;
      for (size_t c = 0; c < pattern.pieces.size(); ++c)
        if (!pattern.pieces[c].meets_limit) failing_keys.insert(piece_key(pattern, c));
      for (const auto& [area, i] : candidates) {
        tried.insert(pattern.seams[i].name);
        Pattern trial;
        trial.seams = pattern.seams;
        trial.seams.erase(trial.seams.begin() + static_cast<long>(i));
        assemble_pieces(V, F, trial);
        if (trial.pieces.size() >= pattern.pieces.size()) continue;
        bool ok = true;
        for (size_t c = 0; c < trial.pieces.size() && ok; ++c) {
          PatternPiece& p = trial.pieces[c];
          const auto loops = boundary_loops(p.F);
          if (loops.size() != 1 || euler_characteristic(p.F) != 1) {
            ok = false;
            break;
          }
          p.boundary = loops.front();
          const std::vector<int> key = piece_key(trial, c);
          auto it = cache.find(key);
          if (it == cache.end()) {
            FlattenOptions flatten = options.flatten;
            flatten.injective_fallback = false;
            it = cache.emplace(key, flatten_piece(p.V, p.F, flatten, &p.rest_vertex_ids)).first;
            ++pattern.flattenings;
          }
          p.flat = it->second;
          p.meets_limit = meets_limit(p.flat, options);
          // A piece that failed before may still fail, unchanged; any other
          // piece must meet the limit. Unchanged means the same faces and the
          // same slits: a cut removed to merge two pieces may also run as a
          // slit through a third, which then flattens differently. (Comparing
          // faces only let the adapted shared-body dress lose the limit on a
          // 0.02 m^2 piece, p95 10.4 %, by merging scraps elsewhere.)
          ok = p.meets_limit || failing_keys.count(key);
        }
        if (!ok || (pattern.seams_within_tolerance && !seam_sides_match(trial, options, nullptr))) continue;
        trial.meets_limit = std::all_of(trial.pieces.begin(), trial.pieces.end(),
                                        [](const PatternPiece& p) { return p.meets_limit; });
        trial.seams_within_tolerance = seam_sides_match(trial, options, nullptr);
        trial.rounds = pattern.rounds;
        trial.flattenings = pattern.flattenings;
        trial.merged_cuts = pattern.merged_cuts;
        trial.merged_cuts.push_back(pattern.seams[i].name);
        pattern = std::move(trial);
        merged = true;
        break;
      }
    }
  }
  pattern.cut_cap_reached = added_distortion_cuts >= options.max_added_cuts;
  for (size_t c = 0; c < pattern.pieces.size(); ++c)
    if (!pattern.pieces[c].meets_limit && stuck.count(piece_key(pattern, c)))
      pattern.stuck_pieces.push_back(pattern.pieces[c].name);
  // Pieces left with flipped triangles (the limit was not reached within
  // max_added_cuts) are flattened injectively: the output never has flips.
  for (PatternPiece& p : pattern.pieces)
    if (p.flat.stats.flipped_triangles > 0) {
      p.flat = flatten_piece(p.V, p.F, options.flatten, &p.rest_vertex_ids);
      ++pattern.flattenings;
      p.meets_limit = meets_limit(p.flat, options);
    }
  return pattern;
}

}  // namespace gp
