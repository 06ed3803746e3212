// export-rest: cuts the garment's rest shape along the user's seams (seam
// spec, tool T6) and where the flattening would distort too much, flattens
// the pieces and writes sewing patterns: pattern.svg (1:1, mm), pattern.dxf
// (R12, mm), pieces.obj (3D + flat texture coordinates), pieces_flat.ply
// (2D pieces), timing.json and report.json ("export-rest-report/1", last).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"
#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "pattern/auto_cut.h"
#include "pattern/dxf_writer.h"
#include "pattern/export_report.h"
#include "pattern/layout.h"
#include "pattern/rest_diagnostics.h"
#include "pattern/round_trip.h"
#include "pose/pose_set.h"
#include "pattern/seam_spec.h"
#include "pattern/svg_writer.h"
#include "spec/json_file.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  gp::Tool tool("export-rest", "Cut the rest shape into flat sewing-pattern pieces (SVG, DXF, meshes)");
  std::string mesh_path, garment_path, seams_path, body_path;
  gp::PatternOptions pattern_options;
  gp::LayoutOptions layout_options;
  gp::SeamTolerance tolerance;
  auto& app = tool.app();
  app.add_option("rest", mesh_path, "Rest-shape mesh (PLY/OBJ, metres)")->required();
  app.add_option("--garment", garment_path, "Garment file (garment.json, schema garment/1): name, boundary names, body binding");
  app.add_option("--seams", seams_path, "Seam spec (JSON, schema seam-spec/1); none: only automatic cuts");
  app.add_option("--body", body_path, "Body for seams given on the body (poses.json or mesh) [default: the garment file's body source]");
  app.add_option("--p95-limit", pattern_options.p95_limit, "Principal-stretch error allowed on 95 % of the area [fraction]")
      ->capture_default_str()->check(CLI::Range(1e-6, 1.0));
  app.add_option("--max-limit", pattern_options.max_limit, "Principal-stretch error allowed everywhere [fraction]")
      ->capture_default_str()->check(CLI::Range(1e-6, 1.0));
  app.add_option("--max-cuts", pattern_options.max_added_cuts, "Most extra cuts added for distortion [count]")
      ->capture_default_str()->check(CLI::Range(0, 100000));
  double cone_angle_degrees = 0.0;
  app.add_option("--cone-angle", cone_angle_degrees,
                 "Cut through inner vertices whose angle defect reaches this, in pieces over the limit; 0: never [degrees]")
      ->capture_default_str()->check(CLI::Range(0.0, 360.0));
  std::string round_trip_poses;
  gp::RoundTripOptions round_trip_options;
  app.add_option("--round-trip", round_trip_poses,
                 "Pose set (poses.json) with the garment's design pose: drape the rest shape and the sewn flat pieces "
                 "on it and compare (needs --garment); none: no round trip");
  app.add_option("--round-trip-dt", round_trip_options.dt, "Time step of the round-trip drapes [s]")
      ->capture_default_str()->check(CLI::Range(1e-5, 0.1));
  app.add_option("--round-trip-settle-speed", round_trip_options.settle_speed,
                 "Largest vertex speed of a settled round-trip drape [m/s]")
      ->capture_default_str()->check(CLI::Range(1e-6, 10.0));
  app.add_option("--round-trip-steps", round_trip_options.settle_max_steps, "Most settling steps per round-trip drape [count]")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
  app.add_option("--merge-area", pattern_options.merge_area,
                 "Pieces smaller than this are merged back across added cuts where the merged piece meets the limit; "
                 "0: never [m^2]")
      ->capture_default_str()->check(CLI::Range(0.0, 100.0));
  app.add_option("--arap-iterations", pattern_options.flatten.max_iterations, "Most ARAP iterations per piece [count]")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
  app.add_option("--boundary-weight", pattern_options.flatten.boundary_weight,
                 "Weight of keeping seam edges at their 3D length, relative to ARAP [dimensionless]")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--seam-allowance", layout_options.seam_allowance, "Seam allowance around every piece [m]")
      ->capture_default_str()->check(CLI::Range(0.0, 0.2));
  app.add_option("--notch-spacing", layout_options.notch_spacing, "Distance between notches along a seam [m]")
      ->capture_default_str()->check(CLI::Range(0.01, 10.0));
  app.add_option("--sheet-width", layout_options.sheet_width, "Width of the sheet the pieces are laid out on [m]")
      ->capture_default_str()->check(CLI::Range(0.1, 100.0));
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    gp::set_thread_count(tool.common().threads);
    const auto start = Clock::now();
    gp::OrderedJson timing;
    auto lap = [&, last = start](const char* phase) mutable {
      const auto now = Clock::now();
      timing[phase] = std::chrono::duration<double>(now - last).count();
      last = now;
    };
    if (!round_trip_poses.empty() && garment_path.empty())
      throw gp::UsageError("--round-trip needs the garment file (--garment): pins, material, design pose", "--round-trip");
    if (pattern_options.p95_limit > pattern_options.max_limit)
      throw gp::UsageError("--p95-limit must not exceed --max-limit", "--p95-limit");

    gp::MeshReadResult read = gp::read_mesh(mesh_path);
    for (const auto& w : read.warnings) tool.log().warning(w);
    const gp::Mesh& rest = read.mesh;
    if (rest.F.rows() == 0) throw gp::GeometryError("the rest shape has no triangles", mesh_path);
    if (!rest.V.allFinite()) throw gp::GeometryError("the rest shape has non-finite vertex coordinates", mesh_path);

    gp::GarmentFile garment;
    bool have_garment = !garment_path.empty();
    std::string name = fs::path(mesh_path).stem().string();
    std::map<int, std::string> boundary_names;
    if (have_garment) {
      garment = gp::read_garment_file(garment_path);
      name = garment.name;
      if (garment.vertex_count != rest.V.rows() || garment.face_count != rest.F.rows())
        throw gp::GeometryError("the rest shape has " + std::to_string(rest.V.rows()) + " vertices and " +
                                    std::to_string(rest.F.rows()) + " triangles, the garment file " +
                                    std::to_string(garment.vertex_count) + " and " +
                                    std::to_string(garment.face_count),
                                mesh_path);
      for (const auto& loop : garment.loops)
        for (int v : loop.vertex_ids) boundary_names.emplace(v, loop.name);
    }
    std::vector<gp::SeamPath> seams;
    gp::SeamSpec spec;
    if (!seams_path.empty()) {
      spec = gp::read_seam_spec(seams_path);
      bool on_body = false, on_design = false;
      for (const auto& s : spec.seams) {
        on_body = on_body || s.on == gp::SeamSurface::body;
        on_design = on_design || s.on == gp::SeamSurface::design;
      }
      gp::DesignBody body;
      if (on_body) {
        if (!have_garment)
          throw gp::UsageError("seams on the body need the garment file (--garment) for its binding", seams_path);
        body = gp::load_design_body(garment, garment_path, body_path);
      }
      // The garment as designed (beside its garment file) lies at the comfort
      // offset from the body; the adapted rest shape may not.
      const bool need_design = on_body || on_design;
      gp::Mesh design;
      if (need_design) {
        if (!have_garment)
          throw gp::UsageError("seams on the garment as designed need the garment file (--garment)", seams_path);
        const fs::path design_path = fs::path(garment_path).parent_path() / garment.mesh_file;
        design = gp::read_mesh(design_path).mesh;
        if (design.F.rows() != rest.F.rows() || design.V.rows() != rest.V.rows() || design.F != rest.F)
          throw gp::GeometryError("the rest shape does not have the designed garment's connectivity", design_path.string());
      }
      seams = gp::resolve_seams(rest.V, rest.F, spec, have_garment ? &garment : nullptr, on_body ? &body : nullptr,
                                need_design ? &design.V : nullptr);
    }
    lap("read");

    pattern_options.cone_angle = cone_angle_degrees * M_PI / 180.0;
    pattern_options.seam_tolerance = tolerance.absolute;
    pattern_options.seam_tolerance_relative = tolerance.relative;
    const gp::Pattern pattern = gp::make_pattern(rest.V, rest.F, seams, pattern_options, boundary_names);
    lap("cut_and_flatten");
    const gp::Layout layout = gp::layout_pattern(pattern, layout_options);
    lap("layout");
    if (!pattern.meets_limit) {
      std::string why;
      if (pattern.cut_cap_reached)
        why = "the cap of " + std::to_string(pattern_options.max_added_cuts) + " extra cuts (--max-cuts) was reached";
      for (const std::string& piece : pattern.stuck_pieces)
        why += (why.empty() ? "no cut rule places a new cut in piece " : ", piece ") + piece;
      tool.log().warning("the distortion limit is not met: " + (why.empty() ? std::string("see report.json") : why) +
                         " (report.json lists the pieces)");
    }

    // Figures of the rest shape against the garment as designed (beside its
    // garment file): growth, tucks and cone points explain a pattern that
    // cannot meet the limit (rest_diagnostics.h).
    gp::OrderedJson diagnostics;
    gp::Mesh design;
    bool have_design = false;
    if (have_garment) {
      const fs::path design_path = fs::path(garment_path).parent_path() / garment.mesh_file;
      if (fs::exists(design_path)) {
        design = gp::read_mesh(design_path).mesh;
        have_design = design.V.rows() == rest.V.rows() && design.F == rest.F;
        if (have_design) {
          // A cone point with defect 2 pi * max_limit cannot be flattened within the limit unless its
          // neighbourhood takes that error in full (see rest_diagnostics.h).
          const double cone = 2.0 * M_PI * pattern_options.max_limit;
          const gp::RestShapeDiagnostics d = gp::diagnose_rest_shape(design.V, rest.V, rest.F, cone);
          diagnostics = {{"design_mesh", design_path.string()},
                         {"area_growth", d.area_growth},
                         {"face_growth_p95", d.growth_p95},
                         {"face_growth_max", d.growth_max},
                         {"turned_faces", d.turned_faces},
                         {"turned_area_fraction", d.turned_area_fraction},
                         {"cone_angle_deg", d.cone_angle * 180.0 / M_PI},
                         {"cone_points", d.cone_points},
                         {"cone_points_design", d.cone_points_design},
                         {"max_abs_angle_defect_deg", d.max_abs_defect * 180.0 / M_PI},
                         {"abs_angle_defect_sum_rad", d.abs_defect_sum},
                         {"abs_angle_defect_sum_design_rad", d.abs_defect_sum_design}};
          if (!pattern.meets_limit && d.cone_points > d.cone_points_design)
            tool.log().warning("the rest shape has " + std::to_string(d.cone_points) + " cone points (the design " +
                               std::to_string(d.cone_points_design) + ") and " + std::to_string(d.turned_faces) +
                               " faces turned over in tucks; they cannot be flattened within the limit without a "
                               "cut through each (see rest_shape in report.json)");
        }
      }
    }

    gp::RoundTripResult trip;
    std::string round_trip_failure;
    if (!round_trip_poses.empty()) {
      const gp::PoseSet poses = gp::load_pose_set(round_trip_poses);
      // A failed drape is a finding about the pattern, not a failed export:
      // it is reported and the pattern still written.
      try {
        trip = gp::round_trip(poses, garment, rest.V, rest.F, pattern, layout, round_trip_options,
                              have_design ? &design.V : nullptr);
      } catch (const gp::NumericalError& e) {
        round_trip_failure = e.what();
        tool.log().warning(round_trip_failure);
      }
      lap("round_trip");
    }

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    if (!round_trip_poses.empty() && round_trip_failure.empty()) {
      gp::Mesh drape;
      drape.F = rest.F;
      drape.V = trip.V_rest_drape;
      gp::write_mesh(out.file("round_trip_rest_drape.ply"), drape);
      drape.V = trip.V_sewn_drape;
      gp::write_mesh(out.file("round_trip_sewn_drape.ply"), drape);
    }
    gp::write_file_atomic(out.file("pattern.svg"), [&](std::ostream& s) { gp::write_svg(s, pattern, layout, {name}); }, false);
    gp::write_file_atomic(out.file("pattern.dxf"), [&](std::ostream& s) { gp::write_dxf(s, pattern, layout, name); }, false);
    gp::write_file_atomic(out.file("pieces.obj"), [&](std::ostream& s) { gp::write_pieces_obj(s, pattern, layout); }, false);
    gp::write_mesh(out.file("pieces_flat.ply"), gp::flat_pieces_mesh(pattern, layout));
    lap("write");

    gp::OrderedJson report;
    report["schema"] = gp::schema_tag("export-rest-report", 1);
    report["input"] = {{"rest", mesh_path},
                       {"rest_sha256", gp::sha256_file_hex(mesh_path)},
                       {"garment", garment_path},
                       {"seams", seams_path},
                       {"vertices", rest.V.rows()},
                       {"faces", rest.F.rows()}};
    report["options"] = {{"p95_limit", pattern_options.p95_limit},
                         {"max_limit", pattern_options.max_limit},
                         {"max_cuts", pattern_options.max_added_cuts},
                         {"tip_weight", pattern_options.tip_weight},
                         {"cone_angle_deg", cone_angle_degrees},
                         {"merge_area", pattern_options.merge_area},
                         {"arap_iterations", pattern_options.flatten.max_iterations},
                         {"arap_tolerance", pattern_options.flatten.tolerance},
                         {"line_search_margin", pattern_options.flatten.line_search_margin},
                         {"boundary_weight", pattern_options.flatten.boundary_weight},
                         {"max_boundary_weight", pattern_options.max_boundary_weight},
                         {"seam_allowance", layout_options.seam_allowance},
                         {"notch_spacing", layout_options.notch_spacing},
                         {"notch_length", layout_options.notch_length},
                         {"sheet_width", layout_options.sheet_width},
                         {"gap", layout_options.gap},
                         {"margin", layout_options.margin},
                         {"seam_mismatch_tolerance", {{"absolute", tolerance.absolute}, {"relative", tolerance.relative}}},
                         {"threads", tool.common().threads},
                         {"seam_spec", seams_path.empty() ? gp::OrderedJson() : gp::to_json(spec)}};
    auto stretch_json = [](const gp::StretchFigures& f) {
      return gp::OrderedJson{{"max_s1", f.max_s1}, {"p95_s1", f.p95_s1}, {"mean_s1", f.mean_s1}, {"min_s2", f.min_s2}};
    };
    auto run_json = [](const gp::DrapeRun& r) {
      return gp::OrderedJson{{"settle_steps", r.settle_steps}, {"settled", r.settled}};
    };
    if (round_trip_poses.empty())
      report["round_trip"] = {{"checked", false}, {"why", "not requested (--round-trip POSES_JSON)"}};
    else if (!round_trip_failure.empty())
      report["round_trip"] = {{"checked", false},
                              {"poses", round_trip_poses},
                              {"dt_s", round_trip_options.dt},
                              {"why", round_trip_failure}};
    else
      report["round_trip"] = {{"checked", true},
                              {"poses", round_trip_poses},
                              {"pose", trip.pose},
                              {"start", have_design ? "designed garment" : "rest shape"},
                              {"dt_s", round_trip_options.dt},
                              {"settle_max_steps", round_trip_options.settle_max_steps},
                              {"settle_speed_m_per_s", round_trip_options.settle_speed},
                              {"distance_mm",
                               {{"max", 1000.0 * trip.max_distance},
                                {"mean", 1000.0 * trip.mean_distance},
                                {"p95", 1000.0 * trip.p95_distance}}},
                              {"sewn_stretch_against_flat_pieces", stretch_json(trip.sewn_drape_stretch)},
                              {"rest_drape_stretch_against_rest_shape", stretch_json(trip.rest_drape_stretch)},
                              {"rest_drape", run_json(trip.rest_run)},
                              {"sewn_drape", run_json(trip.sewn_run)},
                              {"meshes", {"round_trip_rest_drape.ply", "round_trip_sewn_drape.ply"}}};
    report["rest_shape"] = diagnostics.is_null() ? gp::OrderedJson::object() : diagnostics;
    const gp::OrderedJson body = gp::pattern_report(pattern, layout, pattern_options, tolerance);
    for (auto it = body.begin(); it != body.end(); ++it) report[it.key()] = it.value();
    if (!round_trip_poses.empty() && round_trip_failure.empty()) {
      timing["round_trip_rest_drape"] = trip.rest_run.seconds;
      timing["round_trip_sewn_drape"] = trip.sewn_run.seconds;
    }
    timing["total"] = std::chrono::duration<double>(Clock::now() - start).count();
    gp::write_json_file(out.file("timing.json"), {{"schema", gp::schema_tag("timing", 1)}, {"seconds", timing}});
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    const auto& sum = report["summary"];
    tool.log().info("wrote " + tool.common().out_dir + ": " + std::to_string(pattern.pieces.size()) + " pieces, " +
                    std::to_string(pattern.seams.size()) + " seams, worst p95 " +
                    gp::format_fixed(100.0 * sum["worst_p95_error"].get<double>(), 2) + " %, max " +
                    gp::format_fixed(100.0 * sum["worst_max_error"].get<double>(), 2) + " %");
    return 0;
  });
}
