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

namespace gp {
namespace {

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f %%", 100.0 * x);
  return buf;
}

std::string metres(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3f m", x);
  return buf;
}

// The curve of a piece (local ids) on the pattern mesh.
SurfaceCurve piece_to_mesh(const PatternPiece& p, const SurfaceCurve& c) {
  SurfaceCurve out;
  for (const CurvePoint& q : c) {
    if (q.is_vertex()) out.push_back(CurvePoint::at_vertex(p.mesh_vertex_ids[q.vertex]));
    else if (q.is_edge()) out.push_back(CurvePoint::on_edge(p.mesh_vertex_ids[q.a], p.mesh_vertex_ids[q.b], q.t));
    else out.push_back(CurvePoint::in_face(p.face_ids[static_cast<size_t>(q.face)], q.bary));
  }
  return out;
}

// Cache key of a piece: its triangles as sorted triples of pattern-mesh
// vertex ids (unchanged by insertions elsewhere), then its slits.
std::vector<int> piece_key(const Pattern& pattern, size_t c) {
  const PatternPiece& p = pattern.pieces[c];
  std::vector<std::array<int, 3>> tri;
  for (int f = 0; f < p.F.rows(); ++f) {
    std::array<int, 3> t{p.mesh_vertex_ids[p.F(f, 0)], p.mesh_vertex_ids[p.F(f, 1)], p.mesh_vertex_ids[p.F(f, 2)]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    tri.push_back(t);
  }
  std::sort(tri.begin(), tri.end());
  std::vector<int> key;
  for (const auto& t : tri) key.insert(key.end(), t.begin(), t.end());
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
bool seam_sides_match(const Pattern& pattern, const PatternOptions& options, double margin, std::set<int>* mismatched) {
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
    if (std::abs(left[i] - right[i]) <= margin * std::max(options.seam_tolerance, options.seam_tolerance_relative * length[i]))
      continue;
    ok = false;
    if (!mismatched) return false;
    mismatched->insert(pattern.piece_of_face[static_cast<size_t>(e.left_face)]);
    mismatched->insert(pattern.piece_of_face[static_cast<size_t>(e.right_face)]);
  }
  return ok;
}

std::vector<char> boundary_flags(const PatternPiece& p) {
  std::vector<char> b(static_cast<size_t>(p.V.rows()), 0);
  for (const auto& loop : boundary_loops(p.F))
    for (int v : loop) b[static_cast<size_t>(v)] = 1;
  return b;
}

// The rest faces piece c covers, sorted.
std::vector<int> piece_rest_faces(const Pattern& pattern, size_t c) {
  std::vector<int> out;
  for (int f : pattern.pieces[c].face_ids) out.push_back(pattern.mesh.rest_face[static_cast<size_t>(f)]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

double panel_excess(const std::vector<MaterialFace>& faces, const PatternOptions& options) {
  const double c_lim = options.symmetric ? options.max_limit : options.compression_worst1;
  const double e_lim = options.symmetric ? options.max_limit : options.ease_worst5;
  double excess = 0.0;
  for (const MaterialFace& m : faces) {
    const double c = 1.0 - m.stretch[1], e = m.stretch[0] - 1.0;
    excess += m.area * (std::max(0.0, c - c_lim) / c_lim + std::max(0.0, e - e_lim) / e_lim);
  }
  return excess;
}

bool meets_limit(const PatternPiece& piece, const PatternOptions& options) {
  if (piece.flat.stats.flipped_triangles > 0 || piece.flat.boundary_overlaps) return false;
  const DistortionStats& s = piece.stats;
  if (options.symmetric) return s.p95_error <= options.p95_limit && s.max_error <= options.max_limit;
  return s.worst1_compression <= options.compression_worst1 && s.worst5_ease <= options.ease_worst5;
}

Pattern cut_user_seams(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                       const PatternOptions& options) {
  Pattern pattern;
  pattern.mesh = pattern_mesh_of_rest(V, F);
  // Fixed points of every seam: its clicks, its ends, the vertices it shares
  // with another seam and those on the boundary.
  std::vector<int> uses(static_cast<size_t>(V.rows()), 0);
  for (const auto& s : seams)
    for (int v : s.vertex_ids) ++uses[static_cast<size_t>(v)];
  std::vector<char> on_boundary(static_cast<size_t>(V.rows()), 0);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) on_boundary[static_cast<size_t>(v)] = 1;
  std::vector<PatternSeam> added;
  std::vector<SurfaceCurve> curves;
  for (const auto& s : seams) {
    // Clicked points are kept within the smoothing's tolerance (their rest
    // vertex stands for the click only up to the mesh's resolution); the
    // ends, shared and boundary vertices are fixed.
    std::vector<int> fixed;
    for (int v : s.vertex_ids)
      if (uses[static_cast<size_t>(v)] > 1 || on_boundary[static_cast<size_t>(v)]) fixed.push_back(v);
    PatternSeam seam{s.name, "user", "", {}, s.closed, false, {}};
    SurfaceCurve c;
    if (options.smooth) {
      c = smooth_edge_path(V, F, s.vertex_ids, fixed, s.closed, options.smoothing, &seam.smoothed, s.click_ids);
    } else {
      for (int v : s.vertex_ids) c.push_back(CurvePoint::at_vertex(v));
      if (s.closed) c.push_back(CurvePoint::at_vertex(s.vertex_ids.front()));
    }
    added.push_back(seam);
    curves.push_back(c);
  }
  try {
    insert_cuts(pattern, added, curves);
  } catch (const GeometryError& e) {
    // Smoothed seams that cross each other: cut along the edge paths instead.
    if (!options.smooth) throw;
    pattern = Pattern{};
    pattern.mesh = pattern_mesh_of_rest(V, F);
    for (size_t i = 0; i < seams.size(); ++i) {
      added[i].smoothed = false;
      curves[i].clear();
      for (int v : seams[i].vertex_ids) curves[i].push_back(CurvePoint::at_vertex(v));
      if (seams[i].closed) curves[i].push_back(CurvePoint::at_vertex(seams[i].vertex_ids.front()));
    }
    insert_cuts(pattern, added, curves);
    pattern.notes.push_back(std::string("the smoothed user seams could not be cut together (") + e.what() +
                            "): they are cut along the rest shape's edges");
  }
  return pattern;
}

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

}  // namespace

void cut_armholes(Pattern& pattern, const PatternOptions& options, const PatternContext& context) {
  const PatternMesh& mesh = pattern.mesh;
  std::vector<PatternSeam> seams;
  std::vector<SurfaceCurve> curves;
  double h = 0.0;
  int edges = 0;
  for (int f = 0; f < mesh.F.rows(); ++f)
    for (int k = 0; k < 3; ++k, ++edges) h += (mesh.V.row(mesh.F(f, k)) - mesh.V.row(mesh.F(f, (k + 1) % 3))).norm();
  h /= std::max(1, edges);
  // The body's vertical axis: through the area centroid of the garment.
  const Eigen::Vector3d axis = area_centroid(mesh.rest_V, mesh.rest_F);
  // The distance and its cross-sections are taken on the rest shape, whose
  // triangles do not depend on where earlier cuts ran; the level set is cut
  // on the pattern mesh from the same piecewise-linear distance.
  // Every limb's opening first: where its tube meets the body, and on which
  // side of the body's axis it lies.
  struct Opening {
    std::string name;
    std::vector<int> loop;
    Eigen::VectorXd d;          // geodesic distance from the loop, per rest vertex
    double found = -1.0;        // distance of its armhole, metres
    Eigen::Vector3d from;       // the loop's centroid
    bool paired = false;        // found is the mean of a mirrored pair's
  };
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
    if (Eigen::Vector2d(o.from.x() - axis.x(), o.from.z() - axis.z()).norm() < options.limb_offset) continue;
    o.d = heat_geodesic_distance(mesh.rest_V, mesh.rest_F, loop);
    double reach = 0.0;
    for (int v = 0; v < o.d.size(); ++v)
      if (std::isfinite(o.d[v])) reach = std::max(reach, o.d[v]);
    // Cross-section length along the tube: a sleeve keeps about its girth,
    // and where it meets the body the level set runs down the body's side
    // and its length grows fast.
    // L(t) on a fixed grid; its slope by least squares over a window, so
    // that the chord noise of single level sets does not decide; the
    // crossing of the threshold interpolated between grid points, so that
    // it moves continuously with the shape.
    const double step = 0.5 * h;
    std::vector<double> ts, ls;
    for (double t = step; t < reach; t += step) {
      ts.push_back(t);
      ls.push_back(level_set_length(mesh.rest_V, mesh.rest_F, o.d, t));
    }
    std::vector<double> slope(ts.size(), 0.0);
    for (size_t k = 0; k < ts.size(); ++k) {
      double st = 0.0, sl = 0.0, stt = 0.0, stl = 0.0;
      int count = 0;
      for (size_t j = 0; j < ts.size(); ++j)
        if (std::abs(ts[j] - ts[k]) <= options.slope_window) {
          st += ts[j], sl += ls[j], stt += ts[j] * ts[j], stl += ts[j] * ls[j];
          ++count;
        }
      const double den = count * stt - st * st;
      slope[k] = den > 0.0 ? (count * stl - st * sl) / den : 0.0;
    }
    for (size_t k = 1; k < ts.size(); ++k)
      if (slope[k] >= options.armhole_slope && slope[k - 1] < options.armhole_slope) {
        o.found = ts[k - 1] + (options.armhole_slope - slope[k - 1]) / (slope[k] - slope[k - 1]) * step;
        break;
      }
    // No tube (a neckline or an armhole opening) grows at once.
    if (o.found < options.min_sleeve_length) continue;
    openings.push_back(std::move(o));
  }
  // A tailor cuts both sleeves of a pair alike: two openings on either side
  // of the axis, at about the same height and distance from it, take the
  // mean of their two distances. Each alone would move with the few
  // millimetres by which a scanned body or its remeshed garment is not
  // symmetric, and the two sleeves would differ by that times their girth.
  if (openings.size() == 2) {
    Opening& a = openings[0];
    Opening& b = openings[1];
    const double ra = Eigen::Vector2d(a.from.x() - axis.x(), a.from.z() - axis.z()).norm();
    const double rb = Eigen::Vector2d(b.from.x() - axis.x(), b.from.z() - axis.z()).norm();
    const bool mirrored = (a.from.x() - axis.x()) * (b.from.x() - axis.x()) < 0.0 &&
                          std::abs(ra - rb) <= options.mirror_tolerance * std::max(ra, rb) &&
                          std::abs(a.from.y() - b.from.y()) <= options.mirror_tolerance * std::max(ra, rb) &&
                          std::abs(a.found - b.found) <= options.mirror_tolerance * std::max(a.found, b.found);
    if (mirrored) {
      a.found = b.found = 0.5 * (a.found + b.found);
      a.paired = b.paired = true;
    }
  }
  for (const Opening& o : openings) {
    Eigen::VectorXd dm(mesh.V.rows());
    for (int v = 0; v < mesh.V.rows(); ++v) {
      const SurfacePoint& q = mesh.rest_point[static_cast<size_t>(v)];
      dm[v] = q.face < 0 ? 0.0
                         : q.bary[0] * o.d[mesh.rest_F(q.face, 0)] + q.bary[1] * o.d[mesh.rest_F(q.face, 1)] +
                               q.bary[2] * o.d[mesh.rest_F(q.face, 2)];
    }
    auto sets = closed_level_sets(mesh.F, dm, o.found, options.smoothing.trace.snap_fraction,
                                  options.smoothing.trace.min_edge_fraction);
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
  if (seams.empty()) return;
  try {
    Pattern trial = pattern;
    insert_cuts(trial, seams, curves);
    pattern = std::move(trial);
    return;
  } catch (const GeometryError&) {
    // Two armholes that cross (on a rest shape grown into flaps, the level
    // sets of two sleeves can meet) or one that crosses itself: keep those
    // that go in together, in order, and leave the others to the later cuts.
  }
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

void merge_armhole_slivers(Pattern& pattern, const PatternOptions& options) {
  std::set<std::vector<int>> tried;
  for (int guard = 0; guard < 1000; ++guard) {
    // The smallest sliver not tried yet.
    size_t sliver = pattern.pieces.size();
    double smallest = options.sliver_area;
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

void cut_to_disks(Pattern& pattern, const PatternOptions& options, const PatternContext& context) {
  int count = 0;
  for (int round = 0; round < 1000; ++round) {
    std::vector<PatternSeam> seams;
    std::vector<SurfaceCurve> curves;
    for (const PatternPiece& p : pattern.pieces) {
      const auto loops = boundary_loops(p.F);
      const int euler = euler_characteristic(p.F);
      if (loops.size() == 1 && euler == 1) continue;
      const int genus2 = 2 - euler - static_cast<int>(loops.size());
      if (genus2 != 0)
        throw GeometryError("piece " + p.name + " has genus " + std::to_string(genus2 / 2) +
                            " (a handle); add seams that cut through its handles");
      const int n = static_cast<int>(p.V.rows());
      const auto neighbors = vertex_neighbors(p.F, n);
      const Eigen::MatrixXd N = vertex_normals(p.V, p.F);
      // A tailor's cut runs down the side or under the arm: length on a
      // surface facing front or back (|n_z| near 1) costs more.
      auto cost = [&](int a, int b) {
        const Eigen::Vector3d nm = (N.row(a) + N.row(b)).normalized();
        const double nz = std::isfinite(nm.z()) ? nm.z() : 0.0;
        return (p.V.row(a) - p.V.row(b)).norm() * (1.0 + options.front_back_cost * nz * nz);
      };
      const double inf = std::numeric_limits<double>::infinity();
      const auto search_from = [&](const std::vector<int>& sources, const std::function<bool(int)>& stop) {
        GraphSearch<double> search = graph_search(static_cast<size_t>(n), inf, true);
        dijkstra(neighbors, sources, cost, inf, stop, search);
        return search;
      };
      const auto never = [](int) { return false; };
      std::vector<int> path;
      std::string reason;
      auto loop_name = [&](const std::vector<int>& loop) {
        for (int v : loop) {
          const int m = p.mesh_vertex_ids[v];
          if (m < pattern.mesh.rest_vertex_count) {
            const auto it = context.boundary_names.find(m);
            if (it != context.boundary_names.end()) return "'" + it->second + "'";
          }
        }
        return std::string("through pattern vertex ") + std::to_string(p.mesh_vertex_ids[loop.front()]);
      };
      if (loops.empty()) {
        const std::vector<double> dist = search_from({0}, never).dist;
        int far = 0;
        for (int v = 0; v < n; ++v)
          if (dist[static_cast<size_t>(v)] > dist[static_cast<size_t>(far)]) far = v;
        const GraphSearch<double> from_far = search_from({far}, never);
        int other = far;
        for (int v = 0; v < n; ++v)
          if (from_far.dist[static_cast<size_t>(v)] > from_far.dist[static_cast<size_t>(other)]) other = v;
        path = trace_parents(from_far.parent, other);
        reason = "piece " + p.name + " is closed: opened between its two farthest points";
      } else {
        std::vector<int> loop_of(static_cast<size_t>(n), -1);
        for (size_t l = 0; l < loops.size(); ++l)
          for (int v : loops[l]) loop_of[static_cast<size_t>(v)] = static_cast<int>(l);
        int reached = -1;
        const GraphSearch<double> search = search_from(loops.front(), [&](int v) {
          if (loop_of[static_cast<size_t>(v)] > 0) {
            reached = v;
            return true;
          }
          return false;
        });
        if (reached < 0) throw GeometryError("piece " + p.name + " has boundary loops that no path joins");
        path = trace_parents(search.parent, reached);
        reason = "piece " + p.name + " has " + std::to_string(loops.size()) +
                 " boundary loops and must be a disk to be flattened: joins the boundary " + loop_name(loops.front()) +
                 " to the boundary " + loop_name(loops[static_cast<size_t>(loop_of[static_cast<size_t>(reached)])]) +
                 " along the shortest path that keeps off the front and back";
      }
      PatternSeam seam{"join" + std::to_string(++count), "topology", reason, {}, false, false, {}};
      SurfaceCurve c;
      if (options.smooth && path.size() > 2) {
        // Smoothed in the piece itself, so that it cannot cross into another.
        std::vector<int> fixed{path.front(), path.back()};
        const auto flags = boundary_flags(p);
        for (int v : path)
          if (flags[static_cast<size_t>(v)]) fixed.push_back(v);
        c = smooth_edge_path(p.V, p.F, path, fixed, false, options.smoothing, &seam.smoothed);
      } else {
        for (int v : path) c.push_back(CurvePoint::at_vertex(v));
      }
      curves.push_back(piece_to_mesh(p, c));
      seam.reason += ", " + metres(curve_length(p.V, p.F, c)) + " long";
      seams.push_back(seam);
    }
    if (seams.empty()) return;
    insert_cuts(pattern, seams, curves);
  }
  throw GeometryError("cutting the pieces into disks did not finish");
}

namespace {

// Every piece's distortion against the material and whether it, and the
// pattern, meet the limit, from the pieces' current flattenings.
void measure_pieces(Pattern& pattern, const PatternOptions& options) {
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    PatternPiece& p = pattern.pieces[c];
    p.stats = material_distortion(pattern, c);
    p.meets_limit = meets_limit(p, options);
  }
  pattern.meets_limit = std::all_of(pattern.pieces.begin(), pattern.pieces.end(),
                                    [](const PatternPiece& p) { return p.meets_limit; });
}

// The flattening options of the piece with `key`: its own seam weight where
// match_seams raised it.
FlattenOptions piece_flatten_options(const PatternOptions& options, const FlattenCache& cache,
                                     const std::vector<int>& key) {
  FlattenOptions flatten = options.flatten;
  const auto w = cache.boundary_weight.find(key);
  if (w != cache.boundary_weight.end()) flatten.boundary_weight = w->second;
  return flatten;
}

}  // namespace

void flatten_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, bool injective) {
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    PatternPiece& p = pattern.pieces[c];
    p.boundary = boundary_loops(p.F).front();
    const std::vector<int> key = piece_key(pattern, c);
    auto it = cache.results.find(key);
    // A plain flattening without flips is what the injective one returns too.
    if (it == cache.results.end() || (injective && it->second.stats.flipped_triangles > 0)) {
      FlattenOptions flatten = piece_flatten_options(options, cache, key);
      flatten.injective_fallback = injective;
      cache.results[key] = flatten_piece(p.V, p.F, flatten, &p.mesh_vertex_ids);
      it = cache.results.find(key);
      ++pattern.flattenings;
    }
    p.flat = it->second;
  }
  measure_pieces(pattern, options);
}

namespace {

// The output pieces' flattenings iterated on to final_tolerance: the cutter's
// decisions are made on flattenings stopped at `tolerance`, and the pieces
// it hands out are their converged shapes.
void polish_pieces(Pattern& pattern, const PatternOptions& options, const FlattenCache& cache) {
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    PatternPiece& p = pattern.pieces[c];
    polish_flattening(p.V, p.F, p.flat, piece_flatten_options(options, cache, piece_key(pattern, c)),
                      &p.mesh_vertex_ids);
  }
  measure_pieces(pattern, options);
}

}  // namespace

bool match_seams(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  std::set<int> within;
  pattern.seams_within_tolerance = seam_sides_match(pattern, options, 1.0, nullptr);
  // The boundary weight keeps most seam sides within the tolerance; a
  // mismatch beyond match_margin times the tolerance gets its pieces
  // flattened again, with 4 times the weight up to max_boundary_weight.
  std::set<int> mismatched;
  seam_sides_match(pattern, options, options.match_margin, &mismatched);
  bool again = false;
  for (int c : mismatched) {
    const std::vector<int> key = piece_key(pattern, static_cast<size_t>(c));
    auto w = cache.boundary_weight.emplace(key, options.flatten.boundary_weight).first;
    if (w->second <= 0.0 || w->second * 4.0 > options.max_boundary_weight) continue;
    w->second *= 4.0;
    cache.results.erase(key);
    again = true;
  }
  return again;
}

int place_darts_and_panels(Pattern& pattern, const PatternOptions& options, PanelLedger* ledger) {
  std::vector<PatternSeam> seams;
  std::vector<SurfaceCurve> curves;
  int darts = 0, panels = 0;
  for (const auto& s : pattern.seams) {
    if (s.kind == "dart") ++darts;
    if (s.kind == "panel") ++panels;
  }
  // Panel seams removed again keep their names: new ones are numbered on.
  for (const auto& m : pattern.merged_cuts)
    if (m.rfind("panel", 0) == 0) ++panels;
  // Failing pieces, the largest first: the piece budget goes where the most
  // cloth is.
  std::vector<size_t> order;
  for (size_t c = 0; c < pattern.pieces.size(); ++c)
    if (!pattern.pieces[c].meets_limit) order.push_back(c);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return pattern.pieces[a].stats.area_3d > pattern.pieces[b].stats.area_3d;
  });
  if (order.empty()) return 0;
  // A tailor cuts both sides of the body alike: a piece's mirror image gets
  // the mirror image of its darts and panel seam, whether or not it is over
  // the limit itself.
  const PieceMirror mirror = options.mirror ? mirror_pieces(pattern, options.mirror_overlap) : PieceMirror{};
  auto partner = [&](size_t c) { return mirror.partner.empty() ? -1 : mirror.partner[c]; };
  std::vector<char> done(pattern.pieces.size(), 0);
  // Pieces given a cut this round (a piece's mirror image that was given
  // none, on its own, still takes the mirror image of the piece's).
  std::vector<char> cut(pattern.pieces.size(), 0);
  int pieces = static_cast<int>(pattern.pieces.size());

  // What a piece was given: its dart tips and the point its panel seam runs
  // through, and the names of the cuts.
  struct Given {
    std::vector<DartTip> tips;
    std::vector<std::string> darts;
    std::optional<Eigen::Vector3d> centre;
    std::string panel;
  };
  // Mirror images are judged and removed together (review_panels,
  // merge_small_pieces).
  auto pair_mirrors = [&](PatternSeam& seam, const std::string& image) {
    if (image.empty()) return;
    seam.mirror = image;
    for (PatternSeam& s : seams)
      if (s.name == image) s.mirror = seam.name;
  };
  auto place = [&](size_t c, const Given* source, size_t source_piece) {
    Given given;
    const PatternPiece& p = pattern.pieces[c];
    const std::string over =
        source ? "piece " + p.name + " is cut as its mirror image " + pattern.pieces[source_piece].name + " is: "
               : "piece " + p.name + " exceeds the limit (compression " + percent(p.stats.worst1_compression) +
                     " over its worst 1 %, ease " + percent(p.stats.worst5_ease) + " over its worst 5 %): ";
    Eigen::MatrixXd chart;
    try {
      chart = conformal_chart(p);
    } catch (const NumericalError&) {
      pattern.notes.push_back("piece " + p.name + ": no conformal chart to place a dart or seam in");
      return given;
    }
    // Darts first (a tailor darts before adding a seam): every tip strong
    // enough at once, up to the piece's budget.
    const int left = options.max_darts - static_cast<int>(p.dart_seams.size());
    if (left > 0) {
      // Darts already in the piece and those placed now, as chart polylines:
      // a new dart must not cross one (their curves would cross in a face).
      std::vector<Eigen::MatrixXd> drawn;
      {
        std::map<int, int> local;
        for (int v = 0; v < p.V.rows(); ++v) local[p.mesh_vertex_ids[v]] = v;
        for (int d : p.dart_seams) {
          std::vector<Eigen::Vector2d> pts;
          const auto& ids = pattern.seams[static_cast<size_t>(d)].vertex_ids;
          for (int v : ids) {
            const auto it = local.find(v);
            if (it != local.end()) pts.push_back(chart.row(it->second).transpose());
          }
          Eigen::MatrixXd P(static_cast<int>(pts.size()), 2);
          for (size_t i = 0; i < pts.size(); ++i) P.row(static_cast<int>(i)) = pts[i].transpose();
          drawn.push_back(P);
        }
      }
      auto add_dart = [&](const DartTip& tip, const std::string& how, const std::string& mirror_of) {
        if (static_cast<int>(given.tips.size()) >= left) return;
        const auto curve = dart_curve(p, chart, tip, options, drawn);
        if (!curve) return;
        drawn.push_back(curve_positions(chart, p.F, *curve));
        char deg[32];
        std::snprintf(deg, sizeof(deg), "%.1f", tip.curvature * 180.0 / M_PI);
        PatternSeam seam{"dart" + std::to_string(++darts), "dart", "", {}, false, true, {}};
        pair_mirrors(seam, mirror_of);
        seam.reason = over + how + " (" + deg + " degrees within " + metres(options.kernel_radius) + "), " +
                      metres(curve_length(p.V, p.F, *curve)) + " long";
        given.tips.push_back(tip);
        given.darts.push_back(seam.name);
        seams.push_back(seam);
        curves.push_back(piece_to_mesh(p, *curve));
      };
      const std::string mode = std::string("dart to the mode of its ") +
                               (options.dart_placement == PatternOptions::DartPlacement::conformal
                                    ? "log conformal factor"
                                    : "Gaussian curvature");
      if (source) {
        for (size_t i = 0; i < source->tips.size(); ++i)
          if (const auto tip = dart_tip_near(pattern, c, mirror.reflect(source->tips[i].point), options.min_dart_angle,
                                             options))
            add_dart(*tip, "the mirror image of " + source->darts[i], source->darts[i]);
      } else {
        for (const DartTip& tip : dart_tips(pattern, c, options, left)) add_dart(tip, mode, "");
      }
    }
    const std::vector<int> rest_faces = piece_rest_faces(pattern, c);
    // A piece whose mirror image's panel seam did not pay is refused too.
    const int d = partner(c);
    const bool refused =
        ledger && (ledger->refused.count(rest_faces) ||
                   (d >= 0 && d != static_cast<int>(c) &&
                    ledger->refused.count(piece_rest_faces(pattern, static_cast<size_t>(d)))));
    // A piece and its mirror image take two pieces from the budget together.
    const int cost = !source && d >= 0 && d != static_cast<int>(c) && !cut[static_cast<size_t>(d)] ? 2 : 1;
    if (given.tips.empty() && pieces + cost <= options.max_pieces && !refused && (!source || source->centre)) {
      std::optional<Eigen::Vector3d> centre =
          source ? std::optional<Eigen::Vector3d>(mirror.reflect(*source->centre)) : panel_centre(p, options);
      // A piece across the plane is split as a tailor splits a front or a
      // back: by a centre seam (two mirrored seams were tried; README.md,
      // "Both sides cut alike").
      std::string how;
      if (centre && !source && partner(c) == static_cast<int>(c)) {
        centre = centre_seam_point(p, mirror.plane_x, *centre);
        how = "centre seam along the grain at the middle of the body, at the height of the centroid of its conformal "
              "distortion energy";
      }
      std::string where;
      auto curve = centre ? panel_curve(pattern, c, chart, *centre, options, &where) : std::nullopt;
      if (source) where = "the mirror image of " + source->panel;
      if (source && !curve) {
        // No room where the image falls (the two sides of a scanned body
        // differ): the piece's own panel seam, so that both sides are split.
        centre = panel_centre(p, options);
        curve = centre ? panel_curve(pattern, c, chart, *centre, options) : std::nullopt;
        where += ", through its own centroid (the mirrored point leaves no room)";
      }
      if (curve) {
        if (!how.empty()) where = how;
        PatternSeam seam{"panel" + std::to_string(++panels), "panel", "", {}, false, true, {}};
        if (source) pair_mirrors(seam, source->panel);
        seam.reason = over + where + ", " + metres(curve_length(p.V, p.F, *curve)) + " long";
        seams.push_back(seam);
        curves.push_back(piece_to_mesh(p, *curve));
        if (ledger)
          ledger->trials.push_back(
              {seam.name, rest_faces, panel_excess(material_faces(pattern, c), options), p.stats.worst1_compression});
        ++pieces;
        given.centre = centre;
        given.panel = seam.name;
      }
    }
    if (given.tips.empty() && !given.centre) {
      if (source)
        pattern.notes.push_back(over + "no dart or panel seam fits where its mirror image has one");
      else
        pattern.notes.push_back(over + "no further dart or panel seam fits" +
                                (refused ? " (a panel seam did not relieve it)"
                                         : pieces + cost > options.max_pieces ? " (the pattern has its most pieces)" : ""));
    }
    return given;
  };

  for (size_t c : order) {
    if (done[c]) continue;
    done[c] = 1;
    const Given given = place(c, nullptr, c);
    cut[c] = !given.tips.empty() || given.centre;
    const int d = partner(c);
    if (d < 0 || d == static_cast<int>(c) || cut[static_cast<size_t>(d)]) continue;
    if (!cut[c]) continue;  // the mirror image decides for itself
    done[static_cast<size_t>(d)] = 1;
    const Given image = place(static_cast<size_t>(d), &given, c);
    cut[static_cast<size_t>(d)] = !image.tips.empty() || image.centre;
    // A panel seam whose mirror image has no room is not cut either, and the
    // piece gets no other: one side split and the other not is no pattern.
    if (!given.panel.empty() && image.panel.empty()) {
      for (size_t i = 0; i < seams.size(); ++i)
        if (seams[i].name == given.panel) {
          seams.erase(seams.begin() + static_cast<long>(i));
          curves.erase(curves.begin() + static_cast<long>(i));
          break;
        }
      if (ledger) {
        auto& trials = ledger->trials;
        trials.erase(std::remove_if(trials.begin(), trials.end(),
                                    [&](const PanelTrial& t) { return t.seam == given.panel; }),
                     trials.end());
        ledger->refused.insert(piece_rest_faces(pattern, c));
      }
      --panels;
      --pieces;
      pattern.notes.push_back("piece " + pattern.pieces[c].name + ": no panel seam, as its mirror image " +
                              pattern.pieces[static_cast<size_t>(d)].name + " has no room for one");
    }
  }
  if (seams.empty()) return 0;
  insert_cuts(pattern, seams, curves);
  return static_cast<int>(seams.size());
}

