#pragma once
// From a rest shape and the user's seams to the pieces of a sewing pattern a
// tailor would sew, in phases (each a function below):
//   1. user seams: the seam spec's edge paths smoothed into curves through
//      the rest shape's triangles and cut (surface_curve.h, curve_insertion.h);
//   2. cut to disks: every piece with several boundary loops (or none) is
//      opened along the shortest path between two of its loops, measured in a
//      metric that makes the body's front and back dear and its sides and
//      underarms cheap (a tailor's side seam), smoothed like a user seam;
//   3. flatten: every piece (flatten.h) with a one-sided target, the flat
//      piece as large as the rest shape or up to `ease` larger;
//   4. match seams: pieces whose seam sides differ beyond the tolerance are
//      flattened again with a stronger boundary-length term;
//   5. darts and panels: a piece over the limit gets a dart, a straight wedge
//      in its flattening from its nearest edge to a tip placed at the
//      concentration of Gaussian curvature (or of the log conformal factor,
//      as cone points are placed in boundary-first flattening, Sawhney and
//      Crane 2017), at most `max_darts` per piece; a piece still over the
//      limit with its darts is split by a panel seam along or across the
//      grain through the concentration of its compression;
//   6. merge: an added cut that leaves a piece smaller than `min_piece_area`
//      is removed again.
// Phases 3-5 repeat until every piece meets the limit or nothing more can be
// placed. Every decision is taken on smooth quantities (kernel-weighted
// curvature, mode of a smooth density, chart positions) with ties broken by
// ids, so that a small change of the rest shape moves cuts a little and
// changes no count.
#include <map>
#include <set>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "pattern/flatten.h"
#include "pattern/pattern.h"
#include "pattern/seam_spec.h"
#include "pattern/surface_curve.h"

namespace gp {

struct PatternOptions {
  // The limit, one-sided: a flat piece smaller than its rest triangle (s2 < 1)
  // must be stretched when sewn, so compression 1 - s2 is bounded tightly; a
  // larger one (s1 > 1) is ease, bounded loosely so that the garment keeps
  // its shape. Fractions; means over the worst part of the area (flatten.h:
  // continuous, unlike percentiles, so that a small change of the shape does
  // not flip the verdict). No bound applies to single triangles: a dart's
  // tip, where its wedge closes, always has a few triangles far off, and they
  // do not change how the garment fits.
  double compression_worst1 = 0.03;  // mean 1 - s2 over the worst 1 % of the area
  double ease_worst5 = 0.10;         // mean s1 - 1 over the worst 5 % of the area
  // The symmetric limit instead (max(|s1-1|, |s2-1|), as before ease was
  // allowed): p95 and max.
  bool symmetric = false;
  double p95_limit = 0.02;
  double max_limit = 0.05;

  enum class DartPlacement {
    curvature,  // mode of the kernel-smoothed angle defect (integrated Gaussian curvature)
    conformal,  // minimum of the log conformal factor u (L u = -K, u = 0 on the boundary)
  };
  DartPlacement dart_placement = DartPlacement::curvature;
  int max_darts = 2;                // per piece
  double kernel_radius = 0.06;      // metres: radius of the curvature / density kernel
  double min_dart_angle = 0.25;     // radians of Gaussian curvature within the kernel below which no dart is placed
  double tip_margin = 0.05;         // metres: a dart's tip lies at least this far inside its piece
  double min_dart_length = 0.05;    // metres
  int max_pieces = 12;              // panel seams stop at this many pieces
  // A panel seam stays only where it relieves at least this much of its
  // piece's cloth beyond the limit (panel_excess) per metre of its length:
  // seam length weighed against distortion, as variational surface cutting
  // weighs them (Sharp and Crane 2018). A seam that only moves the excess
  // from one piece to the other, or leaves a cone point where it was,
  // costs seam length for nothing.
  double min_panel_relief = 0.01;   // m^2 per metre of seam
  // The stretch the sewn garment may take, the fit's delta (it may stretch
  // to 1 + delta; export-rest takes it from the fit's report with --fit).
  // A flat piece's compression eats into it: a piece compressed by c needs
  // stretch 1 / (1 - c) before the motion adds any. So a panel seam that
  // relieves less than min_panel_relief is still kept where it brings both
  // its pieces within the limit and the piece it split was compressed (mean
  // over its worst 1 %) by more than budget_share of this budget: there the
  // little cloth it relieves is what the fit has left. Where the piece was
  // only just over the limit with most of the budget to spare, the seam
  // costs its length for nothing.
  double stretch_budget = 0.10;     // fraction (simulate-adapt's default delta)
  double budget_share = 0.5;        // fraction of stretch_budget

