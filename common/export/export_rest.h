#pragma once
// The export-rest stage as a library call: read the rest shape (and the
// garment file and seam spec), make the pattern (make_pattern.h), lay it out,
// diagnose the rest shape, check that the garment sewn from the pattern fits
// every key pose of the fit (sewn_fit.h, with the fit's report), and write
// pattern.svg, pattern.dxf, pieces.obj, pieces_flat.ply, the sewn garment's
// drapes, timing.json and report.json ("export-rest-report/1", last).
#include <filesystem>
#include <string>
#include <vector>

#include "garment/garment_file.h"
#include "io/mesh.h"
#include "pattern/dxf_writer.h"
#include "pattern/export_report.h"
#include "pattern/layout.h"
#include "pattern/make_pattern.h"
#include "export/fit_settings.h"
#include "pattern/seam_spec.h"
#include "export/sewn_fit.h"
#include "spec/json_file.h"

namespace gp {

struct ExportRestOptions {
  std::string rest;        // rest-shape mesh (PLY/OBJ, metres)
  std::string garment;     // garment file (garment.json); empty: none
  std::string seams;       // seam spec (seam-spec/1); empty: only topology cuts
  std::string body;        // body for seams on the body (poses.json or mesh); empty: the garment's body source
  // The fit's report (simulate-adapt's report.json): the sewn-fit check runs
  // through its poses and motion with its settings. Empty: no check.
  std::string fit;
  PatternOptions pattern;
  LayoutOptions layout;
  // pattern.dxf's profile and style text; style defaults to the garment's name.
  DxfOptions dxf;
  SeamTolerance tolerance;
  DrapeCriteria drape;     // the sewn drape against the fit's verified drape (sewn_fit.h)
  // The drape bounds judge the sewn garment settled at each key pose alone
  // from the reference drape (sewn_fit.h), not its drape after the whole
  // motion, which a micron of noise on the rest shape moves by centimetres
  // (README.md); false: only the drape after the motion, judged.
  bool drape_settled = true;
  int threads = 1;
  adapt::ProgressCallback progress;  // the sewn-fit simulation's progress (lines prefixed "verification: ")
};

struct ExportRestResult {
  Mesh rest;
  std::string name;            // the garment's name (or the mesh's stem)
  bool have_garment = false;
  GarmentFile garment;
  SeamSpec spec;
  std::vector<SeamPath> seams;
  Pattern pattern;
  Layout layout;
  OrderedJson rest_shape;      // diagnostics of the rest shape against the design (empty object without)
  bool sewn_fit_done = false;    // the sewn garment was simulated (with or without success)
  std::string sewn_fit_error;    // a simulation that failed for good (the check then fails)
  FitSettings fit;               // the fit's settings the check used
  double stretch_budget = 0.0;   // PanelOptions::stretch_budget the cutter used (the fit's delta with --fit)
  // The options the pattern was cut with: the stage's, with the fit's stretch budget, or, where the
  // pattern cut within its limit sewed into a garment that failed the fit and the plain cut's passed,
  // the plain cut's (no limit weighting, no relief share); plain_cut_because then says why.
  PatternOptions cut_options;
  std::string plain_cut_because;
  SewnFitResult sewn_fit;
  // Whether the pattern fails the sewn-fit check (the stage then exits 8).
  bool sewn_fit_failed() const { return sewn_fit_done && (!sewn_fit_error.empty() || !sewn_fit.passed()); }
  OrderedJson timing;          // seconds per phase; "total" (set by the caller) ends timing.json
  std::vector<std::string> warnings;
};

// Runs the stage up to (not including) writing. Throws the library's typed
// errors: UsageError (inconsistent options), InputError, SpecError,
// GeometryError (also: --fit names a fit of another rest shape, whose
// verified drapes are not this rest shape's), NumericalError (also: a flat
// piece still overlaps itself after make_pattern split it; no pattern is
// written with one).
ExportRestResult export_rest(const ExportRestOptions& options);

// The stage's report ("export-rest-report/1"), without timings.
OrderedJson export_rest_report(const ExportRestResult& result, const ExportRestOptions& options);

// Writes every output file into `dir` (an existing folder), report.json last.
void write_export_rest(const ExportRestResult& result, const ExportRestOptions& options,
                       const std::filesystem::path& dir);

}  // namespace gp
