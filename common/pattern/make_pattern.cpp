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
    if (options.seams.smooth) {
      c = smooth_edge_path(V, F, s.vertex_ids, fixed, s.closed, options.seams.smoothing, &seam.smoothed, s.click_ids);
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
    if (!options.seams.smooth) throw;
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

Pattern make_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                     const PatternOptions& options, const PatternContext& context) {
  LapTimer timer;
  std::map<std::string, double> seconds;
  auto lap = [&](const std::string& phase) { seconds[phase] += timer.lap(); };
  Pattern pattern = cut_user_seams(V, F, seams, options);
  lap("user_seams");
  if (options.armholes.enabled) {
    cut_armholes(pattern, options, context);
    merge_armhole_slivers(pattern, options);
  }
  lap("armholes");
  cut_to_disks(pattern, options, context);
  lap("disks");
  FlattenCache cache;
  PanelLedger ledger;
  for (int round = 0; round < options.panels.max_rounds; ++round) {
    ++pattern.rounds;
    flatten_pieces(pattern, options, cache, true);
    while (match_seams(pattern, options, cache)) flatten_pieces(pattern, options, cache, true);
    // A piece over one bound and within the other trades them before it
    // gets a dart or a panel seam.
    if (balance_ease(pattern, options, cache))
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
  if (balance_ease(pattern, options, cache))
    while (match_seams(pattern, options, cache)) flatten_pieces(pattern, options, cache, true);
  lap("merge");
  polish_pieces(pattern, options, cache);
  pattern.seams_within_tolerance = seam_sides_match(pattern, options, 1.0, nullptr);
  // The final names: mirrored pieces named alike, from their average.
  if (options.panels.mirror) name_pieces(pattern, mirror_pieces(pattern, options.panels.mirror_overlap));
  lap("polish");
  pattern.seconds = seconds;
  return pattern;
}

}  // namespace gp
