// make-marker: nests a pattern's pieces on a fabric width (the marker a
// cutting room lays its fabric by) and writes marker.svg, marker.pdf,
// timing.json and report.json ("make-marker-report/1": length,
// utilisation, every piece's placement). Input: an export-rest folder (its
// marker_pieces.json) or any marker-pieces/1 file. The work is
// gp::nest_marker (common/marker/nest_marker.h).
#include <chrono>
#include <filesystem>
#include <stdexcept>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/text_format.h"
#include "marker/marker_pieces.h"
#include "marker/marker_writers.h"
#include "marker/nest_marker.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  gp::Tool tool("make-marker", "Nest the pattern's pieces on a fabric width: marker SVG and PDF, length, utilisation");
  std::string input;
  gp::NestOptions o;
  bool width_given = false;
  auto& app = tool.app();
  app.add_option("pieces", input, "An export-rest output folder (its marker_pieces.json) or a marker-pieces/1 file")->required();
  app.add_option_function<double>(
         "--width", [&](double w) { o.width = w, width_given = true; },
         "Fabric width, in the pieces' units (metres for a pattern) [default: the file's fabric_width, else 1.5]")
      ->check(CLI::Range(1e-6, 1e6));
  app.add_option("--resolution", o.resolution, "Raster cell, in the pieces' units [default: width / 300]")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--seed", o.seed, "Seed of the search over the pieces' order")->capture_default_str();
  app.add_option("--time-budget", o.budget_s,
                 "Work budget of the search, in seconds of the build machine (counted as work, not by the clock, so "
                 "that a seed and a budget give the same marker anywhere) [s]")
      ->capture_default_str()->check(CLI::Range(0.0, 3600.0));
  std::string title;
  app.add_option("--title", title, "Name on the drawings [default: the input's folder or file name]");
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    fs::path file = input;
    if (fs::is_directory(file)) file /= "marker_pieces.json";
    const gp::MarkerPieces pieces = gp::read_marker_pieces(file);
    if (!width_given) o.width = pieces.fabric_width > 0.0 ? pieces.fabric_width : 1.5;
    if (title.empty()) title = fs::is_directory(input) ? fs::path(input).lexically_normal().parent_path().filename().string()
                                                      : file.stem().string();
    if (title.empty()) title = "marker";
    const gp::MarkerResult marker = gp::nest_marker(pieces, o);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    const fs::path dir = out.staging_path();
    gp::write_file_atomic(dir / "marker.svg", [&](std::ostream& s) { gp::write_marker_svg(s, pieces, marker, title); }, false);
    gp::write_file_atomic(dir / "marker.pdf", [&](std::ostream& s) { gp::write_marker_pdf(s, pieces, marker, title); });
    gp::OrderedJson timing;
    timing["schema"] = gp::schema_tag("timing", 1);
    timing["tool"] = "make-marker";
    timing["total_s"] = seconds;
    gp::write_json_file(dir / "timing.json", timing);
    const gp::OrderedJson report = gp::marker_report(pieces, marker, o);
    gp::write_json_file(dir / "report.json", report);
    out.commit();
    tool.log().info("wrote " + tool.common().out_dir + ": " + std::to_string(marker.placements.size()) + " pieces, " +
                    gp::format_fixed(marker.length, 3) + " " + pieces.units + " long on " + gp::format_fixed(o.width, 3) +
                    ", utilisation " + gp::format_fixed(100.0 * marker.utilisation, 1) + " %");
    if (report["overlapping_pairs"].get<int>() != 0 || !report["inside_width"].get<bool>())
      throw std::logic_error("the marker's own check found overlapping pieces or a piece outside the width (report.json)");
    return 0;
  });
}
