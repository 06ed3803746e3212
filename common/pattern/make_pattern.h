#pragma once
// From a rest shape and the user's seams to the pieces of a sewing pattern,
// in phases, one function each (README.md has the method); phases 3-5 repeat
// until every piece meets the limit. Decisions use smooth quantities with
// ties broken by ids, so a small change of the rest shape changes no count.
#include <map>
#include <set>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "pattern/flatten.h"
#include "pattern/pattern.h"
#include "pattern/pattern_options.h"
#include "pattern/seam_spec.h"
#include "pattern/surface_curve.h"

namespace gp {

// No flipped triangle, no overlapping outline, distortion within the limit.
bool meets_limit(const PatternPiece& piece, const PatternOptions& options);

// The rest shape is in the body's frame (+y up, +z front, +x the body's left).
struct PatternContext {
  std::map<int, std::string> boundary_names;  // rest vertex -> loop name
};

// Phase 1: the pattern mesh refined along the user seams (smoothed unless
// options.seams.smooth is false) and cut into pieces.
Pattern cut_user_seams(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                       const PatternOptions& options);

// Phase 1b: armholes (see ArmholeOptions, PatternOptions::armholes).
void cut_armholes(Pattern& pattern, const PatternOptions& options, const PatternContext& context);

// Phase 1c: a sliver (< sliver_area) an armhole left beside a user seam joins
// the neighbour sharing the most armhole.
void merge_armhole_slivers(Pattern& pattern, const PatternOptions& options);

// Phase 2: topology cuts until every piece is a disk. Throws GeometryError
// for a piece of genus > 0 (seams must cut its handles).
void cut_to_disks(Pattern& pattern, const PatternOptions& options, const PatternContext& context);

// Flattenings reused across rounds, keyed by the piece's triangles and slits.
struct FlattenCache {
  std::map<std::vector<int>, FlattenResult> results;
  std::map<std::vector<int>, double> boundary_weight;  // raised where seam sides differ
  std::map<std::vector<int>, double> ease_weight;      // set where balance_ease moved it
};

// Phase 3: flattens every piece (or reuses an unchanged one) and sets
// meets_limit; `injective` asks for a flip-free result.
void flatten_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, bool injective);

// Phase 4: whether the pieces on mismatched seams were flattened again.
bool match_seams(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// Phase 4b (one-sided limit): a piece over one bound and within the other
// is flattened again with ease cheaper or dearer (PanelOptions, README.md
// "Ease against compression, piece by piece"). Whether any piece changed.
bool balance_ease(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// Last: the output pieces' flattenings converged to final_tolerance (the
// decisions use flattenings stopped at `tolerance`).
void polish_pieces(Pattern& pattern, const PatternOptions& options, const FlattenCache& cache);

// A panel seam on trial: the piece it split (rest faces, sorted) and its
// excess (panel_excess) before the split.
struct PanelTrial {
  std::string seam;
  std::vector<int> rest_faces;
  double excess_before = 0.0;
  double compression_before = 0.0;  // the piece's mean 1 - s2 over its worst 1 % of area
};

// Panel seams on trial, and pieces whose panel seam did not pay (not tried again).
struct PanelLedger {
  std::vector<PanelTrial> trials;
  std::set<std::vector<int>> refused;
};

// The cloth beyond the limit (m^2): sum of area * (max(0, c - c_lim) / c_lim
// + max(0, e - e_lim) / e_lim), c = 1 - s2, e = s1 - 1, limits
// compression_worst1 and ease_worst5 (symmetric: max_limit); on rest faces,
// so a piece and its two halves compare.
double panel_excess(const std::vector<MaterialFace>& faces, const PatternOptions& options);

// Phase 5: one dart (Sawhney and Crane 2017) or panel seam in every piece
// over the limit that `ledger` did not refuse; returns the cuts added.
int place_darts_and_panels(Pattern& pattern, const PatternOptions& options, PanelLedger* ledger = nullptr);

// Phase 5b: a panel seam on trial that did not pay (PanelOptions) is removed
// with its mirror image and its piece refused; returns how many.
int review_panels(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, PanelLedger& ledger);

// Phase 6: removes added cuts bordering a piece under min_piece_area, each
// with its mirror image (pieces stay disks; armholes stay).
void merge_small_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// Phase 6b: removes the dart whose crossed sides overlap its piece when that
// leaves fewer overlapping pieces (of several, the least panel_excess).
void remove_overlapping_darts(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// Phase 6c: a piece whose outline still overlaps itself is split along the
// grain through the crossing, at most max_overlap_splits rounds; returns how
// many seams were added.
int split_overlapping_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// All phases.
Pattern make_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                     const PatternOptions& options, const PatternContext& context = {});

}  // namespace gp