namespace {

// Takes the seams at `indices` out of the pattern (pieces not reassembled);
// a cut whose mirror image goes loses its pairing.
void erase_seams(Pattern& pattern, std::vector<size_t> indices) {
  std::sort(indices.rbegin(), indices.rend());
  std::set<std::string> gone;
  for (size_t i : indices) {
    gone.insert(pattern.seams[i].name);
    pattern.seams.erase(pattern.seams.begin() + static_cast<long>(i));
  }
  for (PatternSeam& s : pattern.seams)
    if (gone.count(s.mirror)) s.mirror.clear();
}

// Where a panel seam runs on the pattern as it is.
struct PanelSides {
  size_t seam = 0;       // index in pattern.seams
  std::set<int> pieces;  // the pieces on either side: the parts of the piece it split
  double length = 0.0;   // metres
};

std::optional<PanelSides> panel_sides(const Pattern& pattern, const std::string& name) {
  PanelSides j;
  j.seam = pattern.seams.size();
  for (size_t i = 0; i < pattern.seams.size(); ++i)
    if (pattern.seams[i].name == name) j.seam = i;
  if (j.seam >= pattern.seams.size()) return std::nullopt;
  for (const CutEdge& e : pattern.cut.edges)
    if (static_cast<size_t>(e.seam) == j.seam) {
      j.pieces.insert(pattern.piece_of_face[static_cast<size_t>(e.left_face)]);
      j.pieces.insert(pattern.piece_of_face[static_cast<size_t>(e.right_face)]);
      j.length += e.length;
    }
  return j;
}

}  // namespace

