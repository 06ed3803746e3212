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

bool meets_limit(const PatternPiece& piece, const PatternOptions& options) {
  if (piece.flat.stats.flipped_triangles > 0 || piece.flat.boundary_overlaps) return false;
  const DistortionStats& s = piece.stats;
  if (options.limit.symmetric) return s.p95_error <= options.limit.p95_limit && s.max_error <= options.limit.max_limit;
  return s.worst1_compression <= options.limit.compression_worst1 && s.worst5_ease <= options.limit.ease_worst5;
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
  // The limit weighting aims at the cutter's own limit.
  flatten.limit_compression = options.limit.symmetric ? options.limit.max_limit : options.limit.compression_worst1;
  flatten.limit_ease = options.limit.symmetric ? options.limit.max_limit : options.limit.ease_worst5;
  // ... and leaves no triangle compressed beyond its share of the fit's
  // stretch budget (PanelOptions::weighting_budget_share).
  flatten.compression_budget = options.panels.weighting_budget_share * options.panels.stretch_budget;
  const auto w = cache.boundary_weight.find(key);
  if (w != cache.boundary_weight.end()) flatten.boundary_weight = w->second;
  const auto e = cache.ease_weight.find(key);
  if (e != cache.ease_weight.end()) flatten.ease_weight = e->second;
  return flatten;
}

// How far a piece is from the one-sided limit: the larger of its two bounds'
// ratios (at most 1: within), infinite with flips or an overlapping outline.
double limit_ratio(const PatternPiece& p, const PatternOptions& options) {
  if (p.flat.stats.flipped_triangles > 0 || p.flat.boundary_overlaps) return std::numeric_limits<double>::infinity();
  auto ratio = [](double value, double bound) {
    return bound > 0.0 ? value / bound : (value > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  };
  return std::max(ratio(p.stats.worst1_compression, options.limit.compression_worst1),
                  ratio(p.stats.worst5_ease, options.limit.ease_worst5));
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


bool balance_ease(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  if (options.limit.symmetric || options.panels.ease_balance_steps <= 0 || options.panels.ease_balance_factor <= 1.0) return false;
  bool changed = false;
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    PatternPiece& p = pattern.pieces[c];
    if (p.meets_limit || p.flat.stats.flipped_triangles > 0 || p.flat.boundary_overlaps) continue;
    const bool tight = p.stats.worst1_compression > options.limit.compression_worst1;
    const bool loose = p.stats.worst5_ease > options.limit.ease_worst5;
    if (tight == loose) continue;  // over both bounds (or neither): no trade helps
    const std::vector<int> key = piece_key(pattern, c);
    const FlattenOptions base = piece_flatten_options(options, cache, key);
    // Over compression: ease made cheaper, so that the piece grows where it
    // was tight; over ease: dearer.
    const double factor = tight ? 1.0 / options.panels.ease_balance_factor : options.panels.ease_balance_factor;
    const FlattenResult before = p.flat;
    const DistortionStats stats_before = p.stats;
    double best_ratio = limit_ratio(p, options), best_weight = base.ease_weight;
    FlattenResult best = before;
    double w = base.ease_weight;
    for (int k = 0; k < options.panels.ease_balance_steps; ++k) {
      const double next = std::clamp(w * factor, std::max(options.panels.min_ease_weight, 1e-6), 1.0);
      if (next == w) break;
      w = next;
      FlattenOptions flatten = base;
      flatten.ease_weight = w;
      flatten.injective_fallback = true;
      p.flat = flatten_piece(p.V, p.F, flatten, &p.mesh_vertex_ids);
      ++pattern.flattenings;
      p.stats = material_distortion(pattern, c);
      const double r = limit_ratio(p, options);
      if (r < best_ratio) {
        best_ratio = r;
        best_weight = w;
        best = p.flat;
      }
      if (r <= 1.0) break;
    }
    p.flat = best;
    p.stats = stats_before;
    // Only a trade that brings the piece within the limit is kept: one that
    // only brings it nearer moves its outline for nothing a dart or a panel
    // seam would not then redo.
    if (best_weight != base.ease_weight && best_ratio <= 1.0) {
      cache.ease_weight[key] = best_weight;
      cache.results[key] = best;
      changed = true;
    }
  }
  measure_pieces(pattern, options);
  return changed;
}

bool match_seams(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  std::set<int> within;
  pattern.seams_within_tolerance = seam_sides_match(pattern, options, 1.0, nullptr);
  // The boundary weight keeps most seam sides within the tolerance; a
  // mismatch beyond match_margin times the tolerance gets its pieces
  // flattened again, with 4 times the weight up to max_boundary_weight.
  std::set<int> mismatched;
  seam_sides_match(pattern, options, options.seams.match_margin, &mismatched);
  bool again = false;
  for (int c : mismatched) {
    const std::vector<int> key = piece_key(pattern, static_cast<size_t>(c));
    auto w = cache.boundary_weight.emplace(key, options.flatten.boundary_weight).first;
    if (w->second <= 0.0 || w->second * 4.0 > options.seams.max_boundary_weight) continue;
    w->second *= 4.0;
    cache.results.erase(key);
    again = true;
  }
  return again;
}

}  // namespace gp