  double min_piece_area = 0.01;     // m^2: added cuts leave no piece smaller than this
  int max_rounds = 16;              // flatten / place rounds

  // Armholes: a boundary loop that ends a limb's tube (a sleeve: a loop whose
  // centroid lies at least limb_offset from the body's vertical axis through
  // the garment's centroid) gets a seam around the tube where it meets the
  // body: the level set of the geodesic distance from the loop at which the
  // level set's length first grows faster than armhole_slope (metres per
  // metre, a slope fitted over +-slope_window), at least min_sleeve_length
  // from the loop (an armhole opening without sleeve grows at once).
  bool armholes = true;
  double min_sleeve_length = 0.04;  // metres
  double armhole_slope = 2.0;
  double slope_window = 0.03;       // metres
  double limb_offset = 0.12;        // metres
  double sliver_area = 1e-4;        // m^2: smaller pieces an armhole cuts off join their neighbour

  // Topology cuts: cost of a unit of length on a surface whose normal faces
  // front or back (|n_z| = 1) relative to one facing sideways or down.
  double front_back_cost = 4.0;

  bool smooth = true;               // cuts through triangles along smooth curves (false: along rest edges)
  EdgePathSmoothing smoothing;

  // Seam tolerance: the two flat sides of a seam may differ by
  // max(seam_tolerance, seam_tolerance_relative * 3D length). Pieces on a
  // seam beyond match_margin times that are flattened again with 4 times the
  // boundary weight, up to max_boundary_weight. At 1.5 the demo's shoulder
  // seams were left at 1.1 times the tolerance (seams_within_tolerance
  // false); at 1 a pattern whose pieces could be matched is within it.
  double seam_tolerance = 0.002;           // metres
  double seam_tolerance_relative = 0.005;  // fraction
  double match_margin = 1.0;
  double max_boundary_weight = 640.0;
  FlattenOptions flatten = default_flatten();

  // The flattening prices ease at a quarter of compression (curvature that
  // no cut relieves becomes ease rather than compression) and holds the
  // pieces' edges at their 3D length with weight 40, which keeps the sides
  // of every seam of the example garments within the seam tolerance without
  // flattening pieces again (a decision that a small change of the shape
  // could flip).
  static FlattenOptions default_flatten() {
    FlattenOptions f;
    f.ease_weight = 0.25;
    f.boundary_weight = 40.0;
    return f;
  }
};

// Whether a piece meets the limit of `options`: no flipped triangle, no
// overlap of its outline, and its material distortion (piece.stats) within
// the limit.
bool meets_limit(const PatternPiece& piece, const PatternOptions& options);

// What the cutter knows of the garment besides its rest shape: names of the
// boundary loops (for reasons), for the piece names the body's frame (+y up,
// +z the body's front, +x its left) is that of the rest shape.
struct PatternContext {
  std::map<int, std::string> boundary_names;  // rest vertex -> loop name
};

// Phase 1: the pattern mesh refined along the user seams (smoothed unless
// options.smooth is false) and cut into pieces.
Pattern cut_user_seams(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                       const PatternOptions& options);

// Phase 1b: armholes (see PatternOptions::armholes).
void cut_armholes(Pattern& pattern, const PatternOptions& options, const PatternContext& context);

// Phase 1c: a piece smaller than options.sliver_area that an armhole cut off
// (where it runs within a hair of a user seam, the two cross back and forth
// and leave slivers between them) joins the neighbour with which it shares
// the most armhole: that stretch of the armhole is not cut (the loop becomes
// an open seam, or several, ending on the user seam). Listed in the notes.
void merge_armhole_slivers(Pattern& pattern, const PatternOptions& options);

// Phase 2: topology cuts until every piece is a disk. Throws GeometryError
// for a piece of genus > 0 (seams must cut its handles).
void cut_to_disks(Pattern& pattern, const PatternOptions& options, const PatternContext& context);

// Flattenings of unchanged pieces are reused across rounds: the key is the
// piece's triangles (pattern-mesh vertex ids) and its slits.
struct FlattenCache {
  std::map<std::vector<int>, FlattenResult> results;
  std::map<std::vector<int>, double> boundary_weight;  // raised where seam sides differ
};

// Phase 3: flattens every piece (or reuses an unchanged one) and sets
// meets_limit; `injective` asks for a flip-free result.
void flatten_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, bool injective);

