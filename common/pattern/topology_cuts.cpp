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

void cut_to_disks(Pattern& pattern, const PatternOptions& options, const PatternContext& context) {
  int count = 0;
  for (int round = 0; round < 1000; ++round) {
    std::vector<PatternSeam> seams;
    std::vector<SurfaceCurve> curves;
    for (size_t piece = 0; piece < pattern.pieces.size(); ++piece) {
      const PatternPiece& p = pattern.pieces[piece];
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
        return (p.V.row(a) - p.V.row(b)).norm() * (1.0 + options.seams.front_back_cost * nz * nz);
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
        // A tailor's sleeve seam runs under the arm, from the cuff to the
        // armpit, where it splits the armpit's saddle between its two sides:
        // from the lowest point of a sleeve's outline (the underside of the
        // cuff or the armpit, in a design pose with the arms down or out).
        // Joined anywhere along a loop instead, one sleeve of the generated
        // shirt was opened over the shoulder, its armpit in the middle of the
        // piece (pattern README, "Sleeves opened under the arm").
        int from_loop = 0;
        std::vector<int> sources = loops.front();
        const bool sleeve = piece_limb(pattern, piece) >= 0;
        if (sleeve) {
          std::vector<int> all;
          for (const auto& loop : loops) all.insert(all.end(), loop.begin(), loop.end());
          const int lowest =
              *std::min_element(all.begin(), all.end(), [&](int a, int b) { return p.V(a, 1) < p.V(b, 1); });
          from_loop = loop_of[static_cast<size_t>(lowest)];
          sources = {lowest};
        }
        int reached = -1;
        const GraphSearch<double> search = search_from(sources, [&](int v) {
          if (loop_of[static_cast<size_t>(v)] >= 0 && loop_of[static_cast<size_t>(v)] != from_loop) {
            reached = v;
            return true;
          }
          return false;
        });
        if (reached < 0) throw GeometryError("piece " + p.name + " has boundary loops that no path joins");
        path = trace_parents(search.parent, reached);
        reason = "piece " + p.name + " has " + std::to_string(loops.size()) +
                 " boundary loops and must be a disk to be flattened: joins the boundary " +
                 loop_name(loops[static_cast<size_t>(from_loop)]) +
                 " to the boundary " + loop_name(loops[static_cast<size_t>(loop_of[static_cast<size_t>(reached)])]) +
                 (sleeve ? " along the shortest path from its lowest point (under the arm)"
                         : " along the shortest path that keeps off the front and back");
      }
      PatternSeam seam{"join" + std::to_string(++count), "topology", reason, {}, false, false, {}};
      SurfaceCurve c;
      if (options.seams.smooth && path.size() > 2) {
        // Smoothed in the piece itself, so that it cannot cross into another.
        std::vector<int> fixed{path.front(), path.back()};
        const auto flags = boundary_flags(p);
        for (int v : path)
          if (flags[static_cast<size_t>(v)]) fixed.push_back(v);
        c = smooth_edge_path(p.V, p.F, path, fixed, false, options.seams.smoothing, &seam.smoothed);
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

}  // namespace gp