int review_panels(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, PanelLedger& ledger) {
  int removed = 0;
  // In the order they were placed, each judged on the pattern as the
  // removals before it left it (a removal changes no other piece); a seam
  // and its mirror image together.
  const std::vector<PanelTrial> trials = std::move(ledger.trials);
  ledger.trials.clear();
  std::set<std::string> judged;
  for (const PanelTrial& first : trials) {
    if (judged.count(first.seam)) continue;
    std::vector<const PanelTrial*> group{&first};
    judged.insert(first.seam);
    const auto j0 = panel_sides(pattern, first.seam);
    if (!j0) continue;
    const std::string& image = pattern.seams[j0->seam].mirror;
    for (const PanelTrial& t : trials)
      if (!image.empty() && t.seam == image && !judged.count(t.seam)) {
        group.push_back(&t);
        judged.insert(t.seam);
      }
    // Judged together: the cloth beyond the limit in the pieces they split
    // against that in all their parts, and their whole length.
    std::vector<PanelSides> js;
    std::set<int> parts;
    double length = 0.0, before = 0.0, compression = 0.0;
    bool tight = false;
    for (const PanelTrial* t : group) {
      const auto j = panel_sides(pattern, t->seam);
      if (!j) continue;
      js.push_back(*j);
      parts.insert(j->pieces.begin(), j->pieces.end());
      length += j->length;
      before += t->excess_before;
      compression = std::max(compression, t->compression_before);
      tight = tight || t->compression_before > options.budget_share * options.stretch_budget;
    }
    double after = 0.0;
    bool within = true;
    for (int c : parts) {
      after += panel_excess(material_faces(pattern, static_cast<size_t>(c)), options);
      within = within && pattern.pieces[static_cast<size_t>(c)].meets_limit;
    }
    const double relief = before - after;
    char buf[220];
    std::snprintf(buf, sizeof(buf), "%.1f of the %s %.1f cm^2 of cloth beyond the limit (%.0f cm^2 per metre of seam)",
                  1e4 * relief, js.size() > 1 ? "two mirrored pieces'" : "piece's", 1e4 * before,
                  length > 0.0 ? 1e4 * relief / length : 0.0);
    // A seam that brings both its pieces within the limit does what the
    // cutter is for, however little cloth that took, where the compression
    // it relieved ate much of the fit's stretch budget.
    // And the cutter stops adding pieces only when the limit is met (issue
    // 49): a seam that took away most of its piece's cloth beyond the limit
    // (min_relief_share) stays, however long, while that piece was over it.
    const bool most = options.min_relief_share > 0.0 && before > 0.0 && relief >= options.min_relief_share * before;
    if (relief >= options.min_panel_relief * length || (within && tight) || most) {
      char budget[180] = "";
      if (relief < options.min_panel_relief * length && within && tight)
        std::snprintf(budget, sizeof(budget),
                      ", and both its pieces meet the limit (the piece was compressed by %.2f %%, more than %.0f %% of "
                      "the stretch budget %.3f)",
                      100.0 * compression, 100.0 * options.budget_share, options.stretch_budget);
      else if (relief < options.min_panel_relief * length)
        std::snprintf(budget, sizeof(budget), ", at least %.0f %% of it (min_relief_share)",
                      100.0 * options.min_relief_share);
      for (const PanelSides& j : js) pattern.seams[j.seam].reason += std::string("; it relieved ") + buf + budget;
      continue;
    }
    Pattern without = pattern;
    std::vector<size_t> gone;
    std::vector<std::string> names;
    for (const PanelSides& j : js) {
      gone.push_back(j.seam);
      names.push_back(pattern.seams[j.seam].name);
    }
    erase_seams(without, gone);
    assemble_pieces(without);
    if (!std::all_of(without.pieces.begin(), without.pieces.end(), [](const PatternPiece& p) { return is_disk(p); }))
      continue;
    flatten_pieces(without, options, cache, true);
    for (const std::string& name : names) {
      without.merged_cuts.push_back(name);
      without.notes.push_back(name + " removed: " + (js.size() > 1 ? "with its mirror image it" : "it") +
                              " relieved only " + buf);
    }
    for (const PanelTrial* t : group) ledger.refused.insert(t->rest_faces);
    pattern = std::move(without);
    removed += static_cast<int>(names.size());
  }
  return removed;
}