// Phase 4: whether the pieces on mismatched seams were flattened again.
bool match_seams(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// A panel seam on trial: the piece it split (its rest faces, sorted) and
// that piece's excess over the limit (panel_excess) before the split.
struct PanelTrial {
  std::string seam;
  std::vector<int> rest_faces;
  double excess_before = 0.0;
  double compression_before = 0.0;  // the piece's mean 1 - s2 over its worst 1 % of area
};

// What the cutter has learnt across rounds: panel seams on trial, and the
// pieces (by their rest faces) whose panel seam did not pay and is not tried
// again.
struct PanelLedger {
  std::vector<PanelTrial> trials;
  std::set<std::vector<int>> refused;
};

// The cloth of the rest faces `faces` beyond the limit, as a tailor would
// weigh a panel seam: sum over the faces of area * (max(0, c - c_lim) / c_lim
// + max(0, e - e_lim) / e_lim), c = 1 - s2 the compression, e = s1 - 1 the
// ease, c_lim and e_lim the limit's (compression_worst1, ease_worst5; the
// symmetric limit: max_limit for both). m^2; taken on rest faces, so that a
// piece and the two it is split into compare.
double panel_excess(const std::vector<MaterialFace>& faces, const PatternOptions& options);

// Phase 5: one dart or panel seam in every piece over the limit that can
// take one (no panel seam in a piece `ledger` refused); returns how many
// cuts were added and puts the panel seams on trial in `ledger`.
int place_darts_and_panels(Pattern& pattern, const PatternOptions& options, PanelLedger* ledger = nullptr);

// Phase 5b, after the pieces of the panel seams on trial are flattened: a
// panel seam that relieved less than `min_panel_relief` times its length of
// its piece's excess over the limit, and either left one of its pieces over
// the limit or split a piece compressed by no more than `budget_share` of
// `stretch_budget`, is removed again (listed under
// merged_cuts with a note) and its piece refused further panel seams; one
// that stays has the relief added to its reason. Returns how many were
// removed.
int review_panels(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, PanelLedger& ledger);

// Phase 6: removes added cuts (panel or topology seams whose removal keeps
// every piece a disk) that border a piece smaller than min_piece_area.
// Armholes stay: a short sleeve's halves are small because the user's seams
// halve it.
void merge_small_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// Phase 6b: removes a dart of a piece whose flat outline overlaps itself
// (its sides crossed: the flattening wanted less cloth there, not more)
// when that leaves fewer overlapping pieces; it is listed under merged_cuts
// with a note.
void remove_overlapping_darts(Pattern& pattern, const PatternOptions& options, FlattenCache& cache);

// All phases.
Pattern make_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                     const PatternOptions& options, const PatternContext& context = {});

}  // namespace gp
