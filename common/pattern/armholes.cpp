#include "pattern/make_pattern.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <optional>
#include <set>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/stopwatch.h"
#include "mesh/graph_paths.h"
#include "mesh/heat_geodesics.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pattern/dart_placement.h"
#include "pattern/piece_mirror.h"
#include "pattern/piece_names.h"
#include "pattern/cutter_helpers.h"

namespace gp {

namespace {

// Length of the level set {d = t} of the piecewise-linear d (#V).
double level_set_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::VectorXd& d, double t) {
  double length = 0.0;
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d points[2];
    int count = 0;
    for (int k = 0; k < 3 && count < 2; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      const bool above_a = d[a] >= t, above_b = d[b] >= t;
      if (above_a == above_b || !std::isfinite(d[a]) || !std::isfinite(d[b])) continue;
      const double s = (t - d[a]) / (d[b] - d[a]);
      points[count++] = (1.0 - s) * V.row(a).transpose() + s * V.row(b).transpose();
    }
    if (count == 2) length += (points[1] - points[0]).norm();
  }
  return length;
}

// The level set {d = t} as closed curves of edge points (each closed curve
// ends with its first point again); open chains (reaching the boundary) are
// dropped.
std::vector<SurfaceCurve> closed_level_sets(const Eigen::MatrixXi& F, const Eigen::VectorXd& d, double t,
                                            double snap_fraction, double edge_fraction) {
  std::map<std::pair<int, int>, std::vector<int>> faces_of;  // crossed edge -> faces
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if ((d[a] >= t) != (d[b] >= t)) faces_of[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  std::map<int, std::vector<std::pair<int, int>>> edges_of;  // face -> its crossed edges
  for (const auto& [e, fs] : faces_of)
    for (int f : fs) edges_of[f].push_back(e);
  std::set<std::pair<int, int>> used;
  std::vector<SurfaceCurve> out;
  for (const auto& [start, fs] : faces_of) {
    if (used.count(start) || fs.size() != 2) continue;
    SurfaceCurve c;
    std::pair<int, int> e = start;
    int face = fs[0];
    bool closed = false;
    for (;;) {
      used.insert(e);
      const double s = std::clamp((t - d[e.first]) / (d[e.second] - d[e.first]), edge_fraction, 1.0 - edge_fraction);
      c.push_back(CurvePoint::on_edge(e.first, e.second, s));
      const auto& es = edges_of[face];
      if (es.size() != 2) break;
      const std::pair<int, int> next = es[0] == e ? es[1] : es[0];
      if (next == start) {
        closed = true;
        break;
      }
      if (used.count(next)) break;
      const auto& nf = faces_of[next];
      if (nf.size() != 2) break;
      face = nf[0] == face ? nf[1] : nf[0];
      e = next;
    }
    if (closed && c.size() >= 3) {
      c.push_back(c.front());
      c = snap_to_vertices(c, snap_fraction);
      if (c.size() >= 4) out.push_back(c);
    }
  }
  return out;
}

// Every limb's opening: where its tube meets the body, and on which side of
// the body's axis it lies.
struct Opening {
  std::string name;
  std::vector<int> loop;
  Eigen::VectorXd d;          // geodesic distance from the loop, per rest vertex
  double found = -1.0;        // distance of its armhole, metres
  Eigen::Vector3d from;       // the loop's centroid
  bool paired = false;        // found is the mean of a mirrored pair's
};

// Mean edge length of the pattern mesh (each face's three edges).
double mean_edge_length(const PatternMesh& mesh) {
  double h = 0.0;
  int edges = 0;
  for (int f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k, ++edges) h += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
  return h / std::max(1, edges);
}

// The distance from the opening at which its cross-section first grows
// faster than armhole_slope, -1 where it never does. The cross-section
// length along the tube: a sleeve keeps about its girth, and where it meets
// the body the level set runs down the body's side and its length grows
// fast. L(t) on a fixed grid of `step`; its slope by least squares over a
// window, so that the chord noise of single level sets does not decide; the
// crossing of the threshold interpolated between grid points, so that it
// moves continuously with the shape.
double armhole_distance(const PatternMesh& mesh, const Eigen::VectorXd& d, double step, const PatternOptions& options) {
  double reach = 0.0;
  for (int v = 0; v < d.size(); ++v)
    if (std::isfinite(d[v])) reach = std::max(reach, d[v]);
  std::vector<double> ts, ls;
  for (double t = step; t < reach; t += step) {
    ts.push_back(t);
    ls.push_back(level_set_length(mesh.rest_V, mesh.rest_F, d, t));
  }
  std::vector<double> slope(ts.size(), 0.0);
  for (size_t k = 0; k < ts.size(); ++k) {
    double st = 0.0, sl = 0.0, stt = 0.0, stl = 0.0;
    int count = 0;
    for (size_t j = 0; j < ts.size(); ++j)
      if (std::abs(ts[j] - ts[k]) <= options.armholes.slope_window) {
        st += ts[j], sl += ls[j], stt += ts[j] * ts[j], stl += ts[j] * ls[j];
        ++count;
      }
    const double den = count * stt - st * st;
    slope[k] = den > 0.0 ? (count * stl - st * sl) / den : 0.0;
  }
  for (size_t k = 1; k < ts.size(); ++k)
    if (slope[k] >= options.armholes.armhole_slope && slope[k - 1] < options.armholes.armhole_slope)
      return ts[k - 1] + (options.armholes.armhole_slope - slope[k - 1]) / (slope[k] - slope[k - 1]) * step;
  return -1.0;
}

// The boundary loops that end a limb's tube, with their armhole distances.
// The distance and its cross-sections are taken on the rest shape, whose
// triangles do not depend on where earlier cuts ran.
std::vector<Opening> limb_openings(const PatternMesh& mesh, const Eigen::Vector3d& axis, double h,
                                   const PatternOptions& options, const PatternContext& context) {
  std::vector<Opening> openings;
  for (const auto& loop : boundary_loops(mesh.rest_F)) {
    Opening o;
    o.loop = loop;
    o.name = "through rest vertex " + std::to_string(loop.front());
    for (int v : loop)
      if (context.boundary_names.count(v)) {
        o.name = "'" + context.boundary_names.at(v) + "'";
        break;
      }
    // A limb's opening lies away from the body's vertical axis (+y through
    // the garment's centroid): a sleeve's hem does, the torso's hem and the
    // neckline do not (the torso is a tube too, and its base would be a yoke).
    o.from = Eigen::Vector3d::Zero();
    for (int v : loop) o.from += mesh.rest_V.row(v).transpose();
    o.from /= static_cast<double>(loop.size());
    if (Eigen::Vector2d(o.from.x() - axis.x(), o.from.z() - axis.z()).norm() < options.armholes.limb_offset) continue;
    o.d = heat_geodesic_distance(mesh.rest_V, mesh.rest_F, loop);
    o.found = armhole_distance(mesh, o.d, 0.5 * h, options);
    // No tube (a neckline or an armhole opening) grows at once.
    if (o.found < options.armholes.min_sleeve_length) continue;
    openings.push_back(std::move(o));
  }
  return openings;
}

// A tailor cuts both sleeves of a pair alike: two openings on either side
// of the axis, at about the same height and distance from it, take the
// mean of their two distances. Each alone would move with the few
// millimetres by which a scanned body or its remeshed garment is not
// symmetric, and the two sleeves would differ by that times their girth.
void pair_mirrored_openings(std::vector<Opening>& openings, const Eigen::Vector3d& axis, const PatternOptions& options) {
  if (openings.size() != 2) return;
  Opening& a = openings[0];
  Opening& b = openings[1];
  const double ra = Eigen::Vector2d(a.from.x() - axis.x(), a.from.z() - axis.z()).norm();
  const double rb = Eigen::Vector2d(b.from.x() - axis.x(), b.from.z() - axis.z()).norm();
  const bool mirrored = (a.from.x() - axis.x()) * (b.from.x() - axis.x()) < 0.0 &&
                        std::abs(ra - rb) <= options.armholes.mirror_tolerance * std::max(ra, rb) &&
                        std::abs(a.from.y() - b.from.y()) <= options.armholes.mirror_tolerance * std::max(ra, rb) &&
                        std::abs(a.found - b.found) <= options.armholes.mirror_tolerance * std::max(a.found, b.found);
  if (mirrored) {
    a.found = b.found = 0.5 * (a.found + b.found);
    a.paired = b.paired = true;
  }
}

// The armhole seams at the openings' distances, cut on the pattern mesh from
// the same piecewise-linear distance; each limb found is recorded in
// `pattern` (limbs, limb_of_rest_face).
void armhole_seams(Pattern& pattern, const std::vector<Opening>& openings, const Eigen::Vector3d& axis,
                   const PatternOptions& options, std::vector<PatternSeam>& seams, std::vector<SurfaceCurve>& curves) {
  const PatternMesh& mesh = pattern.mesh;
  for (const Opening& o : openings) {
    Eigen::VectorXd dm(mesh.V.rows());
    for (int v = 0; v < mesh.V.rows(); ++v) {
      const SurfacePoint& q = mesh.rest_point[static_cast<size_t>(v)];
      dm[v] = q.face < 0 ? 0.0
                         : q.bary[0] * o.d[mesh.rest_F(q.face, 0)] + q.bary[1] * o.d[mesh.rest_F(q.face, 1)] +
                               q.bary[2] * o.d[mesh.rest_F(q.face, 2)];
    }
    auto sets = closed_level_sets(mesh.F, dm, o.found, options.seams.smoothing.trace.snap_fraction,
                                  options.seams.smoothing.trace.min_edge_fraction);
    if (sets.size() != 1) continue;
    // The limb: the rest faces on the loop's side of the level set.
    if (pattern.limb_of_rest_face.empty()) pattern.limb_of_rest_face.assign(static_cast<size_t>(mesh.rest_F.rows()), -1);
    for (int f = 0; f < mesh.rest_F.rows(); ++f)
      if (pattern.limb_of_rest_face[static_cast<size_t>(f)] < 0 &&
          (o.d[mesh.rest_F(f, 0)] + o.d[mesh.rest_F(f, 1)] + o.d[mesh.rest_F(f, 2)]) / 3.0 < o.found)
        pattern.limb_of_rest_face[static_cast<size_t>(f)] = static_cast<int>(pattern.limbs.size());
    pattern.limbs.push_back({o.name, o.from.x() > axis.x()});
    PatternSeam seam{"armhole" + std::to_string(seams.size() + 1), "armhole", "", {}, true, true, {}};
    seam.reason = "the tube ending at the boundary " + o.name + " (a sleeve) meets the body " + metres(o.found) +
                  " from it, where its cross-section starts to grow fast" +
                  (o.paired ? " (the mean of it and its mirror image, so that both sleeves are cut alike)" : "") +
                  ": a seam around it there (" + metres(curve_length(mesh.V, mesh.F, sets.front())) + ")";
    seams.push_back(seam);
    curves.push_back(sets.front());
  }
}

// Two armholes that cross (on a rest shape grown into flaps, the level sets
// of two sleeves can meet) or one that crosses itself: keep those that go in
// together, in order, and leave the others to the later cuts.
void insert_armholes_that_fit(Pattern& pattern, const std::vector<PatternSeam>& seams,
                              const std::vector<SurfaceCurve>& curves) {
  std::vector<size_t> kept;
  for (size_t i = 0; i < seams.size(); ++i) {
    std::vector<PatternSeam> s;
    std::vector<SurfaceCurve> c;
    for (size_t k : kept) s.push_back(seams[k]), c.push_back(curves[k]);
    s.push_back(seams[i]);
    c.push_back(curves[i]);
    Pattern trial = pattern;
    try {
      insert_cuts(trial, s, c);
      kept.push_back(i);
    } catch (const GeometryError& e) {
      pattern.notes.push_back("no armhole at the boundary " + pattern.limbs[i].loop + ": its seam would cross " +
                              (kept.empty() ? "itself" : "another armhole") + " (" + e.what() + ")");
    }
  }
  std::vector<int> new_index(seams.size(), -1);
  std::vector<Limb> limbs;
  std::vector<PatternSeam> s;
  std::vector<SurfaceCurve> c;
  for (size_t k : kept) {
    new_index[k] = static_cast<int>(limbs.size());
    limbs.push_back(pattern.limbs[k]);
    s.push_back(seams[k]);
    c.push_back(curves[k]);
  }
  for (int& l : pattern.limb_of_rest_face)
    if (l >= 0) l = new_index[static_cast<size_t>(l)];
  pattern.limbs = limbs;
  if (limbs.empty()) pattern.limb_of_rest_face.clear();
  if (!s.empty()) insert_cuts(pattern, s, c);
}

}  // namespace

