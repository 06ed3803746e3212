#include "pattern/export_rest.h"

#include <chrono>
#include <cmath>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"
#include "io/mesh_io.h"
#include "pattern/dxf_writer.h"
#include "pattern/rest_diagnostics.h"
#include "pattern/svg_writer.h"
#include "pose/pose_set.h"

namespace gp {
namespace fs = std::filesystem;

ExportRestResult export_rest(const ExportRestOptions& options) {
  using Clock = std::chrono::steady_clock;
  ExportRestResult result;
  auto last = Clock::now();
  auto lap = [&](const char* phase) {
    const auto now = Clock::now();
    result.timing[phase] = std::chrono::duration<double>(now - last).count();
    last = now;
  };
  if (!options.round_trip.empty() && options.garment.empty())
    throw UsageError("--round-trip needs the garment file (--garment): pins, material, design pose", "--round-trip");

  MeshReadResult read = read_mesh(options.rest);
  result.warnings = read.warnings;
  result.rest = read.mesh;
  const Mesh& rest = result.rest;
  if (rest.F.rows() == 0) throw GeometryError("the rest shape has no triangles", options.rest);
  if (!rest.V.allFinite()) throw GeometryError("the rest shape has non-finite vertex coordinates", options.rest);

  result.have_garment = !options.garment.empty();
  result.name = fs::path(options.rest).stem().string();
  PatternContext context;
  if (result.have_garment) {
    result.garment = read_garment_file(options.garment);
    result.name = result.garment.name;
    if (result.garment.vertex_count != rest.V.rows() || result.garment.face_count != rest.F.rows())
      throw GeometryError("the rest shape has " + std::to_string(rest.V.rows()) + " vertices and " +
                              std::to_string(rest.F.rows()) + " triangles, the garment file " +
                              std::to_string(result.garment.vertex_count) + " and " +
                              std::to_string(result.garment.face_count),
                          options.rest);
    for (const auto& loop : result.garment.loops)
      for (int v : loop.vertex_ids) context.boundary_names.emplace(v, loop.name);
  }
  // The garment as designed (beside its garment file) lies at the comfort
  // offset from the body; the adapted rest shape may not.
  Mesh design;
  bool have_design = false;
  if (result.have_garment) {
    const fs::path design_path = fs::path(options.garment).parent_path() / result.garment.mesh_file;
    if (fs::exists(design_path)) {
      design = read_mesh(design_path).mesh;
      have_design = design.V.rows() == rest.V.rows() && design.F == rest.F;
    }
  }
  if (!options.seams.empty()) {
    result.spec = read_seam_spec(options.seams);
    bool on_body = false, on_design = false;
    for (const auto& s : result.spec.seams) {
      on_body = on_body || s.on == SeamSurface::body;
      on_design = on_design || s.on == SeamSurface::design;
    }
    DesignBody body;
    if (on_body) {
      if (!result.have_garment)
        throw UsageError("seams on the body need the garment file (--garment) for its binding", options.seams);
      body = load_design_body(result.garment, options.garment, options.body);
    }
    const bool need_design = on_body || on_design;
    if (need_design) {
      if (!result.have_garment)
        throw UsageError("seams on the garment as designed need the garment file (--garment)", options.seams);
      if (!have_design)
        throw GeometryError("the rest shape does not have the designed garment's connectivity",
                            (fs::path(options.garment).parent_path() / result.garment.mesh_file).string());
    }
    result.seams = resolve_seams(rest.V, rest.F, result.spec, result.have_garment ? &result.garment : nullptr,
                                 on_body ? &body : nullptr, need_design ? &design.V : nullptr);
  }
  lap("read");

  result.pattern = make_pattern(rest.V, rest.F, result.seams, options.pattern, context);
  lap("cut_and_flatten");
  for (const auto& [phase, s] : result.pattern.seconds) result.timing["cut_and_flatten_" + phase] = s;
  LayoutOptions layout = options.layout;
  layout.title = result.name;
  result.layout = layout_pattern(result.pattern, layout);
  lap("layout");
  if (!result.pattern.meets_limit) {
    std::string failing;
    for (const PatternPiece& p : result.pattern.pieces)
      if (!p.meets_limit) failing += (failing.empty() ? "" : ", ") + p.name;
    result.warnings.push_back("the distortion limit is not met in " + failing + " (report.json lists the pieces)");
  }

  // Figures of the rest shape against the garment as designed: growth, tucks
  // and cone points explain a pattern that cannot meet the limit.
  result.rest_shape = OrderedJson::object();
  if (have_design) {
    // A cone point whose defect is 2 pi * the limit cannot be flattened
    // within it unless its neighbourhood takes that error in full.
    const double limit = options.pattern.symmetric ? options.pattern.max_limit : options.pattern.compression_worst1;
    const double cone = 2.0 * M_PI * limit;
    const RestShapeDiagnostics d = diagnose_rest_shape(design.V, rest.V, rest.F, cone);
    result.rest_shape = {{"design_mesh", (fs::path(options.garment).parent_path() / result.garment.mesh_file).string()},
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
    if (!result.pattern.meets_limit && d.cone_points > d.cone_points_design)
      result.warnings.push_back("the rest shape has " + std::to_string(d.cone_points) + " cone points (the design " +
                                std::to_string(d.cone_points_design) + ") and " + std::to_string(d.turned_faces) +
                                " faces turned over in tucks (see rest_shape in report.json)");
  }

  if (!options.round_trip.empty()) {
    const PoseSet poses = load_pose_set(options.round_trip);
    // A failed drape is a finding about the pattern, not a failed export:
    // it is reported and the pattern still written.
    try {
      result.round_trip = gp::round_trip(poses, result.garment, rest.V, rest.F, result.pattern, result.layout,
                                         options.round_trip_options, have_design ? &design.V : nullptr);
      result.round_trip_done = true;
    } catch (const NumericalError& e) {
      result.round_trip_failure = e.what();
      result.warnings.push_back(result.round_trip_failure);
    }
    lap("round_trip");
  }
  return result;
}

OrderedJson export_rest_report(const ExportRestResult& result, const ExportRestOptions& options) {
  const PatternOptions& po = options.pattern;
  const LayoutOptions& lo = options.layout;
  OrderedJson report;
  report["schema"] = schema_tag("export-rest-report", 1);
  report["input"] = {{"rest", options.rest},
                     {"rest_sha256", sha256_file_hex(options.rest)},
                     {"garment", options.garment},
                     {"seams", options.seams},
                     {"vertices", result.rest.V.rows()},
                     {"faces", result.rest.F.rows()}};
  OrderedJson limit;
  if (po.symmetric)
    limit = {{"kind", "symmetric"}, {"p95_error", po.p95_limit}, {"max_error", po.max_limit}};
  else
    limit = {{"kind", "one-sided"},
             {"compression_worst1", po.compression_worst1},
             {"ease_worst5", po.ease_worst5}};
  report["options"] = {
      {"limit", limit},
      {"dart_placement", po.dart_placement == PatternOptions::DartPlacement::conformal ? "conformal" : "curvature"},
      {"max_darts", po.max_darts},
      {"kernel_radius", po.kernel_radius},
      {"min_dart_angle_deg", po.min_dart_angle * 180.0 / M_PI},
      {"tip_margin", po.tip_margin},
      {"min_dart_length", po.min_dart_length},
      {"max_pieces", po.max_pieces},

      {"min_piece_area", po.min_piece_area},
      {"max_rounds", po.max_rounds},
      {"front_back_cost", po.front_back_cost},
      {"smooth", po.smooth},
      {"smoothing_wavelength", po.smoothing.wavelength},
      {"smoothing_band_rings", po.smoothing.band_rings},
      {"snap_fraction", po.smoothing.trace.snap_fraction},
      {"flatten_ease_weight", po.flatten.ease_weight},
      {"flatten_iterations", po.flatten.max_iterations},
      {"flatten_tolerance", po.flatten.tolerance},
      {"line_search_margin", po.flatten.line_search_margin},
      {"boundary_weight", po.flatten.boundary_weight},
      {"max_boundary_weight", po.max_boundary_weight},
      {"seam_allowance", lo.seam_allowance},
      {"notch_spacing", lo.notch_spacing},
      {"notch_length", lo.notch_length},
      {"sheet_width", lo.sheet_width},
      {"gap", lo.gap},
      {"margin", lo.margin},
      {"seam_mismatch_tolerance", {{"absolute", options.tolerance.absolute}, {"relative", options.tolerance.relative}}},
      {"threads", options.threads},
      {"seam_spec", options.seams.empty() ? OrderedJson() : to_json(result.spec)}};
  auto stretch_json = [](const StretchFigures& f) {
    return OrderedJson{{"max_s1", f.max_s1}, {"p95_s1", f.p95_s1}, {"mean_s1", f.mean_s1}, {"min_s2", f.min_s2}};
  };
  auto run_json = [](const DrapeRun& r) { return OrderedJson{{"settle_steps", r.settle_steps}, {"settled", r.settled}}; };
  const RoundTripOptions& ro = options.round_trip_options;
  if (options.round_trip.empty())
    report["round_trip"] = {{"checked", false}, {"why", "not requested (--round-trip POSES_JSON)"}};
  else if (!result.round_trip_done)
    report["round_trip"] = {
        {"checked", false}, {"poses", options.round_trip}, {"dt_s", ro.dt}, {"why", result.round_trip_failure}};
  else {
    const RoundTripResult& trip = result.round_trip;
    report["round_trip"] = {{"checked", true},
                            {"poses", options.round_trip},
                            {"pose", trip.pose},
                            {"start", result.rest_shape.empty() ? "rest shape" : "designed garment"},
                            {"dt_s", ro.dt},
                            {"settle_max_steps", ro.settle_max_steps},
                            {"settle_speed_m_per_s", ro.settle_speed},
                            {"distance_mm",
                             {{"max", 1000.0 * trip.max_distance},
                              {"mean", 1000.0 * trip.mean_distance},
                              {"p95", 1000.0 * trip.p95_distance}}},
                            {"sewn_stretch_against_flat_pieces", stretch_json(trip.sewn_drape_stretch)},
                            {"rest_drape_stretch_against_rest_shape", stretch_json(trip.rest_drape_stretch)},
                            {"rest_drape", run_json(trip.rest_run)},
                            {"sewn_drape", run_json(trip.sewn_run)},
                            {"meshes", {"round_trip_rest_drape.ply", "round_trip_sewn_drape.ply"}}};
  }
  report["rest_shape"] = result.rest_shape;
  const OrderedJson body = pattern_report(result.pattern, result.layout, po, options.tolerance);
  for (auto it = body.begin(); it != body.end(); ++it) report[it.key()] = it.value();
  return report;
}

void write_export_rest(const ExportRestResult& result, const ExportRestOptions& options, const fs::path& dir) {
  if (result.round_trip_done) {
    Mesh drape;
    drape.F = result.rest.F;
    drape.V = result.round_trip.V_rest_drape;
    write_mesh(dir / "round_trip_rest_drape.ply", drape);
    drape.V = result.round_trip.V_sewn_drape;
    write_mesh(dir / "round_trip_sewn_drape.ply", drape);
  }
  const Pattern& pattern = result.pattern;
  const Layout& layout = result.layout;
  write_file_atomic(dir / "pattern.svg", [&](std::ostream& s) { write_svg(s, pattern, layout, {result.name}); }, false);
  write_file_atomic(dir / "pattern.dxf", [&](std::ostream& s) { write_dxf(s, pattern, layout, result.name); }, false);
  write_file_atomic(dir / "pieces.obj", [&](std::ostream& s) { write_pieces_obj(s, pattern, layout); }, false);
  write_file_atomic(dir / "seams.obj", [&](std::ostream& s) { write_seams_obj(s, pattern); }, false);
  write_mesh(dir / "pieces_flat.ply", flat_pieces_mesh(pattern, layout));
  OrderedJson timing = result.timing;
  if (result.round_trip_done) {
    timing["round_trip_rest_drape"] = result.round_trip.rest_run.seconds;
    timing["round_trip_sewn_drape"] = result.round_trip.sewn_run.seconds;
  }
  write_json_file(dir / "timing.json", {{"schema", schema_tag("timing", 1)}, {"seconds", timing}});
  write_json_file(dir / "report.json", export_rest_report(result, options));
}

}  // namespace gp
