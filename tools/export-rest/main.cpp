// export-rest: cuts the rest shape along the user's seams, adds darts and
// panel seams where the flattening would distort too much, flattens the pieces
// and writes the pattern; with --fit, the sewn garment is simulated through the
// fit's key poses and judged (exit 8). The work is gp::export_rest (export_rest.h).
#include <chrono>

#include "adapt/motion_progress.h"
#include "cli/tool.h"
#include "core/atomic_file.h"
#include "export/export_rest.h"
#include "export/export_rest_cli.h"
#include "pattern/svg_writer.h"

int main(int argc, char** argv) {
  gp::Tool tool("export-rest", "Cut the rest shape into flat sewing-pattern pieces (SVG, DXF, meshes)");
  gp::ExportRestOptions o;
  auto& app = tool.app();
  gp::ExportRestChoices choices;
  gp::add_export_rest_options(app, o, choices);
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    gp::set_thread_count(tool.common().threads);
    const auto start = std::chrono::steady_clock::now();
    o.threads = tool.common().threads;
    gp::apply_choices(choices, o);

    gp::adapt::MotionProgressLine progress(o.fit.empty() ? gp::adapt::MotionRunOptions{}
                                                         : gp::read_fit_settings(o.fit).run);
    const auto run_start = std::chrono::steady_clock::now();
    o.progress = [&](const gp::adapt::MotionProgress& p) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
      tool.log().progress(progress.line(p, elapsed), p.key_done);
      if (p.key_done) {
        tool.log().progress_done();
        tool.log().info(p.message);
      }
    };
    gp::ExportRestResult result = gp::export_rest(o);
    tool.log().progress_done();
    for (const auto& w : result.warnings) tool.log().warning(w);
    result.timing["total"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    gp::write_export_rest(result, o, out.staging_path());
    out.commit();
    const gp::Pattern& p = result.pattern;
    int darts = 0;
    for (const auto& s : p.seams) darts += s.kind == "dart" ? 1 : 0;
    tool.log().info("wrote " + tool.common().out_dir + ": " + std::to_string(p.pieces.size()) + " pieces, " +
                    std::to_string(darts) + " darts, " + std::to_string(p.seams.size()) + " seams; the limit is " +
                    (p.meets_limit ? "met" : "not met"));
    if (result.sewn_fit_failed()) {
      const std::string why = result.sewn_fit_error.empty() ? gp::sewn_fit_failure(result.sewn_fit, p)
                                                            : result.sewn_fit_error;
      tool.log().error(gp::ExitCode::check_failed, "the garment sewn from the pattern fails its fit at " + why);
      return static_cast<int>(gp::ExitCode::check_failed);
    }
    return 0;
  });
}
