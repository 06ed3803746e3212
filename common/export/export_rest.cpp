#include "export/export_rest.h"

#include <cmath>
#include <cstdio>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"
#include "adapt/simulate_report.h"
#include "core/stopwatch.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "io/mesh_io.h"
#include "pattern/dxf_writer.h"
#include "marker/marker_pieces.h"
#include "pattern/pdf_writer.h"
#include "pattern/rest_diagnostics.h"
#include "pattern/svg_writer.h"
#include "pose/pose_set.h"
#include "spec/option_fields.h"

namespace gp {
namespace {
// m: a cone point this far from every seam and boundary lies inside a piece.
constexpr double kConeInsideMargin = 0.01;
}  // namespace
namespace fs = std::filesystem;
namespace {

// The title on the pattern's labels: the garment's name, and the fabric when
// the spec chose one (the paper's default stays unnamed, as before).
std::string pattern_title(const ExportRestResult& result) {
  if (result.have_garment && result.garment.material.fabric != "paper") {
    return result.name + ", " + result.garment.material.fabric;
  }
  return result.name;
}

// The sewn garment's drape at key pose k ("sewn_02_armsup.ply"), the rest shape's own drape
// where export-rest simulated it as the reference ("rest_02_armsup.ply", the fit having no
// verified drapes), and the sewn garment settled at key pose k alone from the reference drape
// ("settled_02_armsup.ply"; not with --drape-after-motion): simulate-adapt's naming.
std::string sewn_drape_name(const adapt::KeyPoseResult& k) { return adapt::drape_file_name("sewn", k); }
std::string rest_drape_name(const adapt::KeyPoseResult& k) { return adapt::drape_file_name("rest", k); }
std::string settled_drape_name(const adapt::KeyPoseResult& k) { return adapt::drape_file_name("settled", k); }

OrderedJson vector_json(const Eigen::Vector3d& x) { return OrderedJson::array({x.x(), x.y(), x.z()}); }

// The sewn drapes against the verified ones, over all key poses, and how
// much of the flattening's ease is extra cloth in the drape: the pattern's
// cloth exceeds the rest shape's by sewn / rest area - 1; the drape's by
// sewn / verified drape area - 1 (cloth that hangs, not stretched flat, is
// the difference). Their ratio is the share of the ease the drape shows.
OrderedJson drape_summary(const SewnFitResult& sewn) {
  const double ease = sewn.rest_area > 0.0 ? sewn.sewn_rest_area / sewn.rest_area - 1.0 : 0.0;
  OrderedJson j = {{"criteria", write_options(sewn.drape_criteria, DrapeCriteriaFields{})},
                   {"measured", !sewn.drape.empty()},
                   {"why_not", sewn.drape.empty() ? OrderedJson(sewn.drape_not_measured) : OrderedJson(nullptr)},
                   {"verdict", sewn.drape.empty() ? "not measured" : sewn.drape_passed() ? "pass" : "fail"},
                   {"judged", sewn.drape.empty()     ? OrderedJson(nullptr)
                              : sewn.settled.empty() ? "the drape after the whole motion"
                                                     : "the sewn garment settled at each key pose alone from the reference drape"},
                   {"reference", sewn.drape.empty()               ? OrderedJson(nullptr)
                                 : sewn.reference_is_rest_shape ? "the rest shape simulated by export-rest"
                                                                : "the fit's verified drapes"},
                   {"rest_area_m2", sewn.rest_area},
                   {"sewn_rest_area_m2", sewn.sewn_rest_area},
                   {"pattern_ease", ease}};
  if (sewn.drape.empty()) return j;
  double mean = 0.0, p95 = 0.0, max = 0.0, area_ratio = 0.0;
  for (const DrapeDistance& d : sewn.drape) {
    mean = std::max(mean, d.mean);
    p95 = std::max(p95, d.p95);
    max = std::max(max, d.max);
    area_ratio += d.verified_area > 0.0 ? d.sewn_area / d.verified_area : 0.0;
  }
  area_ratio /= static_cast<double>(sewn.drape.size());
  if (!sewn.settled.empty()) {
    double s_mean = 0.0, s_p95 = 0.0, s_max = 0.0;
    for (const DrapeDistance& d : sewn.settled) {
      s_mean = std::max(s_mean, d.mean);
      s_p95 = std::max(s_p95, d.p95);
      s_max = std::max(s_max, d.max);
    }
    j["settled_worst_mean_m"] = s_mean;
    j["settled_worst_p95_m"] = s_p95;
    j["settled_max_m"] = s_max;
  }
  j["worst_mean_m"] = mean;
  j["worst_p95_m"] = p95;
  j["max_m"] = max;
  j["mean_drape_area_ratio"] = area_ratio;
  j["ease_in_drape"] = area_ratio - 1.0;
  j["ease_share_in_drape"] = ease != 0.0 ? OrderedJson((area_ratio - 1.0) / ease) : OrderedJson(nullptr);
  return j;
}

// The sewn garment's in-between frames, each transition as the fit's verification reports its own
// (adapt::to_json); the sewn frames' drapes are not written.
OrderedJson transitions_json(const adapt::FitVerification& v) {
  OrderedJson list = OrderedJson::array();
  for (const adapt::TransitionCheck& t : v.transitions) list.push_back(adapt::to_json(t, ""));
  return list;
}

OrderedJson sewn_fit_report(const ExportRestResult& result, const ExportRestOptions& options) {
  if (!result.sewn_fit_done)
    return {{"checked", false}, {"why", "no fit report given (--fit FIT/report.json)"}};
  const SewnFitResult& sewn = result.sewn_fit;
  const adapt::FitCriteria& c = result.fit.criteria;
  auto piece_name = [&result](int p) {
    return p >= 0 ? OrderedJson(result.pattern.pieces[static_cast<size_t>(p)].name) : OrderedJson(nullptr);
  };
  const std::vector<int> vertex_piece = piece_of_rest_vertex(result.pattern);
  OrderedJson poses = OrderedJson::array();
  for (size_t i = 0; i < sewn.verification.poses.size(); ++i) {
    const adapt::PoseCheck& check = sewn.verification.poses[i];
    const adapt::KeyPoseResult& k = check.figures;
    const SewnPoseWhere& w = sewn.where[i];
    OrderedJson pieces = OrderedJson::array();
    for (const PieceStretch& p : w.pieces)
      pieces.push_back({{"piece", piece_name(p.piece)},
                        {"area_fraction_above_limit", p.area_fraction_above},
                        {"max_stretch", p.max_stretch}});
    OrderedJson where = {{"pieces_above_limit", pieces},
                         {"worst_face", {{"rest_face", w.worst_face},
                                         {"piece", piece_name(w.worst_face_piece)},
                                         {"position_m", vector_json(w.worst_face_position)}}}};
    if (w.deepest_vertex >= 0)
      where["deepest_vertex_inside"] = {{"vertex", w.deepest_vertex},
                                        {"piece", piece_name(w.deepest_vertex_piece)},
                                        {"position_m", vector_json(w.deepest_vertex_position)}};
    else
      where["deepest_vertex_inside"] = nullptr;
    OrderedJson pose = adapt::to_json(check, sewn_drape_name(k));
    pose["where"] = where;
    if (i < sewn.drape.size()) {
      const DrapeDistance& d = sewn.drape[i];
      pose["distance_to_verified"] = {
          {"verdict", d.passed() ? "pass" : "fail"},
          {"failures", d.failures},
          {"verified_mesh", d.verified_mesh},
          {"verified_mesh_in", sewn.reference_is_rest_shape ? "pattern" : "fit"},
          {"mean_m", d.mean},
          {"p95_m", d.p95},
          {"max_m", d.max},
          {"farthest", {{"vertex", d.max_vertex},
                        {"piece", d.max_vertex >= 0 ? piece_name(vertex_piece[static_cast<size_t>(d.max_vertex)])
                                                    : OrderedJson(nullptr)},
                        {"position_m", vector_json(d.max_position)}}},
          {"sewn_drape_area_m2", d.sewn_area},
          {"verified_drape_area_m2", d.verified_area},
          {"drape_area_ratio", d.verified_area > 0.0 ? d.sewn_area / d.verified_area : 0.0}};
    }
    if (i < sewn.settled.size()) {
      auto figures = [](const DrapeDistance& d) {
        return OrderedJson{{"mean_m", d.mean}, {"p95_m", d.p95}, {"max_m", d.max}};
      };
      pose["settled_from_reference"] = {{"verdict", sewn.settled[i].passed() ? "pass" : "fail"},
                                        {"mesh", settled_drape_name(k)},
                                        {"failures", sewn.settled[i].failures},
                                        {"sewn", figures(sewn.settled[i])},
                                        {"rest_shape", figures(sewn.settled_floor[i])}};
    }
    // The sewn garment's stretch against its reference's at this pose.
    if (sewn.reference_is_rest_shape && i < sewn.reference.poses.size())
      pose["reference"] = adapt::to_json(sewn.reference.poses[i], rest_drape_name(sewn.reference.poses[i].figures));
    poses.push_back(pose);
  }
  const bool failed = result.sewn_fit_failed();
  return {{"checked", true},
          {"verdict", failed ? "fail" : "pass"},
          {"fit_report", options.fit},
          {"poses", result.fit.poses},
          {"motion", result.fit.motion},
          {"start", "garment as designed"},
          {"delta", result.fit.delta()},
          {"criteria", write_options(c, adapt::FitCriteriaFields{})},
          {"error", result.sewn_fit_error.empty() ? OrderedJson(nullptr) : OrderedJson(result.sewn_fit_error)},
          {"failure", failed ? OrderedJson(result.sewn_fit_error.empty() ? sewn_fit_failure(sewn, result.pattern)
                                                                         : result.sewn_fit_error)
                             : OrderedJson(nullptr)},
          {"faces_from_rest_shape", sewn.faces_from_rest_shape.size()},
          {"drape", drape_summary(sewn)},
          {"steps", sewn.verification.steps},
          {"rejected_steps", sewn.verification.rejected_steps},
          {"frame_stride", result.fit.frame_stride},
          {"key_poses", poses},
          {"transitions", transitions_json(sewn.verification)}};
}

}  // namespace

namespace {

// The rest shape, the garment file and its design mesh (`design`, where it
// has the rest shape's connectivity: have_design), and the seams resolved
// on the rest shape, into `result`; the loops' names into `context`.
void read_inputs(const ExportRestOptions& options, ExportRestResult& result, PatternContext& context, Mesh& design,
                 bool& have_design) {
  MeshReadResult read = read_mesh(options.rest);
  result.warnings = read.warnings;
  result.rest = read.mesh;
  const Mesh& rest = result.rest;
  if (rest.F.rows() == 0) throw GeometryError("the rest shape has no triangles", options.rest);
  if (!rest.V.allFinite()) throw GeometryError("the rest shape has non-finite vertex coordinates", options.rest);

  result.have_garment = !options.garment.empty();
  result.name = fs::path(options.rest).stem().string();
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
  have_design = false;
  if (result.have_garment) {
    const fs::path design_path = fs::path(options.garment).parent_path() / result.garment.mesh_file;
    if (fs::exists(design_path)) {
      design = read_mesh(design_path).mesh;
      have_design = design.V.rows() == rest.V.rows() && design.F == rest.F;
    }
  }
  if (options.seams.empty()) return;
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

// Never a pattern with an overlapping piece: its outline crosses itself,
// so it cannot be cut from a sheet (make_pattern first removes a dart
// whose sides crossed, then splits the piece through the crossing). What
// is left is the flattening's failure on this rest shape; nothing is
// written.
void refuse_overlapping_pieces(const Pattern& pattern) {
  for (const PatternPiece& p : pattern.pieces) {
    if (!p.flat.boundary_overlaps) continue;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    for (int v : p.flat.overlap_vertex_ids) at += p.V.row(v).transpose();
    if (!p.flat.overlap_vertex_ids.empty()) at /= static_cast<double>(p.flat.overlap_vertex_ids.size());
    char where[160];
    std::snprintf(where, sizeof(where), "near (%.3f, %.3f, %.3f) m on the rest shape", at.x(), at.y(), at.z());
    throw NumericalError("the flat piece " + p.name + " overlaps itself and no cut removed the overlap", where);
  }
}

// Which piece fails the limit, by how much and where: the rest-shape point
// of its face farthest over the bound it exceeds, so that a tailor (or a
// seam spec) can put a dart or a seam there.
std::string limit_warning(const Pattern& pattern, const PatternOptions& po) {
  std::string failing;
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    const PatternPiece& p = pattern.pieces[c];
    if (p.meets_limit) continue;
    const bool compression = po.limit.symmetric ? p.stats.max_error > po.limit.max_limit
                                          : p.stats.worst1_compression > po.limit.compression_worst1;
    const Eigen::Vector3d worst = worst_region_centroid(material_faces(pattern, c),
                                                        compression ? 0.01 : 0.05, compression, po.darts.kernel_radius);
    char buf[256];
    if (po.limit.symmetric)
      std::snprintf(buf, sizeof(buf), "%s (p95 error %.1f %%, max %.1f %%", p.name.c_str(), 100.0 * p.stats.p95_error,
                    100.0 * p.stats.max_error);
    else
      std::snprintf(buf, sizeof(buf), "%s (compression %.1f %% over its worst 1 %%, ease %.1f %% over its worst 5 %%",
                    p.name.c_str(), 100.0 * p.stats.worst1_compression, 100.0 * p.stats.worst5_ease);
    std::string line = buf;
    if (p.flat.boundary_overlaps) line += ", overlapping";
    if (p.flat.stats.flipped_triangles > 0) line += ", flipped triangles";
    std::snprintf(buf, sizeof(buf), "; its worst %s at (%.3f, %.3f, %.3f) m", compression ? "compression" : "ease",
                  worst.x(), worst.y(), worst.z());
    line += buf;
    failing += (failing.empty() ? "" : ", ") + line + ")";
  }
  return "the distortion limit is not met in " + failing + " (report.json lists the pieces)";
}

// Figures of the rest shape against the garment as designed: growth, tucks
// and cone points explain a pattern that cannot meet the limit.
void rest_shape_figures(const ExportRestOptions& options, const Mesh& design, ExportRestResult& result) {
  const Mesh& rest = result.rest;
  // A cone point whose defect is 2 pi * the limit cannot be flattened
  // within it unless its neighbourhood takes that error in full.
  const double limit = options.pattern.limit.symmetric ? options.pattern.limit.max_limit : options.pattern.limit.compression_worst1;
  const double cone = 2.0 * M_PI * limit;
  const RestShapeDiagnostics d = diagnose_rest_shape(design.V, rest.V, rest.F, cone);
  // The cones a piece must flatten: those at least a centimetre inside it
  // (a seam junction is where pieces meet).
  const InnerCones inside = cone_points_inside_pieces(design.V, rest.V, rest.F, cone, result.pattern.cut.V,
                                                      result.pattern.cut.F, kConeInsideMargin);
  result.rest_shape = {{"design_mesh", (fs::path(options.garment).parent_path() / result.garment.mesh_file).string()},
                       {"area_growth", d.area_growth},
                       {"face_growth_p95", d.growth_p95},
                       {"face_growth_max", d.growth_max},
                       {"turned_faces", d.turned_faces},
                       {"turned_area_fraction", d.turned_area_fraction},
                       {"cone_angle_deg", d.cone_angle * 180.0 / M_PI},
                       {"cone_points", d.cone_points},
                       {"cone_points_design", d.cone_points_design},
                       {"cone_points_inside_pieces", inside.rest},
                       {"cone_points_inside_pieces_design", inside.design},
                       {"cone_inside_margin_m", kConeInsideMargin},
                       {"max_abs_angle_defect_deg", d.max_abs_defect * 180.0 / M_PI},
                       {"abs_angle_defect_sum_rad", d.abs_defect_sum},
                       {"abs_angle_defect_sum_design_rad", d.abs_defect_sum_design}};
  if (!result.pattern.meets_limit && d.cone_points > d.cone_points_design)
    result.warnings.push_back("the rest shape has " + std::to_string(d.cone_points) + " cone points (the design " +
                              std::to_string(d.cone_points_design) + ") and " + std::to_string(d.turned_faces) +
                              " faces turned over in tucks (see rest_shape in report.json)");
}

// The drapes the sewn garment is measured against: the fit's verified drapes
// of this rest shape, or, for a fit run without verification, the rest
// shape simulated here as the sewn garment was (sewn.reference). Fills
// `reference` and `names`; empty when neither exists.
void reference_drapes(const ExportRestOptions& options, PoseInterpolator& interpolator, const MotionSpec& motion,
                      const Mesh& design, ExportRestResult& result, std::vector<Eigen::MatrixXd>& reference,
                      std::vector<std::string>& names) {
  const Mesh& rest = result.rest;
  SewnFitResult& sewn = result.sewn_fit;
  if (result.fit.verified.empty()) {
    try {
      sewn.reference = rest_shape_drapes(interpolator, motion, design.V, rest.V, rest.F, result.garment,
                                         result.fit.run, result.fit.criteria, options.progress);
      sewn.reference_is_rest_shape = true;
    } catch (const NumericalError& e) {
      sewn.drape_not_measured = std::string("the fit has no verified drapes, and the rest shape's own simulation "
                                            "failed: ") + e.what();
      return;
    }
    for (const adapt::PoseCheck& check : sewn.reference.poses) {
      reference.push_back(check.figures.V_draped);
      names.push_back(rest_drape_name(check.figures));
    }
    return;
  }
  for (const FitSettings::VerifiedDrape& d : result.fit.verified) {
    const Mesh m = read_mesh(d.path).mesh;
    if (m.V.rows() != rest.V.rows() || m.F != rest.F)
      throw GeometryError("the fit's verified drape is not a drape of this rest shape (" +
                              std::to_string(m.V.rows()) + " vertices, the rest shape " +
                              std::to_string(rest.V.rows()) + "); --fit must name the fit of " + options.rest,
                          d.path.string());
    reference.push_back(m.V);
    names.push_back(d.mesh);
  }
}

// Settled (the default): the sewn garment (and the rest shape, the floor) settled
// at each key pose alone from the reference drape, and those distances.
void settled_drapes(const ExportRestOptions& options, PoseInterpolator& interpolator, const MotionSpec& motion,
                    const std::vector<Eigen::MatrixXd>& reference, ExportRestResult& result) {
  const Mesh& rest = result.rest;
  SewnFitResult& sewn = result.sewn_fit;
  const auto triangles = sewn_rest_triangles(result.pattern, result.layout, static_cast<int>(rest.F.rows()));
  const auto settled = settle_from_reference(interpolator, motion, reference, rest.F, result.garment, triangles,
                                             result.fit.run, result.fit.criteria);
  const auto floor = settle_from_reference(interpolator, motion, reference, rest.F, result.garment,
                                           adapt::rest_triangles_of(rest.V, rest.F), result.fit.run,
                                           result.fit.criteria);
  sewn.settled_drapes = settled;
  for (size_t i = 0; i < reference.size(); ++i) {
    sewn.settled.push_back(drape_distance(settled[i], reference[i], rest.F, options.drape));
    sewn.settled.back().key = sewn.drape[i].key;
    sewn.settled.back().pose = sewn.drape[i].pose;
    sewn.settled.back().verified_mesh = sewn.drape[i].verified_mesh;
    sewn.settled_floor.push_back(drape_distance(floor[i], reference[i], rest.F, DrapeCriteria{}));
  }
}

// The sewn-fit check (--fit): the garment sewn from the flat pieces,
// simulated through the fit's key poses, then its drapes against the
// reference drapes of this rest shape.
void run_sewn_fit(const ExportRestOptions& options, const Mesh& design, ExportRestResult& result) {
  const Mesh& rest = result.rest;
  const PoseSet poses = load_pose_set(result.fit.poses);
  const MotionSpec motion = read_motion_spec(result.fit.motion, poses);
  if (result.garment.body.vertex_count != 0 &&
      result.garment.body.vertex_count != static_cast<long long>(poses.V[0].rows()))
    throw GeometryError("the garment was designed on a body with " + std::to_string(result.garment.body.vertex_count) +
                            " vertices, the fit's pose set has " + std::to_string(poses.V[0].rows()),
                        result.fit.poses);
  InterpolationOptions interp_options;
  interp_options.anchor = motion.anchor;
  PoseInterpolator interpolator(poses, interp_options);
  // A simulation that fails for good is a finding about the pattern (a
  // pattern far from its rest shape can start with forces no step
  // survives): the check fails and the pattern is still written.
  try {
    // The sewn garment through the motion, judged where the fit was: its key poses and, where the
    // fit's verification solved them, its in-between frames.
    adapt::MotionRunOptions sewn_run = result.fit.run;
    sewn_run.schedule.frame_stride = result.fit.frame_stride;
    result.sewn_fit = sewn_fit_check(interpolator, motion, design.V, rest.F, result.garment, result.pattern,
                                     result.layout, sewn_run, result.fit.criteria, options.progress);
  } catch (const NumericalError& e) {
    result.sewn_fit_error = std::string("the simulation of the sewn garment failed: ") + e.what();
    result.sewn_fit.delta = result.fit.delta();
    result.sewn_fit.drape_not_measured = "the simulation of the sewn garment failed";
  }
  result.sewn_fit_done = true;
  if (!result.sewn_fit_error.empty()) return;
  SewnFitResult& sewn = result.sewn_fit;
  std::vector<Eigen::MatrixXd> reference;
  std::vector<std::string> names;
  reference_drapes(options, interpolator, motion, design, result, reference, names);
  // By default the bounds judge the settled distances, and the
  // distance after the whole motion is reported unbounded.
  const DrapeCriteria motion_bounds = options.drape_settled ? DrapeCriteria{} : options.drape;
  if (!reference.empty()) compare_with_verified(sewn, reference, names, rest.F, motion_bounds);
  sewn.drape_criteria = options.drape;
  if (options.drape_settled && !sewn.drape.empty()) settled_drapes(options, interpolator, motion, reference, result);
}

// The pattern of the rest shape with `po`, its overlaps refused, laid out,
// and its limit warning: result.pattern, layout, cut_options and warnings.
void cut_pattern(const PatternOptions& po, const LayoutOptions& layout_options, const PatternContext& context,
                 ExportRestResult& result) {
  result.pattern = make_pattern(result.rest.V, result.rest.F, result.seams, po, context);
  refuse_overlapping_pieces(result.pattern);
  for (const auto& [phase, s] : result.pattern.seconds) result.timing["cut_and_flatten_" + phase] = s;
  result.cut_options = po;
  LayoutOptions layout = layout_options;
  layout.title = pattern_title(result);
  // The grain per face of the garment (a bias-cut region), as the fit simulated it.
  const std::vector<double> no_grain;
  const std::vector<double>& grain =
      result.have_garment && result.garment.material.turned_grain() ? result.garment.material.grain_angles : no_grain;
  result.layout = layout_pattern(result.pattern, layout, grain);
  if (!result.pattern.meets_limit) result.warnings.push_back(limit_warning(result.pattern, po));
}

// The cut without what pulls a pattern within its limit: no limit
// weighting, no relief share.
PatternOptions plain_cut(PatternOptions po) {
  po.flatten.limit_rounds = 0;
  po.panels.min_relief_share = 0.0;
  return po;
}

bool pulled_within_limit(const PatternOptions& po) {
  return po.flatten.limit_rounds > 0 || po.panels.min_relief_share > 0.0;
}

// 0: the sewn garment passes; 1: it fails the drape bounds only; 2: it
// fails the stretch bounds, or its simulation failed.
int sewn_fit_severity(const ExportRestResult& r) {
  if (!r.sewn_fit_failed()) return 0;
  return r.sewn_fit_error.empty() && r.sewn_fit.verification.passed() ? 1 : 2;
}

}  // namespace

ExportRestResult export_rest(const ExportRestOptions& options) {
  ExportRestResult result;
  LapTimer timer;
  auto lap = [&](const char* phase) { result.timing[phase] = timer.lap(); };
  if (!options.fit.empty() && options.garment.empty())
    throw UsageError("the sewn-fit check (--fit) needs the garment file (--garment): pins, material, design", "--fit");
  PatternContext context;
  Mesh design;
  bool have_design = false;
  read_inputs(options, result, context, design, have_design);
  lap("read");

  // The fit's stretch budget weighs the panel seams (PanelOptions::stretch_budget).
  PatternOptions pattern_options = options.pattern;
  if (!options.fit.empty()) {
    result.fit = read_fit_settings(options.fit);
    result.fit.run.schedule.threads = options.threads;
    pattern_options.panels.stretch_budget = result.fit.delta();
  }
  result.stretch_budget = pattern_options.panels.stretch_budget;
  const std::vector<std::string> input_warnings = result.warnings;
  cut_pattern(pattern_options, options.layout, context, result);
  lap("cut_and_flatten");

  result.rest_shape = OrderedJson::object();
  if (have_design) rest_shape_figures(options, design, result);

  if (!options.fit.empty()) {
    if (!have_design)
      throw GeometryError("the sewn-fit check starts from the garment as designed, which is missing or has another "
                          "connectivity than the rest shape",
                          (fs::path(options.garment).parent_path() / result.garment.mesh_file).string());
    run_sewn_fit(options, design, result);
    lap("sewn_fit");
    // The fit comes before the pattern's own limit: where the pattern cut within it (the limit
    // weighting and the relief share pull its pieces towards compression and more seams) sews into
    // a garment that fails the fit, the plain cut is tried and kept where its garment fails less: a
    // garment that fails the stretch bounds cannot be worn, one that only drapes farther from the
    // fit than the drape bounds can.
    if (result.sewn_fit_failed() && pulled_within_limit(pattern_options)) {
      const std::string because =
          result.sewn_fit_error.empty() ? sewn_fit_failure(result.sewn_fit, result.pattern) : result.sewn_fit_error;
      ExportRestResult weighted = result;
      result.sewn_fit = SewnFitResult{};
      result.sewn_fit_error.clear();
      result.sewn_fit_done = false;
      result.warnings = input_warnings;
      cut_pattern(plain_cut(pattern_options), options.layout, context, result);
      lap("cut_and_flatten_plain");
      run_sewn_fit(options, design, result);
      lap("sewn_fit_plain");
      if (sewn_fit_severity(result) < sewn_fit_severity(weighted)) {
        result.plain_cut_because = "the pattern cut within its limit sewed into a garment that failed the fit (" +
                                   because + "); the plain cut's garment " +
                                   (result.sewn_fit_failed() ? "fails less" : "passes");
        result.warnings.push_back(result.plain_cut_because);
      } else {
        const OrderedJson timing = result.timing;
        result = std::move(weighted);
        result.timing = timing;
      }
    }
  }
  return result;
}

OrderedJson export_rest_report(const ExportRestResult& result, const ExportRestOptions& options) {
  const PatternOptions& po = result.cut_options;
  OrderedJson report;
  report["schema"] = schema_tag("export-rest-report", 1);
  report["input"] = {{"rest", options.rest},
                     {"rest_sha256", sha256_file_hex(options.rest)},
                     {"garment", options.garment},
                     {"seams", options.seams},
                     {"vertices", result.rest.V.rows()},
                     {"faces", result.rest.F.rows()}};
  if (result.have_garment) report["input"]["fabric"] = result.garment.material.fabric;
  // The cutter's options with the stretch budget it used (the fit's delta
  // with --fit).
  // The options the pattern was cut with (the fit's stretch budget with --fit; the plain cut's where
  // the sewn garment of the pattern within its limit failed the fit).
  const PatternOptions& used = result.cut_options;
  report["options"] = {{"pattern", write_options(used, PatternOptionFields{})},
                       {"layout", write_options(options.layout, LayoutOptionFields{})},
                       {"seam_mismatch_tolerance", write_options(options.tolerance, SeamToleranceFields{})},
                       {"dxf", {{"profile", dxf_profile_name(options.dxf.profile)},
                                {"size", options.dxf.size},
                                {"author", options.dxf.author},
                                {"creation_date", options.dxf.date}}},
                       {"threads", options.threads},
                       {"seam_spec", options.seams.empty() ? OrderedJson() : to_json(result.spec)}};
  report["cut"] = {{"plain_after_sewn_fit", !result.plain_cut_because.empty()},
                   {"because", result.plain_cut_because.empty() ? OrderedJson(nullptr)
                                                                : OrderedJson(result.plain_cut_because)}};
  report["sewn_fit"] = sewn_fit_report(result, options);
  report["rest_shape"] = result.rest_shape;
  OrderedJson sheets = OrderedJson::array();
  for (const PaperSize& paper : pdf_papers()) {
    PdfOptions pdf;
    pdf.paper = paper;
    const PdfSummary s = tile_pages(result.layout, pdf);
    OrderedJson blank = OrderedJson::array();
    for (const PdfPage& t : s.tiles)
      if (!t.printed) blank.push_back(t.label);
    sheets.push_back({{"file", "pattern-" + paper.name + ".pdf"},
                      {"paper", paper.name},
                      {"paper_mm", {1000.0 * paper.width, 1000.0 * paper.height}},
                      {"rows", s.rows},
                      {"columns", s.columns},
                      {"pages", s.pages},
                      {"blank_left_out", blank},
                      {"overlap_m", pdf.overlap},
                      {"test_square_m", pdf.test_square}});
  }
  report["sheets"] = sheets;
  const OrderedJson body = pattern_report(result.pattern, result.layout, po, options.tolerance);
  for (auto it = body.begin(); it != body.end(); ++it) report[it.key()] = it.value();
  return report;
}

void write_export_rest(const ExportRestResult& result, const ExportRestOptions& options, const fs::path& dir) {
  for (const adapt::PoseCheck& check : result.sewn_fit.verification.poses) {
    Mesh drape;
    drape.F = result.rest.F;
    drape.V = check.figures.V_draped;
    drape.face_fields.push_back({"max_stretch", check.figures.face_max_stretch});
    for (const DrapeDistance& d : result.sewn_fit.drape)
      if (d.key == check.figures.key && d.pose == check.figures.pose)
        drape.vertex_fields.push_back({"distance_to_verified", d.vertex_distance});
    write_mesh(dir / sewn_drape_name(check.figures), drape);
  }
  const auto& poses = result.sewn_fit.verification.poses;
  for (size_t i = 0; i < result.sewn_fit.settled_drapes.size() && i < poses.size(); ++i) {
    Mesh drape;
    drape.F = result.rest.F;
    drape.V = result.sewn_fit.settled_drapes[i];
    drape.vertex_fields.push_back({"distance_to_verified", result.sewn_fit.settled[i].vertex_distance});
    write_mesh(dir / settled_drape_name(poses[i].figures), drape);
  }
  for (const adapt::PoseCheck& check : result.sewn_fit.reference.poses) {
    Mesh drape;
    drape.F = result.rest.F;
    drape.V = check.figures.V_draped;
    drape.face_fields.push_back({"max_stretch", check.figures.face_max_stretch});
    write_mesh(dir / rest_drape_name(check.figures), drape);
  }
  const Pattern& pattern = result.pattern;
  const Layout& layout = result.layout;
  write_file_atomic(dir / "pattern.svg", [&](std::ostream& s) { write_svg(s, pattern, layout, {pattern_title(result)}); }, false);
  DxfOptions dxf = options.dxf;
  if (dxf.style.empty() || dxf.style == DxfOptions{}.style) dxf.style = pattern_title(result);
  const std::vector<CutInstruction> cut = cut_instructions(pattern);
  write_file_atomic(dir / "pattern.dxf", [&](std::ostream& s) { write_dxf(s, pattern, layout, dxf, cut); }, false);
  for (const PaperSize& paper : pdf_papers()) {
    PdfOptions po;
    po.paper = paper;
    po.title = pattern_title(result);
    write_file_atomic(dir / ("pattern-" + paper.name + ".pdf"),
                      [&](std::ostream& s) { write_pdf(s, pattern, layout, cut, po, options.dxf.date); });
  }
  MarkerPieces for_marker = marker_pieces(pattern, layout, cut);
  // The marker names a fabric the spec chose, as the labels do (the paper's default left as it was).
  if (result.have_garment && result.garment.material.fabric != "paper") for_marker.fabric = result.garment.material.fabric;
  write_json_file(dir / "marker_pieces.json", marker_pieces_json(for_marker));
  write_file_atomic(dir / "pieces.obj", [&](std::ostream& s) { write_pieces_obj(s, pattern, layout); }, false);
  write_file_atomic(dir / "seams.obj", [&](std::ostream& s) { write_seams_obj(s, pattern); }, false);
  write_mesh(dir / "pieces_flat.ply", flat_pieces_mesh(pattern, layout));
  // Flat like the other stages' timing.json: seconds under "<phase>_s", the total last.
  OrderedJson timing;
  timing["schema"] = schema_tag("timing", 1);
  timing["tool"] = "export-rest";
  for (auto it = result.timing.begin(); it != result.timing.end(); ++it) {
    if (it.key() != "total") timing[it.key() + "_s"] = it.value();
  }
  if (result.sewn_fit_done) {
    timing["sewn_fit_simulation_s"] = result.sewn_fit.verification.seconds;
    if (result.sewn_fit.reference_is_rest_shape)
      timing["sewn_fit_reference_simulation_s"] = result.sewn_fit.reference.seconds;
    timing["sewn_fit_steps"] = result.sewn_fit.verification.steps;
  }
  if (result.timing.contains("total")) timing["total_s"] = result.timing["total"];
  write_json_file(dir / "timing.json", timing);
  write_json_file(dir / "report.json", export_rest_report(result, options));
}

}  // namespace gp