void merge_small_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  std::set<std::string> tried;
  for (;;) {
    // The smallest piece below the area bordering an added cut.
    size_t best_seam = pattern.seams.size();
    double best_area = options.min_piece_area;
    for (const CutEdge& e : pattern.cut.edges) {
      const PatternSeam& s = pattern.seams[static_cast<size_t>(e.seam)];
      // User seams and armholes are structure, darts lie inside one piece.
      if (s.kind == "user" || s.kind == "armhole" || s.kind == "dart" || tried.count(s.name)) continue;
      const int l = pattern.piece_of_face[static_cast<size_t>(e.left_face)];
      const int r = pattern.piece_of_face[static_cast<size_t>(e.right_face)];
      if (l == r) continue;
      const double a = std::min(pattern.pieces[static_cast<size_t>(l)].stats.area_3d,
                                pattern.pieces[static_cast<size_t>(r)].stats.area_3d);
      if (a < best_area || (a == best_area && static_cast<size_t>(e.seam) < best_seam))
        best_area = a, best_seam = static_cast<size_t>(e.seam);
    }
    if (best_seam >= pattern.seams.size()) return;
    // The cut goes with its mirror image, as both sides are cut alike.
    std::vector<size_t> gone{best_seam};
    for (size_t i = 0; i < pattern.seams.size(); ++i)
      if (!pattern.seams[best_seam].mirror.empty() && pattern.seams[i].name == pattern.seams[best_seam].mirror)
        gone.push_back(i);
    for (size_t i : gone) tried.insert(pattern.seams[i].name);
    Pattern trial = pattern;
    erase_seams(trial, gone);
    assemble_pieces(trial);
    if (!std::all_of(trial.pieces.begin(), trial.pieces.end(), [](const PatternPiece& p) { return is_disk(p); }))
      continue;
    flatten_pieces(trial, options, cache, true);
    for (size_t i : gone) trial.merged_cuts.push_back(pattern.seams[i].name);
    pattern = std::move(trial);
  }
}

