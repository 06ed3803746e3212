// fit-report: the fit of one customer as pictures and figures. Reads the
// stage folders that pipelines/fit.mk writes under its OUT folder and writes a
// self-contained report folder that opens from disk (index.html, PNG renders,
// glTF models, the pattern, an interactive 3D view per key pose), then
// timing.json and report.json ("fit-report/1", last). See common/report/README.md.
#include <chrono>
#include <thread>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "report/fit_report.h"
#include "report/fit_run.h"
#include "spec/json_file.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  gp::Tool tool("fit-report", "Pictures, 3D views and figures of a fit, as a folder that opens from disk");
  std::string fit_dir, front = "+z", three_dir, font;
  gp::report::FitReportOptions options;
  auto& app = tool.app();
  app.add_option("fit", fit_dir, "The fit's output folder (make fit's OUT: poses/, garment/, fit/, pattern/, ...)")
      ->required();
  app.add_option("--view-width", options.sheet.view_width, "Largest width of a rendered view; views are as wide as the garment needs [pixels]")
      ->capture_default_str()->check(CLI::Range(64, 4096));
  app.add_option("--view-height", options.sheet.view_height, "Height of every rendered view [pixels]")
      ->capture_default_str()->check(CLI::Range(64, 4096));
  app.add_option("--supersampling", options.sheet.supersampling,
                 "Samples per pixel along each axis, for anti-aliasing (1: none) [count]")
      ->capture_default_str()->check(CLI::Range(1, 8));
  app.add_option("--front", front, "The direction the body faces (+y is up) [axis: +x, -x, +z, -z]")
      ->capture_default_str()->check(CLI::IsMember({"+x", "-x", "+z", "-z"}));
  app.add_option("--pattern-width", options.pattern_width, "Width of pattern.png [pixels]")
      ->capture_default_str()->check(CLI::Range(100, 20000));
  app.add_option("--three-dir", three_dir,
                 "three.js package folder to copy into the report [default: " +
                     gp::report::default_three_dir().string() + ", installed by make deps]");
  app.add_option("--font", font, "TrueType font of the labels [default: DejaVu Sans, Debian's fonts-dejavu-core]");
  int workers = std::thread::hardware_concurrency() >= 2 ? 2 : 1;
  app.add_option("--workers", workers,
                 "Views rendered in parallel; the pictures are the same for any count "
                 "[count, default: 2 where the machine has two cores]")
      ->check(CLI::Range(1, 64));
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    options.sheet.threads = workers;
    options.sheet.front = Eigen::Vector3d(front == "+x" ? 1 : front == "-x" ? -1 : 0, 0,
                                          front == "+z" ? 1 : front == "-z" ? -1 : 0);
    options.three_dir = three_dir;
    options.font = font;
    const gp::report::FitRun run = gp::report::read_fit_run(fit_dir);

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    const gp::report::FitReportResult result = gp::report::write_fit_report(run, options, out.staging_path());

    gp::OrderedJson checks = gp::OrderedJson::array();
    int failed = 0;
    for (const auto& c : result.checks) {
      // The words with their figures are on the page; here what a script
      // branches on, with no figure that could differ in its last digits.
      checks.push_back({{"level", gp::report::check_level_name(c.level)}, {"check", c.id}, {"pose", c.pose}});
      failed += c.level == gp::report::CheckLevel::fail;
    }
    gp::OrderedJson report;
    report["schema"] = gp::schema_tag("fit-report", 1);
    report["input"] = {{"fit", fit_dir}, {"key_poses", run.keys.size()}, {"no_adapt_run", run.fit_no_adapt.has_value()}};
    if (!result.fabric.empty()) report["input"]["fabric"] = result.fabric;
    // The colour scales are fixed (render/colour_scale.h); recorded so that a
    // reader of the pictures knows their ends without the page.
    const auto scale_json = [](const gp::render::ColourScale& scale) {
      return gp::OrderedJson{{"min", scale.min_value()}, {"max", scale.max_value()}, {"log_axis", scale.log_axis()}};
    };
    report["options"] = gp::write_options(options, gp::report::FitReportOptionFields{});
    report["options"]["front"] = front;
    report["options"]["stretch_scale"] = scale_json(gp::render::stretch_scale(run.delta));
    report["options"]["stretch_scale"]["limit"] = 1.0 + run.delta;
    report["options"]["growth_scale"] = scale_json(gp::render::growth_scale());
    report["checks"] = checks;
    report["failed_checks"] = failed;
    report["files"] = result.files;
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::write_json_file(out.file("timing.json"), {{"schema", gp::schema_tag("timing", 1)},
                                                  {"tool", "fit-report"},
                                                  {"load_s", result.load_seconds},
                                                  {"render_s", result.render_seconds},
                                                  {"models_s", result.model_seconds},
                                                  {"pattern_s", result.pattern_seconds},
                                                  {"total_s", total}});
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    tool.log().info("wrote " + (fs::path(tool.common().out_dir) / "index.html").string() + " (" +
                    std::to_string(run.keys.size()) + " key poses, " + std::to_string(failed) + " failed checks)");
    return 0;
  });
}
