#pragma once
// The cutter's options (make_pattern.h) in groups by concern: the distortion
// limit, darts, panel seams (and the other added cuts), armholes, seams (and
// the topology cuts' cost) and the flattening, with their defaults and units,
// and the list the reports record them by (flat, as before the grouping).
#include "pattern/flatten.h"
#include "pattern/surface_curve.h"

namespace gp {

// The distortion limit a piece must meet.
struct DistortionLimit {
  // The one-sided limit: compression 1 - s2 (stretched when sewn) tightly,
  // ease s1 - 1 loosely; fractions, as means over the worst part of the area
  // (continuous, unlike percentiles). None per triangle: a dart's tip always
  // has a few far off.
  double compression_worst1 = 0.03;  // mean 1 - s2 over the worst 1 % of the area
  double ease_worst5 = 0.10;         // mean s1 - 1 over the worst 5 % of the area
  bool symmetric = false;           // max(|s1-1|, |s2-1|) instead: p95 and max
  double p95_limit = 0.02;
  double max_limit = 0.05;
};

// Where darts go and how many.
struct DartOptions {
  enum class Placement {
    curvature,  // mode of the kernel-smoothed angle defect (integrated Gaussian curvature)
    conformal,  // minimum of the log conformal factor u (L u = -K, u = 0 on the boundary)
  };
  Placement dart_placement = Placement::curvature;
  int max_darts = 2;                // per piece
  double kernel_radius = 0.06;      // metres: radius of the curvature / density kernel
  double min_dart_angle = 0.25;     // radians of Gaussian curvature within the kernel below which no dart is placed
  double tip_margin = 0.05;         // metres: a dart's tip lies at least this far inside its piece
  bool tip_inward = true;           // a curvature mode nearer the outline gets its tip moved inward to tip_margin
  double min_dart_length = 0.05;    // metres
};

// The cuts the cutter adds where a piece fails the limit: panel seams, both
// sides alike, and the rounds and splits that bound them.
struct PanelOptions {
  // Panel seams stop at this many pieces: the paper's 5-pose shirt has 10
  // (it was 12, which the slim-shirt filled with sleeve quarters and a
  // front split twice; issue 49).
  int max_pieces = 10;
  // A tailor cuts a sleeve in one piece or two (front and back, or upper
  // and under sleeve), with darts or ease where it needs them: a piece most
  // of whose area lies beyond an armhole (a limb, cut_armholes) gets no panel
  // seam once its limb has this many pieces, only darts (issue 49: the
  // slim-shirt's sleeve fronts were split into upper and lower parts, three
  // and four pieces a sleeve). 0: no bound.
  int max_sleeve_pieces = 2;
  // Both sides of the body cut alike (piece_mirror.h): a piece's mirror
  // image gets the mirror image of its darts and panel seam, two such panel
  // seams stay or go together, and a piece that is its own mirror image (a
  // whole back) gets a centre seam. Pieces pair where their mirror images
  // share at least mirror_overlap of their area. A mirrored dart needs the
  // curvature a piece's own dart needs (min_dart_angle): a scanned body's
  // two sides differ, and a dart where the cloth has little to take in has
  // sides that cross.
  bool mirror = true;
  double mirror_overlap = 0.6;      // fraction of a piece's area
  // A panel seam stays where it relieves this much of its piece's excess
  // (panel_excess) per metre: seam length weighed against distortion, as in
  // variational surface cutting (Sharp and Crane 2018).
  double min_panel_relief = 0.01;   // m^2 per metre of seam
  // ... or where it relieves at least this share of the cloth beyond the
  // limit of the piece it split: the cutter stops adding pieces only when
  // the limit is met, and a seam that takes a piece most of the way there
  // is worth its length. With the limit weighting (FlattenOptions::
  // limit_rounds) it takes the demo within the limit in 8 pieces and the
  // opened dress in 10 (BENCHMARKS.md, issue 49); export-rest cuts plain
  // (0, no weighting) where that pattern's sewn garment fails the fit.
  double min_relief_share = 0.5;    // fraction; 0: off
  // The fit's delta (export-rest --fit). A piece compressed by c needs
  // stretch 1 / (1 - c) before the motion adds any, so a seam below the
  // relief still stays when both its pieces meet the limit and the split
  // piece's compression exceeded budget_share of this budget.
  double stretch_budget = 0.10;     // fraction (simulate-adapt's default delta)
  double budget_share = 0.5;        // fraction of stretch_budget
  // The limit weighting (FlattenOptions::compression_budget) compresses no
  // triangle beyond this share of the budget (or its plain compression,
  // where that was more). Without it the test cap's sewn garment (delta
  // 0.04) failed its second pose (4.77 % of the area above 1.04); at half
  // it passes both (0.35 %) but fails an in-between frame (1.02 %), at 0.35
  // and below the cutter drops the cap's panel seams (pattern README, "The
  // limit weighting").
  double weighting_budget_share = 0.5;  // fraction of stretch_budget

