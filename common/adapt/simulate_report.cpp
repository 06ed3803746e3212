#include "adapt/simulate_report.h"

#include <cstdio>

#include "adapt/key_pose_report.h"
#include "collision/crossings.h"
#include "spec/option_fields.h"

namespace gp::adapt {

std::string drape_file_name(const std::string& prefix, const KeyPoseResult& k) {
  char name[256];
  std::snprintf(name, sizeof(name), "%s_%02d_%s.ply", prefix.c_str(), k.key, k.pose.c_str());
  return name;
}

std::string verified_drape_file_name(const KeyPoseResult& k, bool adapted) {
  return drape_file_name(adapted ? "verified" : "draped", k);
}

std::string worst_frame_file_name(const TransitionCheck& t) {
  char name[256];
  std::snprintf(name, sizeof(name), "worst_frame_%02d_%s_to_%s.ply", t.transition, t.from.c_str(), t.to.c_str());
  return name;
}

std::vector<std::pair<std::string, Mesh>> fit_meshes(const FitResult& fit, const Eigen::MatrixXi& F, bool adapted) {
  std::vector<std::pair<std::string, Mesh>> meshes;
  Mesh rest;
  rest.V = fit.run.V_rest;
  rest.F = F;
  meshes.emplace_back("rest.ply", std::move(rest));
  const auto drape = [&](const std::string& name, const KeyPoseResult& k) {
    Mesh draped;
    draped.V = k.V_draped;
    draped.F = F;
    draped.face_fields.push_back({"max_stretch", k.face_max_stretch});
    meshes.emplace_back(name, std::move(draped));
  };
  for (const KeyPoseResult& k : fit.run.keys) drape(drape_file_name("draped", k), k);
  // Without adaptation the run's own drapes are the fresh simulation.
  if (fit.verification && adapted) {
    for (const PoseCheck& check : fit.verification->poses) {
      drape(verified_drape_file_name(check.figures, true), check.figures);
    }
  }
  if (fit.verification) {
    for (const TransitionCheck& t : fit.verification->transitions) {
      if (t.worst >= 0) drape(worst_frame_file_name(t), t.frames[static_cast<size_t>(t.worst)].figures);
    }
  }
  return meshes;
}

namespace {

OrderedJson held_cloth_json(const KeyPoseResult& k) {
  OrderedJson list = OrderedJson::array();
  for (const HeldCloth& h : k.held_cloth) list.push_back(to_json(h));
  return list;
}

}  // namespace

OrderedJson held_json(const FitResult& fit, const MotionSpec& motion, PoseInterpolator& interpolator,
                      const GarmentFile& garment, const MotionRunOptions& options, OpeningOptions opening) {
  const MotionRunResult& result = fit.run;
  if (result.held_key < 0) return nullptr;
  const KeyPoseResult& k = result.keys[static_cast<size_t>(result.held_key)];
  const int pose = motion.keys[static_cast<size_t>(k.key)].pose_index;
  opening.contact_surface = options.contact.surface;
  const Opening o = k.held_cloth.empty() ? Opening{}
                                         : choose_opening(interpolator, pose, k.held_cloth, garment.offset, opening);
  OrderedJson held = {
      {"key", k.key}, {"pose", k.pose}, {"settle_steps", k.settle_steps}, {"held_cloth", held_cloth_json(k)}};
  if (o.found) {
    held["open_suggestion"] = {{"pose", k.pose},
                               {"toward", interpolator.pose_names()[static_cast<size_t>(o.toward)]},
                               {"steps", o.steps},
                               {"fraction", 1.0 / o.steps},
                               {"smallest_gap_mm", 1e3 * o.smallest_gap},
                               {"largest_body_displacement_mm", 1e3 * o.largest_displacement}};
  } else {
    held["open_suggestion"] = nullptr;
  }
  return held;
}

namespace {

OrderedJson verification_json(const FitVerification& verification, const FitOptions& options) {
  OrderedJson poses_json = OrderedJson::array();
  for (const PoseCheck& check : verification.poses) {
    poses_json.push_back(to_json(check, verified_drape_file_name(check.figures, options.motion.adaptation.enabled)));
  }
  OrderedJson transitions_json = OrderedJson::array();
  for (const TransitionCheck& t : verification.transitions) {
    transitions_json.push_back(to_json(t, t.worst >= 0 ? worst_frame_file_name(t) : std::string()));
  }
  return {{"verdict", verification.passed() ? "pass" : "fail"},
          {"criteria", write_options(options.criteria, FitCriteriaFields{})},
          {"steps", verification.steps},
          {"rejected_steps", verification.rejected_steps},
          {"frame_stride", options.frame_stride},
          {"key_poses", poses_json},
          {"transitions", transitions_json}};
}

OrderedJson run_json(const MotionRunResult& result) {
  return {{"steps", result.steps},
          {"rejected_steps", result.solver.rejected},
          {"accepted_folds", result.solver.accepted_flips},
          {"fold_streak_steps", result.solver.fold_streak_steps},
          {"contact_constraints", result.solver.constraints},
          {"contact_releases", result.solver.released},
          {"pinched_contacts", result.collisions.pinched},
          {"crease_contacts", result.collisions.creases},
          {"initial_min_distance_m", result.initial_min_distance},
          {"initial_crossings", collision::to_json(result.initial_crossings)},
          {"continuous_contact_active", result.continuous_contact},
          {"pin_targets_moved", result.pins.pushed},
          {"largest_pin_move_m", result.pins.largest_push},
          {"closest_pin_target_m",
           result.pins.pushed ? OrderedJson(result.pins.closest_before) : OrderedJson(nullptr)},
          {"adaptations", result.adaptations},
          {"arap_converged", result.arap.converged},
          {"all_settled", result.all_settled},
          {"rest_area_growth", result.keys.empty() ? 1.0 : result.keys.back().rest_area_growth}};
}

}  // namespace

OrderedJson simulate_report(const SimulateReportInputs& where, const FitInputs& in, const FitOptions& options,
                            const FitResult& fit, const OrderedJson& held) {
  const MotionRunResult& result = fit.run;
  OrderedJson report;
  report["schema"] = schema_tag("simulate-adapt-report", 1);
  // The fit's options under the keys the sewn-fit check reads them back by
  // (adapt/garment_fit.h), between the inputs and the effective motion.
  report["options"] = {{"poses", where.poses_path}, {"motion", where.motion_path}, {"garment", where.garment_path}};
  report["options"].update(write_options(options, FitOptionFields{}));
  report["options"]["threads"] = where.threads;
  report["options"]["motion_effective"] = to_json(in.motion);
  report["options"]["material"] = to_json(in.garment.material);
  report["options"]["comfort_offset_m"] = in.garment.offset;
  if (in.carried) {
    const CarryToBodyResult& carried = *in.carried;
    report["other_body"] = {
        {"design_pose", in.garment.body.design_pose},
        {"garment_file_sha256", in.design.expected},
        {"pose_set_sha256", in.design.actual},
        {"carried_with_body", carried.carried},
        {"largest_carry_m", carried.carried ? OrderedJson(carried.largest_carry) : OrderedJson(nullptr)},
        {"clearance", to_json(carried.clearance)}};
  }
  report["counts"] = {{"garment_vertices", in.mesh.V.rows()},
                      {"garment_faces", in.mesh.F.rows()},
                      {"body_vertices", in.poses.V[0].rows()},
                      {"body_faces", in.poses.F.rows()},
                      {"body_faces_kept", result.culled_body_faces},
                      {"hull_faces", result.contact_surface.F.rows() - result.contact_surface.body_face_count}};
  OrderedJson hulls = OrderedJson::array();
  for (int h = 0; h < result.contact_surface.hull_count; ++h) {
    const Eigen::Vector3d& c = result.contact_surface.part_centroids[static_cast<size_t>(h)];
    hulls.push_back({{"faces", result.contact_surface.hull_faces[static_cast<size_t>(h)]},
                     {"part_vertices", result.contact_surface.part_vertices[static_cast<size_t>(h)]},
                     {"part_centroid", {c.x(), c.y(), c.z()}}});
  }
  report["hand_hulls"] = hulls;
  OrderedJson keys = OrderedJson::array();
  for (const KeyPoseResult& k : result.keys) keys.push_back(key_pose_json(k, drape_file_name("draped", k)));
  report["key_poses"] = keys;
  OrderedJson cycles = OrderedJson::array();
  for (const FitCycle& c : fit.cycles) {
    cycles.push_back({{"steps", c.steps},
                      {"adaptations", c.adaptations},
                      {"rest_area_growth", c.rest_area_growth},
                      {"verified", c.verified}});
  }
  report["cycles"] = cycles;
  report["held"] = held;
  report["cycle_error"] = fit.cycle_error.empty() ? OrderedJson(nullptr) : OrderedJson(fit.cycle_error);
  report["verification"] = fit.verification ? verification_json(*fit.verification, options) : OrderedJson(nullptr);
  report["run"] = run_json(result);
  return report;
}

OrderedJson simulate_timing(const FitResult& fit, int threads, int workers, double total_s) {
  const MotionRunResult& result = fit.run;
  const auto& t = result.times;
  const double per_step = result.steps > 0 ? 1e3 / result.steps : 0.0;
  OrderedJson timing;
  timing["schema"] = schema_tag("timing", 1);
  timing["tool"] = "simulate-adapt";
  timing["steps_per_s"] = t.total > 0.0 ? result.steps / t.total : 0.0;
  timing["ms_per_step"] = {{"forces_assembly", t.forces_assembly * per_step},
                           {"factorization", t.factorization * per_step},
                           {"solve", t.solve * per_step},
                           {"collisions", t.collisions * per_step},
                           {"continuous_contact", result.contact.seconds * per_step},
                           {"adaptation", t.adaptation * per_step},
                           {"body", t.body * per_step},
                           {"waiting_for_worker", t.waiting * per_step}};
  // Work counters: iterative solvers stop on a residual and the collider
  // skips or reuses queries on exact comparisons, so these counts follow the
  // last bits of the arithmetic (another CPU's BLAS or libm kernels) while the
  // results stay within the solvers' tolerances. The report keeps the
  // decisions that shape the result (steps, rejections, settling).
  timing["work"] = {{"factorizations", result.solver.factorizations},
                    {"cg_iterations", result.solver.cg_iterations},
                    {"membrane_fallbacks", result.solver.membrane_fallbacks},
                    {"arap_iterations", result.arap.iterations},
                    {"arap_max_iterations", result.arap.max_iterations},
                    {"arap_max_residual", result.arap.max_residual},
                    {"body_queries", result.collisions.queries},
                    {"body_queries_skipped", result.collisions.skipped},
                    {"body_queries_reused", result.collisions.reused},
                    {"body_queries_local", result.collisions.local},
                    {"contact_rounds", result.contact.rounds},
                    {"contact_body_vertex", result.contact.body_vertex_contacts},
                    {"contact_edge", result.contact.edge_contacts},
                    {"contact_cloth_vertex", result.contact.cloth_vertex_contacts},
                    {"contact_crossings", result.contact.crossings},
                    {"contact_fail_safe_calls", result.contact.fail_safe_calls},
                    {"contact_fail_safe_vertices", result.contact.fail_safe_vertices},
                    {"contact_unresolved", result.contact.unresolved}};
  // Why steps were rejected: each retry refactors and re-collides, so the
  // reasons (and the faces that keep turning over) say where steps are lost.
  const cloth::RejectionCounts& rc = result.solver.rejections;
  OrderedJson faces = OrderedJson::array();
  for (const auto& [face, count] : cloth::most_inverted_faces(result.solver, 10)) {
    faces.push_back({{"face", face}, {"rejections", count}});
  }
  timing["rejections"] = {{"total", result.solver.rejected},
                          {"inverted_triangle", rc.inverted},
                          {"too_fast", rc.too_fast},
                          {"energy_growth", rc.energy_growth},
                          {"non_finite", rc.non_finite},
                          {"solve_failed", rc.solve_failed},
                          {"most_inverted_faces", faces}};
  timing["static_solve"] = {{"newton_iterations", result.newton_iterations},
                            {"line_search_trials", result.line_search_trials},
                            {"seconds", result.static_seconds}};
  timing["verification_s"] = fit.verification ? fit.verification->seconds : 0.0;
  timing["threads"] = threads;
  timing["workers"] = workers;
  timing["setup_s"] = t.setup;
  timing["run_s"] = t.total;
  timing["total_s"] = total_s;
  return timing;
}

std::vector<std::string> fit_warnings(const FitResult& fit, const MotionRunOptions& options) {
  std::vector<std::string> warnings;
  const MotionRunResult& result = fit.run;
  if (!fit.cycle_error.empty()) {
    warnings.push_back("a further adaptation cycle failed (" + fit.cycle_error +
                       "); the previous cycle's rest shape and its verification are the result");
  }
  if (options.contact.continuous && !result.continuous_contact) {
    const auto& c = result.initial_crossings;
    warnings.push_back("the garment starts through the body (" + std::to_string(c.crossings()) +
                       " edge/triangle crossings, " + std::to_string(c.cloth_vertices_inside) +
                       " vertices inside, " + std::to_string(c.body_vertices_behind) +
                       " body vertices behind it); the continuous contact, which keeps each body part on the "
                       "side of the cloth it starts on, is off for this run");
  }
  for (const auto& k : result.keys) {
    if (k.crossings.intersection_free()) continue;
    warnings.push_back("key pose " + k.pose + ": the cloth passes through the body (" +
                       std::to_string(k.crossings.crossings()) + " edge/triangle crossings, " +
                       std::to_string(k.crossings.cloth_vertices_inside) + " cloth vertices inside, " +
                       std::to_string(k.crossings.body_vertices_behind) + " body vertices behind the cloth)");
  }
  return warnings;
}

std::optional<std::string> fit_failure(const FitResult& fit, const OrderedJson& held, const FitOptions& options) {
  if (!held.is_null()) {
    const KeyPoseResult& k = fit.run.keys[static_cast<size_t>(fit.run.held_key)];
    std::string what = check_pose(k, options.motion.adaptation.adapter.delta, options.criteria).front();
    if (!held["open_suggestion"].is_null()) {
      const auto& o = held["open_suggestion"];
      char line[256];
      std::snprintf(line, sizeof(line),
                    "; opening it 1/%d towards %s frees it (%.0f mm of room, the body moves %.0f mm at most)",
                    o["steps"].get<int>(), o["toward"].get<std::string>().c_str(),
                    o["smallest_gap_mm"].get<double>(), o["largest_body_displacement_mm"].get<double>());
      what += line;
    }
    return "key pose " + std::to_string(k.key) + " (" + k.pose + "): " + what;
  }
  if (fit.verification && !fit.verification->passed()) {
    for (const PoseCheck& check : fit.verification->poses) {
      if (check.passed()) continue;
      return "the verification fails at key pose " + std::to_string(check.figures.key) + " (" + check.figures.pose +
             "): " + check.failures.front();
    }
    for (const TransitionCheck& t : fit.verification->transitions) {
      if (!t.passed()) return "the verification fails: " + failure_line(t);
    }
  }
  return std::nullopt;
}

}  // namespace gp::adapt