void remove_overlapping_darts(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  auto overlaps = [](const Pattern& x) {
    int n = 0;
    for (const PatternPiece& p : x.pieces) n += p.flat.boundary_overlaps ? 1 : 0;
    return n;
  };
  for (;;) {
    // Of the darts in pieces whose outline overlaps itself, the one whose
    // removal removes an overlap, adds none and leaves the least cloth
    // beyond the limit (panel_excess): with two darts in a piece, the one
    // whose sides crossed, which had too little curvature to take in.
    const int before = overlaps(pattern);
    if (before == 0) return;
    std::optional<Pattern> best;
    double best_excess = std::numeric_limits<double>::infinity();
    std::string best_name;
    for (const PatternPiece& p : pattern.pieces) {
      if (!p.flat.boundary_overlaps) continue;
      for (int d : p.dart_seams) {
        Pattern trial = pattern;
        erase_seams(trial, {static_cast<size_t>(d)});
        assemble_pieces(trial);
        if (!std::all_of(trial.pieces.begin(), trial.pieces.end(), [](const PatternPiece& q) { return is_disk(q); }))
          continue;
        flatten_pieces(trial, options, cache, true);
        if (overlaps(trial) >= before) continue;
        double excess = 0.0;
        for (size_t c = 0; c < trial.pieces.size(); ++c) excess += panel_excess(material_faces(trial, c), options);
        if (excess < best_excess) {
          best_excess = excess;
          best_name = pattern.seams[static_cast<size_t>(d)].name;
          best = std::move(trial);
        }
      }
    }
    if (!best) return;
    best->merged_cuts.push_back(best_name);
    best->notes.push_back(best_name + " removed: its sides crossed in the flat piece, which overlapped itself");
    pattern = std::move(*best);
  }
}