void cut_armholes(Pattern& pattern, const PatternOptions& options, const PatternContext& context) {
  const PatternMesh& mesh = pattern.mesh;
  const double h = mean_edge_length(mesh);
  // The body's vertical axis: through the area centroid of the garment.
  const Eigen::Vector3d axis = area_centroid(mesh.rest_V, mesh.rest_F);
  std::vector<Opening> openings = limb_openings(mesh, axis, h, options, context);
  pair_mirrored_openings(openings, axis, options);
  std::vector<PatternSeam> seams;
  std::vector<SurfaceCurve> curves;
  armhole_seams(pattern, openings, axis, options, seams, curves);
  if (seams.empty()) return;
  try {
    Pattern trial = pattern;
    insert_cuts(trial, seams, curves);
    pattern = std::move(trial);
    return;
  } catch (const GeometryError&) {
    // Some do not go in together: insert_armholes_that_fit.
  }
  insert_armholes_that_fit(pattern, seams, curves);
}

void merge_armhole_slivers(Pattern& pattern, const PatternOptions& options) {
  std::set<std::vector<int>> tried;
  for (int guard = 0; guard < 1000; ++guard) {
    // The smallest sliver not tried yet.
    size_t sliver = pattern.pieces.size();
    double smallest = options.armholes.sliver_area;
    for (size_t c = 0; c < pattern.pieces.size(); ++c) {
      const double a = face_areas(pattern.pieces[c].V, pattern.pieces[c].F).sum();
      if (a < smallest && !tried.count(pattern.pieces[c].face_ids)) smallest = a, sliver = c;
    }
    if (sliver >= pattern.pieces.size()) return;
    tried.insert(pattern.pieces[sliver].face_ids);
    // The armhole and neighbour it shares the most length with.
    std::map<std::pair<int, int>, double> shared;  // (seam, neighbour) -> length
    for (const CutEdge& e : pattern.cut.edges) {
      if (pattern.seams[static_cast<size_t>(e.seam)].kind != "armhole") continue;
      const int l = pattern.piece_of_face[static_cast<size_t>(e.left_face)];
      const int r = pattern.piece_of_face[static_cast<size_t>(e.right_face)];
      if ((l == static_cast<int>(sliver)) == (r == static_cast<int>(sliver))) continue;
      shared[{e.seam, l == static_cast<int>(sliver) ? r : l}] += e.length;
    }
    if (shared.empty()) continue;
    auto best = shared.begin();
    for (auto it = shared.begin(); it != shared.end(); ++it)
      if (it->second > best->second) best = it;
    const auto [seam, neighbour] = best->first;
    std::set<std::pair<int, int>> removed;
    for (const CutEdge& e : pattern.cut.edges) {
      if (e.seam != seam) continue;
      const int l = pattern.piece_of_face[static_cast<size_t>(e.left_face)];
      const int r = pattern.piece_of_face[static_cast<size_t>(e.right_face)];
      if ((l == static_cast<int>(sliver) && r == neighbour) || (r == static_cast<int>(sliver) && l == neighbour))
        removed.insert({std::min(e.a, e.b), std::max(e.a, e.b)});
    }
    // The seam's path without those edges: its runs of kept edges.
    const PatternSeam& old = pattern.seams[static_cast<size_t>(seam)];
    std::vector<int> path = old.vertex_ids;
    if (old.closed && !path.empty()) path.push_back(path.front());
    auto gone = [&](size_t i) { return removed.count({std::min(path[i], path[i + 1]), std::max(path[i], path[i + 1])}) > 0; };
    size_t start = 0;
    if (old.closed) {
      // Start after a removed edge, so that no run wraps around.
      while (start + 1 < path.size() && !gone(start)) ++start;
      if (start + 1 >= path.size()) continue;
      std::vector<int> rotated(path.begin() + static_cast<long>(start) + 1, path.end());
      rotated.insert(rotated.end(), path.begin() + 1, path.begin() + static_cast<long>(start) + 2);
      path = rotated;
    }
    std::vector<std::vector<int>> runs;
    std::vector<int> run{path.front()};
    for (size_t i = 0; i + 1 < path.size(); ++i) {
      if (gone(i)) {
        if (run.size() > 1) runs.push_back(run);
        run = {path[i + 1]};
      } else {
        run.push_back(path[i + 1]);
      }
    }
    if (run.size() > 1) runs.push_back(run);
    Pattern trial = pattern;
    PatternSeam base = old;
    base.closed = false;
    trial.seams.erase(trial.seams.begin() + seam);
    for (size_t k = 0; k < runs.size(); ++k) {
      PatternSeam part = base;
      part.vertex_ids = runs[k];
      if (k > 0) part.name = old.name + "_" + std::to_string(k + 1);
      trial.seams.insert(trial.seams.begin() + seam + static_cast<long>(k), part);
    }
    assemble_pieces(trial);
    if (trial.pieces.size() >= pattern.pieces.size() ||
        !std::all_of(trial.pieces.begin(), trial.pieces.end(), [](const PatternPiece& p) { return is_disk(p); }))
      continue;
    char buf[200];
    std::snprintf(buf, sizeof(buf), ": a sliver of %.2f cm^2 between it and a user seam joins the piece across it (%.1f mm of %s not cut)",
                  1e4 * smallest, 1e3 * best->second, old.name.c_str());
    trial.notes.push_back(old.name + buf);
    pattern = std::move(trial);
    tried.clear();
  }
}

}  // namespace gp
