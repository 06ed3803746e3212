#include "export/export_rest_cli.h"

#include "core/error.h"
#include "pattern/dxf_writer.h"

namespace gp {

void add_export_rest_options(CLI::App& app, ExportRestOptions& o, ExportRestChoices& c) {
  PatternOptions& po = o.pattern;
  app.add_option("rest", o.rest, "Rest-shape mesh (PLY/OBJ, metres)")->required();
  app.add_option("--garment", o.garment, "Garment file (garment.json, schema garment/1): name, boundary names, body binding");
  app.add_option("--seams", o.seams, "Seam spec (JSON, schema seam-spec/1); none: only the cuts that open pieces into disks");
  app.add_option("--body", o.body, "Body for seams given on the body (poses.json or mesh) [default: the garment file's body source]");
  app.add_option("--limit", c.limit,
                 "Distortion limit: one-sided (bounds compression tightly, ease loosely) or symmetric (bounds both alike)")
      ->capture_default_str()->check(CLI::IsMember({"one-sided", "symmetric"}));
  app.add_option("--compression-limit", po.limit.compression_worst1,
                 "One-sided limit: mean compression 1 - s2 allowed over the worst 1 % of a piece's area [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--ease-limit", po.limit.ease_worst5,
                 "One-sided limit: mean ease s1 - 1 allowed over the worst 5 % of a piece's area [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_option("--p95-limit", po.limit.p95_limit, "Symmetric limit: error max(|s1-1|, |s2-1|) allowed on 95 % of the area [fraction]")
      ->capture_default_str()->check(CLI::Range(1e-6, 1.0));
  app.add_option("--max-limit", po.limit.max_limit, "Symmetric limit: error allowed everywhere [fraction]")
      ->capture_default_str()->check(CLI::Range(1e-6, 1.0));
  app.add_option("--ease-weight", po.flatten.ease_weight,
                 "Cost of ease relative to compression in the flattening (1 is ARAP) [fraction]")
      ->capture_default_str()->check(CLI::Range(1e-3, 1.0));
  app.add_option("--limit-rounds", po.flatten.limit_rounds, "Rounds in which a piece's triangles beyond 80 % of the limit "
                 "(or of the compression budget, --weighting-budget-share) weigh more in its flattening (0: off) [count]")->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--limit-patience", po.flatten.limit_patience,
                 "The limit weighting stops after this many rounds without a better one [count]")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  app.add_option("--dart-placement", c.placement,
                 "Dart tips at the concentration of Gaussian curvature (curvature) or of the log conformal factor (conformal)")
      ->capture_default_str()->check(CLI::IsMember({"curvature", "conformal"}));
  app.add_option("--max-darts", po.darts.max_darts, "Darts per piece [count]")->capture_default_str()->check(CLI::Range(0, 100));
  app.add_option("--max-pieces", po.panels.max_pieces, "Panel seams stop at this many pieces [count]")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--max-sleeve-pieces", po.panels.max_sleeve_pieces,
                 "A sleeve's pieces get no panel seam once it has this many, only darts (0: no bound) [count]")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--min-relief-share", po.panels.min_relief_share,
                 "... or relieves at least this share of its piece's cloth beyond the limit (0: off) [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--min-panel-relief", po.panels.min_panel_relief,
                 "A panel seam stays only where it relieves this much cloth beyond the limit per metre of its length [m^2/m]")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
  app.add_option("--kernel-radius", po.darts.kernel_radius, "Radius of the curvature and energy kernels [m]")
      ->capture_default_str()->check(CLI::Range(0.005, 1.0));
  app.add_option("--min-dart-angle", po.darts.min_dart_angle, "Least Gaussian curvature around a dart's tip [radians]")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_option("--max-rounds", po.panels.max_rounds, "Rounds of flattening and placing darts and panels [count]")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  app.add_option("--max-overlap-splits", po.panels.max_overlap_splits,
                 "Rounds of splitting a piece whose outline overlaps itself through the crossing; one still "
                 "overlapping fails the stage [count]")->capture_default_str()->check(CLI::Range(0, 100));
  app.add_option("--ease-balance-steps", po.panels.ease_balance_steps, "A piece over one bound of the one-sided limit and "
                 "within the other is flattened again with ease up to this many times cheaper or dearer (0: off) [count]")
      ->capture_default_str()->check(CLI::Range(0, 100));
  app.add_option("--ease-balance-factor", po.panels.ease_balance_factor, "... each time by this factor [ratio]")
      ->capture_default_str()->check(CLI::Range(1.0, 100.0));
  app.add_option("--min-piece-area", po.panels.min_piece_area, "Added cuts leave no piece smaller than this [m^2]")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
  app.add_option("--tip-margin", po.darts.tip_margin, "A dart's tip lies at least this far inside its piece [m]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_flag("--no-tip-inward", c.no_tip_inward,
               "A dart's curvature mode within the tip margin of the outline is skipped, not pointed at from inside");
  app.add_flag("--no-mirror", c.no_mirror,
               "Cut each piece on its own (default: a piece's mirror image across the body gets the mirror image of its darts and panel seams)");
  app.add_option("--mirror-overlap", po.panels.mirror_overlap,
                 "Two pieces are mirror images where their mirrored areas share this much of each [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_flag("--no-armholes", c.no_armholes, "No seam around a sleeve where it meets the body");
  app.add_flag("--edge-cuts", c.edge_cuts, "Cut along the rest shape's edges instead of smooth curves through its triangles");
  app.add_option("--smoothing-wavelength", po.seams.smoothing.wavelength, "Seam wiggles shorter than this are smoothed away [m]")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_option("--smoothing-tolerance", po.seams.smoothing.tolerance,
                 "A cut may leave its edge path freely by this fraction of the path's mean edge length (0: the wavelength alone) [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 2.0));
  app.add_option("--arap-iterations", po.flatten.max_iterations, "Most flattening iterations per piece [count]")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
  app.add_option("--flatten-tolerance", po.flatten.tolerance,
                 "Flattening stops when its energy falls by less than this fraction in an iteration [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--final-tolerance", po.flatten.final_tolerance,
                 "The output pieces' flattenings are iterated on until their energy falls by less than this fraction "
                 "in an iteration, so that the printed pieces do not depend on the last bits of the rest shape "
                 "[fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--snap-fraction", po.seams.smoothing.trace.snap_fraction,
                 "A cut crossing an edge closer than this fraction of its length to an end runs through that end [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 0.5));
  app.add_option("--min-edge-fraction", po.seams.smoothing.trace.min_edge_fraction,
                 "Cut curves cross an edge at least this fraction of its length from its ends [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 0.5));
  app.add_option("--seam-tolerance", po.seams.seam_tolerance, "A seam's two flat sides may differ by this much [m]")
      ->capture_default_str()->check(CLI::Range(0.0, 0.1));
  app.add_option("--seam-tolerance-relative", po.seams.seam_tolerance_relative,
                 "... or by this fraction of its 3D length, where that is more [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 0.1));
  app.add_option("--match-margin", po.seams.match_margin,
                 "Pieces on a seam whose sides differ by more than this times the seam tolerance are flattened again [fraction]")
      ->capture_default_str()->check(CLI::Range(0.1, 100.0));
  app.add_option("--budget-share", po.panels.budget_share,
                 "A panel seam relieving less than --min-panel-relief stays, where both its pieces then meet the limit, only if "
                 "its piece was compressed by more than this share of the stretch budget (the fit's delta with --fit, else 0.10) [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
  app.add_option("--weighting-budget-share", po.panels.weighting_budget_share,
                 "The limit weighting compresses no triangle beyond this share of the stretch budget (the fit's delta with "
                 "--fit, else 0.10), or beyond its compression without the weighting where that was more [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--max-boundary-weight", po.seams.max_boundary_weight,
                 "Pieces on a seam whose sides differ beyond the tolerance are flattened again with up to this boundary weight [dimensionless]")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--boundary-weight", po.flatten.boundary_weight,
                 "Weight of keeping seam edges at their 3D length, relative to the distortion energy [dimensionless]")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--fit", o.fit,
                 "The fit's report (simulate-adapt's report.json): the garment sewn from the flat pieces is simulated "
                 "through the fit's key poses with its settings and judged like its verification; a failing pose "
                 "exits 8 (needs --garment); none: no sewn-fit check");
  app.add_option("--drape-mean-limit", o.drape.max_mean,
                 "Sewn-fit check: a key pose fails when the sewn drape lies farther than this from the fit's "
                 "verified drape (else the rest shape's own) on average (0: not bounded; the goal is 0.005) [m]")->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_option("--drape-p95-limit", o.drape.max_p95,
                 "Sewn-fit check: ... or farther than this on 5 % of the area (0: not bounded; the goal is 0.015) [m]")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_flag_callback("--drape-after-motion", [&o] { o.drape_settled = false; }, "Sewn-fit check: the drape limits judge the "
                        "sewn drape after the whole motion [default: the sewn garment settled at each key pose alone from the reference drape]");
  app.add_option("--seam-allowance", o.layout.seam_allowance, "Seam allowance around every piece [m]")
      ->capture_default_str()->check(CLI::Range(0.0, 0.2));
  app.add_option("--notch-spacing", o.layout.notch_spacing, "Distance between notches along a seam [m]")
      ->capture_default_str()->check(CLI::Range(0.01, 10.0));
  app.add_option("--sheet-width", o.layout.sheet_width, "Width of the sheet the pieces are laid out on [m]")
      ->capture_default_str()->check(CLI::Range(0.1, 100.0));
  app.add_option("--dxf-profile", c.dxf_profile,
                 "pattern.dxf for pattern CAD (astm: ASTM D6673; aama: AAMA-DXF, slit notches) or general CAD (plain)")
      ->capture_default_str()->check(CLI::IsMember({"astm", "aama", "plain"}));
  app.add_option("--size", o.dxf.size, "The DXF's Size and Sample Size: the customer [default: the garment's name]");
  app.add_option("--author", o.dxf.author, "The DXF's Author")->capture_default_str();
  app.add_option("--creation-date", o.dxf.date,
                 "The DXF's Creation Date, YYYY-MM-DD [default: SOURCE_DATE_EPOCH's, else the rest mesh's modification date, UTC]");
}

void apply_choices(const ExportRestChoices& c, ExportRestOptions& o) {
  PatternOptions& po = o.pattern;
  po.limit.symmetric = c.limit == "symmetric";
  po.darts.dart_placement =
      c.placement == "conformal" ? PatternOptions::DartPlacement::conformal : PatternOptions::DartPlacement::curvature;
  po.seams.smooth = !c.edge_cuts;
  po.armholes.enabled = !c.no_armholes;
  po.panels.mirror = !c.no_mirror;
  po.darts.tip_inward = !c.no_tip_inward;
  o.dxf.profile = dxf_profile_from_name(c.dxf_profile);
  if (o.dxf.date.empty()) o.dxf.date = default_creation_date(o.rest);
  if (po.limit.p95_limit > po.limit.max_limit) throw UsageError("--p95-limit must not exceed --max-limit", "--p95-limit");
  o.tolerance.absolute = po.seams.seam_tolerance;
  o.tolerance.relative = po.seams.seam_tolerance_relative;
}

}  // namespace gp