  // A piece over one bound of the one-sided limit and within the other is
  // flattened again with its own ease weight (balance_ease, make_pattern.h):
  // the default weight divided (over compression) or multiplied (over ease)
  // by ease_balance_factor up to ease_balance_steps times, never below
  // min_ease_weight nor above 1 (ARAP). 0 steps: off, the default: on the
  // three customers' fits it brought no piece within the limit that was not
  // (their pieces over one bound are held there by the seam-length term),
  // and it moved the demo's darts (pattern README, "Ease against
  // compression, piece by piece").
  int ease_balance_steps = 0;
  double ease_balance_factor = 1.5;
  double min_ease_weight = 0.02;

  double min_piece_area = 0.01;     // m^2: added cuts leave no piece smaller than this
  int max_rounds = 16;              // flatten / place rounds
  int max_overlap_splits = 4;       // rounds of split_overlapping_pieces
};

// Armholes: a loop ending a limb's tube (centroid at least limb_offset from
// the body's vertical axis) gets a seam at the geodesic level set whose
// length first grows faster than armhole_slope (m/m, fitted over
// +-slope_window), at least min_sleeve_length from the loop. Two limbs
// mirrored across the axis (their distances from it, heights and armhole
// distances equal within mirror_tolerance) share the mean armhole distance.
struct ArmholeOptions {
  bool enabled = true;
  double min_sleeve_length = 0.04;  // metres
  double armhole_slope = 2.0;
  double slope_window = 0.03;       // metres
  double limb_offset = 0.12;        // metres
  double mirror_tolerance = 0.25;   // fraction
  double sliver_area = 1e-4;        // m^2: smaller pieces an armhole cuts off join their neighbour
};

// How seams run and how closely their two flat sides must match.
struct SeamOptions {
  double front_back_cost = 4.0;     // topology cuts: cost of length facing front or back against sideways

  bool smooth = true;               // cuts through triangles along smooth curves (false: along rest edges)
  EdgePathSmoothing smoothing;

  // A seam's flat sides may differ by max(seam_tolerance,
  // seam_tolerance_relative * 3D length); pieces beyond match_margin times
  // that are flattened again with 4 times the boundary weight, up to
  // max_boundary_weight. 1 mm whatever the length: the two edges sewn
  // together must match within 1 mm (kSeamMatch, export_report.h); it was
  // max(2 mm, 0.5 %), which let the slim-shirt's 0.86 m side seam differ
  // by 3.6 mm.
  double seam_tolerance = 0.001;         // metres
  double seam_tolerance_relative = 0.0;  // fraction
  double match_margin = 1.0;
  double max_boundary_weight = 640.0;
};

// The cutter's options, one group per concern; the report records them
// flat, under the names of PatternOptionFields.
struct PatternOptions {
  using DartPlacement = DartOptions::Placement;
  DistortionLimit limit;
  DartOptions darts;
  PanelOptions panels;
  ArmholeOptions armholes;
  SeamOptions seams;
  FlattenOptions flatten = default_flatten();

