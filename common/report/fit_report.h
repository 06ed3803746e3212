#pragma once
// The fit report of one fit folder (fit_run.h): a self-contained folder that
// opens from disk with no server and no network:
//   index.html            the figures of every stage, failed checks first (html_report.h)
//   renders/pose_<kk>_<pose>.png          front, side, back, coloured by stretch
//   renders/before_after_<kk>_<pose>.png  the design and the adapted garment (with fit-noadapt/)
//   renders/rest_vs_design.png            the design and the rest shape coloured by area growth
//   renders/sewn_<kk>_<pose>.png          the sewn drape against its reference, coloured by distance (sewn_sheet.h)
//   models/pose_<kk>_<pose>.glb (+ .glb.js, the same bytes in base64 for the page)
//   models/rest_shape.glb, models/design.glb
//   pattern.svg, pattern.png
//   three/                three.js, its glTF loader and orbit controls, and their licence
//   viewer.js, timing.js
// The caller writes report.json and timing.json.
#include <filesystem>
#include <string>
#include <vector>

#include "report/checks.h"
#include "report/fit_run.h"
#include "report/picture_sheet.h"

namespace gp::report {

struct FitReportOptions {
  SheetOptions sheet;                    // view size, supersampling, front direction, threads
  int pattern_width = 1600;              // width of pattern.png [pixels]
  std::filesystem::path three_dir;       // three.js package folder (build/, examples/js/); empty: as `make deps` installs it
  std::filesystem::path font;            // TrueType font for labels; empty: DejaVu Sans
};

// The options that decide the pictures, as a report records them.
struct FitReportOptionFields {
  template <class Fields>
  void operator()(FitReportOptions& o, Fields& f) const {
    f.group("sheet", o.sheet, SheetOptionFields{});
    f.integer("pattern_width_px", o.pattern_width, Range::between(100, 20000));
  }
};

// The folder `make deps` installs three.js into (compiled in).
std::filesystem::path default_three_dir();

struct FitReportResult {
  std::vector<Check> checks;
  std::vector<std::string> files;        // every file written, relative to the folder, sorted
  double load_seconds = 0.0;             // reading meshes and reports
  double render_seconds = 0.0;           // all pictures
  double model_seconds = 0.0;            // glTF files
  double pattern_seconds = 0.0;          // pattern.png
  std::string fabric;                    // the garment's fabric (common/fabric), empty when its report names none
};

// Writes the report into `folder` (which must exist; normally a staging
// folder). Throws InputError for a missing file (three.js, the font,
// rsvg-convert, a mesh), GeometryError for meshes that do not match.
FitReportResult write_fit_report(const FitRun& run, const FitReportOptions& options,
                                 const std::filesystem::path& folder);

}  // namespace gp::report