namespace {

// The shortest path through piece p (3D edge lengths, inner vertices only
// between its ends) from outline vertex `from` to the outline vertex half
// the outline's length round from it; nullopt when none runs inside.
std::optional<SurfaceCurve> halving_cut(const PatternPiece& p, int from) {
  const std::vector<int>& loop = p.boundary;
  const size_t nb = loop.size();
  const auto start = std::find(loop.begin(), loop.end(), from);
  if (start == loop.end() || nb < 4) return std::nullopt;
  const size_t i0 = static_cast<size_t>(start - loop.begin());
  std::vector<double> along(nb + 1, 0.0);
  for (size_t k = 0; k < nb; ++k)
    along[k + 1] = along[k] + (p.V.row(loop[(i0 + k) % nb]) - p.V.row(loop[(i0 + k + 1) % nb])).norm();
  size_t half = 1;
  while (half + 1 < nb && along[half] < 0.5 * along[nb]) ++half;
  const int to = loop[(i0 + half) % nb];
  const std::vector<char> on_outline = boundary_flags(p);
  std::vector<std::vector<int>> neighbors(static_cast<size_t>(p.V.rows()));
  for (int f = 0; f < p.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = p.F(f, k), b = p.F(f, (k + 1) % 3);
      neighbors[static_cast<size_t>(a)].push_back(b);
      neighbors[static_cast<size_t>(b)].push_back(a);
    }
  for (auto& n : neighbors) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  const double inf = std::numeric_limits<double>::infinity();
  GraphSearch<double> search = graph_search(neighbors.size(), inf, true);
  dijkstra(
      neighbors, {from},
      [&](int v, int w) {
        // Along the outline only to reach the far end directly.
        if (w != to && on_outline[static_cast<size_t>(w)]) return inf;
        if (v == from && w == to && on_outline[static_cast<size_t>(v)]) {
          // An outline edge is no cut.
          const size_t k = static_cast<size_t>(std::find(loop.begin(), loop.end(), w) - loop.begin());
          if (loop[(k + 1) % nb] == v || loop[(k + nb - 1) % nb] == v) return inf;
        }
        return (p.V.row(v) - p.V.row(w)).norm();
      },
      inf, [&](int v) { return v == to; }, search);
  if (!std::isfinite(search.dist[static_cast<size_t>(to)])) return std::nullopt;
  SurfaceCurve cut;
  for (int v : trace_parents(search.parent, to)) cut.push_back(CurvePoint::at_vertex(v));
  if (cut.size() < 2) return std::nullopt;
  return cut;
}

}  // namespace

