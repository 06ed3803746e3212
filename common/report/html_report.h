#pragma once
// The fit report's page (index.html) and its timing script (timing.js).
//
// Every figure taken from a stage's report is written as
//   <span class="figure" data-src="fit/report.json" data-ptr="/key_poses/0/max_stretch"
//         data-format="fixed3">1.100</span>
// (data-src relative to the fit folder, data-ptr a JSON pointer), so that a
// test can check every figure on the page against the reports. A figure that
// no stage wrote reads "not checked" and keeps the pointer it was looked for at.
// Formats: fixed2, fixed3 (plain decimals), percent2 (value x 100, " %"),
// mm2 (value x 1000, " mm"), times3 ("x1.234"), metres2 (" m"), integer,
// yesno ("yes"/"no"), text.
#include <string>
#include <vector>

#include "report/checks.h"
#include "report/fit_run.h"

namespace gp::report {

// What the report folder holds besides the page, as paths relative to it.
struct ReportFiles {
  struct Pose {
    std::string sheet;          // renders/..png: front, side, back with stretch colours
    std::string before_after;   // renders/..png, or empty without a no-adapt run
    std::string sewn_sheet;     // renders/sewn_..png (sewn_sheet.h), or empty where the sewn drape was not measured
    std::string model_id;       // key of the embedded model (models/<id>.glb.js)
    std::string glb;            // models/<id>.glb
  };
  std::vector<Pose> poses;      // one per key pose
  std::string held_sheet;       // renders/held_<kk>_<pose>.png, or empty where the body held nothing
  std::string rest_sheet;       // renders/rest_vs_design.png
  std::string rest_glb, design_glb;
  std::string pattern_svg, pattern_png;
  // Files for the shop floor copied beside the page (files/...), with what
  // each is for: the DXF, the PDFs, the marker's PDF.
  struct Download {
    std::string path, what;
  };
  std::vector<Download> downloads;
  std::string marker_svg;       // files/marker.svg, empty without a marker
  std::vector<std::string> scripts;  // in load order
  std::string front = "0,0,1";       // the body's front direction, where the 3D views start
};

// The page. `title` names the garment.
std::string html_report(const FitRun& run, const ReportFiles& files, const std::vector<Check>& checks,
                        const std::string& title);

// timing.js: window.GP_TIMINGS = [{"stage", "file", "seconds": <timing.json>}, ...] for every stage
// with a timing.json. Timings differ from run to run, so they stay out of index.html.
std::string timing_script(const FitRun& run);

// The number formats above, as the page prints them (exposed for tests).
std::string format_figure(const Json& value, const std::string& format);

}  // namespace gp::report