  // Ease priced at a tenth of compression (curvature no cut relieves
  // becomes ease, and compression eats the sewn garment's stretch budget:
  // pattern README, "Flatten"); edges held at their 3D length with weight
  // 40, which keeps the example garments' seams within tolerance without a
  // second pass. The limit weighting (limit_weights, flatten.h) brings the
  // demo and the opened dress within the limit (with the relief share 0.5);
  // its compression budget (PanelOptions::weighting_budget_share) bounds
  // what it takes from the sewn garment's stretch, and where the garment
  // still fails the fit (the test cap's in-between frame, pattern README,
  // "The limit weighting") export-rest keeps the plain cut. Patience 6: the
  // opened dress's right sleeve front gains ease more than 3 rounds apart.
  static FlattenOptions default_flatten() {
    FlattenOptions f;
    f.ease_weight = 0.1;
    f.boundary_weight = 40.0;
    f.limit_rounds = 20;
    f.limit_patience = 6;
    return f;
  }
};

// The options as a report records them (spec/option_fields.h).
struct PatternOptionFields {
  template <class Fields>
  void operator()(PatternOptions& o, Fields& f) const {
    f.names("limit", o.limit.symmetric, "symmetric", "one-sided");
    f.number("compression_worst1", o.limit.compression_worst1, Range::between(0.0, 1.0));
    f.number("ease_worst5", o.limit.ease_worst5, Range::non_negative());
    f.number("p95_limit", o.limit.p95_limit, Range::non_negative());
    f.number("max_limit", o.limit.max_limit, Range::non_negative());
    f.choice("dart_placement", o.darts.dart_placement,
             ChoiceNames<DartOptions::Placement>{{DartOptions::Placement::curvature, "curvature"},
                                                 {DartOptions::Placement::conformal, "conformal"}});
    f.integer("max_darts", o.darts.max_darts, Range::between(0, 100));
    f.number("kernel_radius_m", o.darts.kernel_radius, Range::positive());
    f.number("min_dart_angle_rad", o.darts.min_dart_angle, Range::non_negative());
    f.number("tip_margin_m", o.darts.tip_margin, Range::non_negative());
    f.flag("tip_inward", o.darts.tip_inward);
    f.number("min_dart_length_m", o.darts.min_dart_length, Range::non_negative());
    f.integer("max_pieces", o.panels.max_pieces, Range::between(0, 1e6));
    f.integer("max_sleeve_pieces", o.panels.max_sleeve_pieces, Range::between(0, 1e6));
    f.flag("mirror", o.panels.mirror);
    f.number("mirror_overlap", o.panels.mirror_overlap, Range::between(0.0, 1.0));
    f.number("min_panel_relief_m2_per_m", o.panels.min_panel_relief, Range::non_negative());
    f.number("min_relief_share", o.panels.min_relief_share, Range::non_negative());
    f.number("stretch_budget", o.panels.stretch_budget, Range::non_negative());
    f.number("budget_share", o.panels.budget_share, Range::non_negative());
    f.number("weighting_budget_share", o.panels.weighting_budget_share, Range::non_negative());
    f.integer("ease_balance_steps", o.panels.ease_balance_steps, Range::between(0, 100));
    f.number("ease_balance_factor", o.panels.ease_balance_factor, Range::between(1.0, 100.0));
    f.number("min_ease_weight", o.panels.min_ease_weight, Range::between(0.0, 1.0));
    f.number("min_piece_area_m2", o.panels.min_piece_area, Range::non_negative());
    f.integer("max_rounds", o.panels.max_rounds, Range::between(1, 1e6));
    f.integer("max_overlap_splits", o.panels.max_overlap_splits, Range::between(0, 100));
    f.flag("armholes", o.armholes.enabled);
    f.number("min_sleeve_length_m", o.armholes.min_sleeve_length, Range::non_negative());
    f.number("armhole_slope", o.armholes.armhole_slope, Range::positive());
    f.number("slope_window_m", o.armholes.slope_window, Range::positive());
    f.number("limb_offset_m", o.armholes.limb_offset, Range::non_negative());
    f.number("mirror_tolerance", o.armholes.mirror_tolerance, Range::non_negative());
    f.number("sliver_area_m2", o.armholes.sliver_area, Range::non_negative());
    f.number("front_back_cost", o.seams.front_back_cost, Range::positive());
    f.flag("smooth", o.seams.smooth);
    f.group("smoothing", o.seams.smoothing, EdgePathSmoothingFields{});
    f.number("seam_tolerance_m", o.seams.seam_tolerance, Range::non_negative());
    f.number("seam_tolerance_relative", o.seams.seam_tolerance_relative, Range::non_negative());
    f.number("match_margin", o.seams.match_margin, Range::non_negative());
    f.number("max_boundary_weight", o.seams.max_boundary_weight, Range::non_negative());
    f.group("flatten", o.flatten, FlattenOptionFields{});
  }
};

}  // namespace gp