int split_overlapping_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  int added = 0;
  int panels = 0;
  for (const auto& s : pattern.seams)
    if (s.kind == "panel") ++panels;
  for (const auto& m : pattern.merged_cuts)
    if (m.rfind("panel", 0) == 0) ++panels;
  // Each round splits every piece still overlapping once, then flattens:
  // a piece's two parts are each smaller than the outline that crossed
  // itself, and a part that still overlaps is split again.
  for (int round = 0; round < options.max_overlap_splits; ++round) {
    std::vector<PatternSeam> seams;
    std::vector<SurfaceCurve> curves;
    for (size_t c = 0; c < pattern.pieces.size(); ++c) {
      const PatternPiece& p = pattern.pieces[c];
      if (!p.flat.boundary_overlaps) continue;
      Eigen::MatrixXd chart;
      try {
        chart = conformal_chart(p);
      } catch (const NumericalError&) {
        continue;
      }
      // Through the crossing: the outline vertices there, halfway to the
      // piece's centroid (a grain line through an outline point itself may
      // only graze the piece).
      Eigen::Vector3d at = Eigen::Vector3d::Zero();
      for (int v : p.flat.overlap_vertex_ids) at += p.V.row(v).transpose();
      if (!p.flat.overlap_vertex_ids.empty()) at /= static_cast<double>(p.flat.overlap_vertex_ids.size());
      const Eigen::Vector3d centroid = p.V.colwise().mean().transpose();
      std::string where;
      std::optional<SurfaceCurve> curve;
      for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.5 * (at + centroid)), at, centroid}) {
        curve = panel_curve(pattern, c, chart, x, options, &where);
        if (curve) break;
      }
      // The grain line needs a chart to run straight in, and the chart of a
      // piece that winds past a full turn overlaps too: else the shortest
      // path through the piece from the crossing to the outline point
      // halfway round from it, which halves the outline's winding.
      for (size_t i = 0; !curve && i < p.flat.overlap_vertex_ids.size(); ++i) {
        curve = halving_cut(p, p.flat.overlap_vertex_ids[i]);
        where = "the shortest path through it from the crossing to the outline point halfway round";
      }
      if (!curve) continue;
      PatternSeam seam{"panel" + std::to_string(++panels), "panel", "", {}, false, true, {}};
      seam.reason = "piece " + p.name + " overlapped itself in the flat near (" + metres(at.x()) + ", " +
                    metres(at.y()) + ", " + metres(at.z()) + "): " + where + ", " +
                    metres(curve_length(p.V, p.F, *curve)) + " long";
      seams.push_back(seam);
      curves.push_back(piece_to_mesh(p, *curve));
    }
    if (seams.empty()) break;
    added += static_cast<int>(seams.size());
    insert_cuts(pattern, seams, curves);
    flatten_pieces(pattern, options, cache, true);
    while (match_seams(pattern, options, cache)) flatten_pieces(pattern, options, cache, true);
  }
  return added;
}

