#pragma once
// The export-rest stage as a library call: read the rest shape (and the
// garment file and seam spec), make the pattern (make_pattern.h), lay it out,
// diagnose the rest shape, optionally drape the sewn pattern (round_trip.h),
// and write pattern.svg, pattern.dxf, pieces.obj, pieces_flat.ply,
// timing.json and report.json ("export-rest-report/1", last).
#include <filesystem>
#include <string>
#include <vector>

#include "garment/garment_file.h"
#include "io/mesh.h"
#include "pattern/export_report.h"
#include "pattern/layout.h"
#include "pattern/make_pattern.h"
#include "pattern/round_trip.h"
#include "pattern/seam_spec.h"
#include "spec/json_file.h"

namespace gp {

struct ExportRestOptions {
  std::string rest;        // rest-shape mesh (PLY/OBJ, metres)
  std::string garment;     // garment file (garment.json); empty: none
  std::string seams;       // seam spec (seam-spec/1); empty: only topology cuts
  std::string body;        // body for seams on the body (poses.json or mesh); empty: the garment's body source
  std::string round_trip;  // pose set with the design pose; empty: no round trip
  PatternOptions pattern;
  LayoutOptions layout;
  SeamTolerance tolerance;
  RoundTripOptions round_trip_options;
  int threads = 1;
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
  bool round_trip_done = false;
  std::string round_trip_failure;  // why the round trip could not be checked
  RoundTripResult round_trip;
  OrderedJson timing;          // seconds per phase
  std::vector<std::string> warnings;
};

// Runs the stage up to (not including) writing. Throws the library's typed
// errors: UsageError (inconsistent options), InputError, SpecError,
// GeometryError, NumericalError.
ExportRestResult export_rest(const ExportRestOptions& options);

// The stage's report ("export-rest-report/1"), without timings.
OrderedJson export_rest_report(const ExportRestResult& result, const ExportRestOptions& options);

// Writes every output file into `dir` (an existing folder), report.json last.
void write_export_rest(const ExportRestResult& result, const ExportRestOptions& options,
                       const std::filesystem::path& dir);

}  // namespace gp