Pattern make_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                     const PatternOptions& options, const PatternContext& context) {
  LapTimer timer;
  std::map<std::string, double> seconds;
  auto lap = [&](const std::string& phase) { seconds[phase] += timer.lap(); };
  Pattern pattern = cut_user_seams(V, F, seams, options);
  lap("user_seams");
  if (options.armholes) {
    cut_armholes(pattern, options, context);
    merge_armhole_slivers(pattern, options);
  }
  lap("armholes");
  cut_to_disks(pattern, options, context);
  lap("disks");
  FlattenCache cache;
  PanelLedger ledger;
  for (int round = 0; round < options.max_rounds; ++round) {
    ++pattern.rounds;
    flatten_pieces(pattern, options, cache, true);
    while (match_seams(pattern, options, cache)) flatten_pieces(pattern, options, cache, true);
    lap("flatten");
    if (review_panels(pattern, options, cache, ledger) > 0)
      while (match_seams(pattern, options, cache)) flatten_pieces(pattern, options, cache, true);
    lap("review_panels");
    if (pattern.meets_limit) break;
    const int added = place_darts_and_panels(pattern, options, &ledger);
    lap("darts_and_panels");
    if (added == 0) break;
  }
  flatten_pieces(pattern, options, cache, true);
  lap("flatten");
  review_panels(pattern, options, cache, ledger);
  merge_small_pieces(pattern, options, cache);
  remove_overlapping_darts(pattern, options, cache);
  split_overlapping_pieces(pattern, options, cache);
  // The output has no flipped triangle: pieces left with flips are
  // flattened injectively.
  flatten_pieces(pattern, options, cache, true);
  lap("merge");
  polish_pieces(pattern, options, cache);
  pattern.seams_within_tolerance = seam_sides_match(pattern, options, 1.0, nullptr);
  // The final names: mirrored pieces named alike, from their average.
  if (options.mirror) name_pieces(pattern, mirror_pieces(pattern, options.mirror_overlap));
  lap("polish");
  pattern.seconds = seconds;
  return pattern;
}

}  // namespace gp
