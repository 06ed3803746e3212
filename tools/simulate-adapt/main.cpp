// simulate-adapt: simulates the garment on the body moving through a motion's
// key poses and adapts its rest shape wherever the cloth stretches more than
// 1 + delta (Wolff et al. 2023); --no-adapt evaluates the fixed design instead.
// Writes rest.ply, draped_<k>_<pose>.ply (face field max_stretch), timing.json
// and report.json (written last) into --out.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include "adapt/fit_verification.h"
#include "adapt/garment_fit.h"
#include "adapt/open_pose.h"
#include "adapt/garment_motion.h"
#include "adapt/motion_progress.h"
#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "garment/design_body.h"
#include "garment/garment_file.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "registration/edge_ratios.h"
#include "spec/json_file.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  gp::Tool tool("simulate-adapt", "Simulate a garment on the moving body and adapt its rest shape");
  std::string poses_path, motion_path, garment_path, solver = "refactor";
  gp::adapt::FitOptions fit_options;
  gp::adapt::MotionRunOptions& options = fit_options.motion;
  gp::adapt::FitCriteria& criteria = fit_options.criteria;
  bool no_adapt = false;
  auto& app = tool.app();
  app.add_option("--poses", poses_path, "Pose set manifest (poses.json, pose-set/1)")->required();
  app.add_option("--motion", motion_path, "Motion spec (motion/1): key poses and frames per transition")->required();
  app.add_option("--garment", garment_path, "Garment file (garment.json, garment/1); its mesh sits beside it")
      ->required();
  app.add_flag("--no-adapt", no_adapt, "Keep the rest shape fixed (evaluate a single-pose design)");
  app.add_flag("--other-body", fit_options.other_body,
               "Fit the garment to a pose set whose design pose is another body than the one it was designed on "
               "(by default that is refused, exit 5)");
  bool no_verify = false;
  app.add_flag("--no-verify", no_verify,
               "Skip the verification pass (the final rest shape simulated afresh through the motion without "
               "adaptation; a failing key pose exits 8) and adapt in one cycle");
  app.add_option("--cycles", fit_options.max_cycles,
                 "Adaptation cycles at most: another cycle through the motion, from the garment as designed with "
                 "the rest shape so far, while the verification fails [count]")
      ->capture_default_str()->check(CLI::Range(1, 100));
  app.add_option("--verify-max-area", criteria.max_area_above,
                 "Verification: a key pose fails when this fraction of the area or more is stretched above "
                 "1+delta [1]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--verify-p99-margin", criteria.p99_margin,
                 "Verification: a key pose fails when its p99 stretch exceeds 1+delta plus this [1]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--verify-max-penetration", criteria.max_penetration,
                 "Verification: a key pose fails when a cloth vertex lies deeper inside the body [m]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--verify-max-crossings", criteria.max_crossings,
                 "Verification: a key pose fails when more body edges pass through cloth triangles and cloth "
                 "edges through body triangles [count]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--verify-tear-stretch", criteria.tear_stretch,
                 "Verification: cloth stretched beyond this would tear [ratio]")
      ->capture_default_str()->check(CLI::Range(1.0, 100.0));
  app.add_option("--verify-max-torn-area", criteria.max_torn_area,
                 "Verification: a key pose fails when more than this fraction of the area is stretched beyond the "
                 "tear stretch [1]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  bool allow_unsettled = false;
  app.add_flag("--verify-allow-unsettled", allow_unsettled,
               "Verification: judge a key pose whose cloth still moves at the settle cap by its figures alone (by "
               "default such a pose fails: its figures are a snapshot of moving cloth)");
  app.add_option("--dt", options.solver.dt, "Simulation time step [s]")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--substeps", options.substeps, "Simulation steps per interpolation frame [count]")
      ->capture_default_str()->check(CLI::Range(1, 1000));
  app.add_option("--adapt-every", options.adapt_every, "Simulation steps between adaptations [count]")
      ->capture_default_str()->check(CLI::Range(1, 100000));
  app.add_option("--delta", options.adaptation.delta, "Stretch limit of the fit: the verification fails cloth above 1+delta; the adaptation clips "
                 "below it (see --margin) [1]")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_option("--margin", options.adaptation.margin,
                 "The adaptation clips stretch at 1+delta-margin, below the fit's limit, so that a fresh simulation "
                 "of the rest shape stays within 1+delta (0: the paper's rule at 1+delta) [1]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--hysteresis", options.adaptation.hysteresis,
                 "A face stretched beyond 1+delta-margin is clipped to 1+delta-margin-hysteresis, so that cloth "
                 "the body holds stretched is not adapted again at every hair above the limit [1]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--arap-tolerance", options.adaptation.arap.tolerance,
                 "ARAP stitching tolerance: largest edge-length change per iteration / mean edge length [1]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--arap-stretch-tolerance", options.adaptation.arap.stretch_tolerance,
                 "ARAP stitching stops instead when no face's principal stretch changes by more than this in one "
                 "iteration (0: the edge rule of --arap-tolerance) [1]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--smoothing-length", options.adaptation.smoothing_length,
                 "The rest shape's stitching resists changes of its form shorter than this, so that growth makes "
                 "smooth bulges rather than tucks (0: plain ARAP) [m]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--adapt-rounds", options.adaptation.rounds,
                 "Clip-and-stitch rounds per adaptation against the same cloth positions [count]")
      ->capture_default_str()->check(CLI::Range(1, 100));
  app.add_flag("--adapt-during-transitions", options.adapt_during_transitions,
               "Adapt also while the body moves between key poses (the paper), not only while the cloth settles "
               "at a key pose");
  app.add_option("--adaptation-lag", options.adaptation_lag,
                 "Steps after which an adaptation computed from the current positions is applied, so that it "
                 "runs beside those steps (0: at once; at most --adapt-every minus 1) [count]")
      ->capture_default_str()->check(CLI::Range(0, 99999));
  app.add_option("--adapt-speed", options.adapt_speed,
                 "At a key pose, adapt once the cloth's largest net vertex speed over a settle check falls below "
                 "this [m/s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-face-growth", options.adaptation.max_face_growth,
                 "A face's rest area is kept within this multiple of its design area (where the body holds the "
                 "cloth, growth cannot relieve the stretch) [1]")
      ->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  app.add_option("--max-area-growth", options.max_area_growth,
                 "A run fails when the rest area exceeds this multiple of the design's (a runaway adaptation) [1]")
      ->capture_default_str()->check(CLI::Range(1.0, 1000.0));
  app.add_option("--settle-speed", options.settle_speed,
                 "Largest net vertex speed of a settled cloth, over each settle check of --adapt-every steps [m/s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--settle-stretch-change", options.settle_stretch_change,
                 "Largest change of the max stretch between settle checks [1]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--settle-max-steps", options.settle_max_steps, "Cap on settling steps at each key pose [count]")
      ->capture_default_str()->check(CLI::Range(0, 10000000));
  app.add_option("--settle-damping", options.settle_damping,
                 "Damping while settling at a key pose, as a fraction of the material's [1]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  app.add_option("--held-steps", options.held_steps,
                 "A key pose whose cloth is stretched beyond --held-stretch and has not improved by 1 % for this "
                 "many settling steps is held by the body: the fit stops there, names the places and proposes "
                 "an opening of the pose (0: settle to the cap) [count]")
      ->capture_default_str()->check(CLI::Range(0, 10000000));
  app.add_option("--held-stretch", options.held_stretch,
                 "Stretch beyond which cloth the body holds counts as torn [1]")
      ->capture_default_str()->check(CLI::Range(1.0, 100.0));
  gp::adapt::OpeningOptions opening_options;
  app.add_option("--open-clearance", opening_options.clearance,
                 "A proposed opening of a held pose leaves at least this many comfort offsets of room where the "
                 "cloth was held [1]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--reach", options.reach, "Body faces farther than this from the garment are culled [m]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--solver", solver,
                 "Linear solver: refactor (a CHOLMOD factor every step, CG with it) or pcg (CG with a reused, "
                 "rotated factor)")
      ->capture_default_str()->check(CLI::IsMember({"pcg", "refactor"}));
  app.add_option("--cg-tolerance", options.solver.cg_tolerance,
                 "Relative residual of the conjugate-gradient solve [1]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  std::string contact = "velocity";
  app.add_option("--contact", contact,
                 "Body contact: velocity (constraints inside the implicit solve, then projection) or "
                 "projection (position projection after the step only)")
      ->capture_default_str()->check(CLI::IsMember({"velocity", "projection"}));
  std::string pinch_gaps = "ray";
  app.add_option("--pinch-gaps", pinch_gaps,
                 "Where two body parts are closer than twice the offset, the cloth keeps half the gap from each: "
                 "the gap along the contact's normal (ray) or to the nearest body surface facing it in any "
                 "direction, never less than the contact thickness (facing)")
      ->capture_default_str()->check(CLI::IsMember({"facing", "ray"}));
  std::string continuous = "on";
  app.add_option("--continuous-contact", continuous,
                 "Intersection-free contact in both directions: body vertices and edges push the cloth out of "
                 "their way and nothing passes through the other surface within a step (on; active when the "
                 "garment starts clear of the body) or cloth vertices against the body only (off)")
      ->capture_default_str()->check(CLI::IsMember({"on", "off"}));
  auto* thickness_option =
      app.add_option("--contact-thickness", options.contact.thickness,
                     "Separation kept between the cloth and body vertices and edges by the continuous contact, and "
                     "the least offset a pinch leaves; default: the garment fabric's thickness, 1 mm where it gives "
                     "none [m]")
          ->check(CLI::PositiveNumber);
  app.add_option("--pin-clearance", options.pin_clearance,
                 "Keep the pinned vertices' targets at least this fraction of the comfort offset from the body in "
                 "every frame, moving them out where another body part rises beside their bound point; 0: they "
                 "follow their binding alone [fraction]")
      ->capture_default_str()->check(CLI::Range(0.0, 1.0));
  std::string hand_hulls = "on";
  app.add_option("--hand-hulls", hand_hulls,
                 "Collide the cloth also with the convex hull of each hand (each thin body part at least "
                 "--hull-min-extent long), so that fingers push the cloth and never hook it (on), or with the "
                 "body's own surface only (off)")
      ->capture_default_str()->check(CLI::IsMember({"on", "off"}));
  app.add_option("--hull-thin", options.contact_surface.thin,
                 "A body vertex is in a thin part when the body along its inward normal is thinner than this [m]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--hull-min-extent", options.contact_surface.min_extent,
                 "Thin parts with a shorter bounding-box diagonal (ears, the nose) keep their own shape [m]")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  // A second thread prepares body frames and adaptations, where the machine
  // has a second core.
  options.threads = std::thread::hardware_concurrency() >= 2 ? 2 : 1;
  app.add_option("--workers", options.threads,
                 "Worker threads of the run: 2 or more prepare the body frames and the lagging adaptations and "
                 "query half the body contacts on a second thread while the cloth steps; 1 runs everything in "
                 "turn. The outputs are the same for any count. Default: 2 where the machine has two cores "
                 "[count]")
      ->capture_default_str()->check(CLI::Range(1, 256));
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    options.adapt = !no_adapt;
    options.adaptation_lag = gp::adapt::applied_adaptation_lag(options);  // recorded as run
    fit_options.verify = !no_verify;
    criteria.require_settled = !allow_unsettled;
    options.velocity_contacts = contact == "velocity";
    options.continuous_contact = continuous == "on";
    options.facing_gaps = pinch_gaps == "facing";
    options.contact_surface.hulls = hand_hulls == "on";
    options.solver.strategy = solver == "pcg" ? gp::cloth::SolverStrategy::pcg_reused_factor
                                              : gp::cloth::SolverStrategy::refactor_every_step;
    const gp::PoseSet poses = gp::load_pose_set(poses_path);
    const gp::MotionSpec motion = gp::read_motion_spec(motion_path, poses);
    // A hand-written manifest bypasses register-check; a pose with vertices
    // thrown away by a registration error would be fitted into the rest shape.
    {
      std::vector<int> used;
      for (const gp::MotionKey& key : motion.keys) used.push_back(key.pose_index);
      gp::check_pose_edge_ratios(poses, used, gp::kDefaultMaxEdgeRatio, poses_path);
    }
    const gp::GarmentFile garment = gp::read_garment_file(garment_path);
    // The cloth's own thickness keeps it off the body (the report records it).
    if (thickness_option->count() == 0) options.contact.thickness = gp::contact_thickness(garment.material);
    const fs::path mesh_path = fs::path(garment_path).parent_path() / garment.mesh_file;
    gp::MeshReadResult read = gp::read_mesh(mesh_path);
    for (const auto& w : read.warnings) tool.log().warning(w);
    if (read.mesh.V.rows() != garment.vertex_count || read.mesh.F.rows() != garment.face_count) {
      throw gp::InputError("garment mesh does not match the garment file's counts", mesh_path.string());
    }
    if (garment.body.vertex_count != 0 && garment.body.vertex_count != static_cast<long long>(poses.V[0].rows())) {
      throw gp::GeometryError("the garment was designed on a body with " +
                                  std::to_string(garment.body.vertex_count) + " vertices, the pose set has " +
                                  std::to_string(poses.V[0].rows()),
                              garment_path);
    }
    const gp::DesignPoseMatch design = gp::match_design_pose(garment, poses);
    if (!design.same && !fit_options.other_body)
      throw gp::GeometryError("pose '" + garment.body.design_pose + "' of the pose set is another body than the "
                              "garment was designed on (its vertex checksum " + design.actual.substr(0, 16) +
                              ", the garment file's " + design.expected.substr(0, 16) +
                              "); pass --other-body to fit it deliberately",
                              poses_path);
    std::optional<gp::CarryToBodyResult> carried;
    if (!design.same) {
      // The garment is put on the new body before it moves: carried with the
      // body where the design body can still be found, and cleared of it.
      Eigen::MatrixXd V_from;
      try {
        const gp::DesignBody from = gp::load_design_body(garment, garment_path, "");
        if (gp::vertex_checksum(from.V) == design.expected) V_from = from.V;
      } catch (const gp::InputError&) {
      }
      carried = gp::carry_to_body(read.mesh.V, read.mesh.F, garment, V_from,
                                  poses.V[static_cast<size_t>(design.pose)], poses.F);
      tool.log().warning("pose '" + garment.body.design_pose + "' is another body than the garment was designed on; "
                         "the garment was " + (carried->carried ? "carried to it and " : "") + "cleared of it (" +
                         (carried->clearance.clear() ? "clear" : "still crossing it") + ") as --other-body asks");
    }
    gp::InterpolationOptions interp_options;
    interp_options.anchor = motion.anchor;
    gp::PoseInterpolator interpolator(poses, interp_options);

    // Progress: a live line on a terminal, plain lines in a log; each key
    // pose's figures as a line of their own.
    gp::adapt::MotionProgressLine progress(options);
    const auto run_start = std::chrono::steady_clock::now();
    const auto progress_callback = [&](const gp::adapt::MotionProgress& p) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
      tool.log().progress(progress.line(p, elapsed), p.key_done);
      if (p.key_done) {
        tool.log().progress_done();
        tool.log().info(p.message);
      } else if (p.settle_steps > 0 ? p.settle_steps % 200 == 0 : p.frame % 20 == 0) {
        tool.log().detail(p.message);  // --verbose: the figures of the moment, now and then
      }
    };
    const gp::adapt::FitResult fit = gp::adapt::fit_garment(interpolator, motion, read.mesh.V, read.mesh.F, garment,
                                                            fit_options, progress_callback);
    tool.log().progress_done();
    const gp::adapt::MotionRunResult& result = fit.run;
    const std::optional<gp::adapt::FitVerification>& verification = fit.verification;
    if (!fit.cycle_error.empty()) {
      tool.log().warning("a further adaptation cycle failed (" + fit.cycle_error +
                         "); the previous cycle's rest shape and its verification are the result");
    }
    if (options.continuous_contact && !result.continuous_contact) {
      const auto& c = result.initial_crossings;
      tool.log().warning("the garment starts through the body (" + std::to_string(c.crossings()) +
                         " edge/triangle crossings, " + std::to_string(c.cloth_vertices_inside) +
                         " vertices inside, " + std::to_string(c.body_vertices_behind) +
                         " body vertices behind it); the continuous contact, which keeps each body part on the "
                         "side of the cloth it starts on, is off for this run");
    }
    for (const auto& k : result.keys) {
      if (k.crossings.intersection_free()) continue;
      tool.log().warning("key pose " + k.pose + ": the cloth passes through the body (" +
                         std::to_string(k.crossings.crossings()) + " edge/triangle crossings, " +
                         std::to_string(k.crossings.cloth_vertices_inside) + " cloth vertices inside, " +
                         std::to_string(k.crossings.body_vertices_behind) + " body vertices behind the cloth)");
    }

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    gp::Mesh rest;
    rest.V = result.V_rest;
    rest.F = read.mesh.F;
    gp::write_mesh(out.file("rest.ply"), rest);
    // A key pose's drape with its largest principal stretch per face.
    auto write_drape = [&](const char* name, const gp::adapt::KeyPoseResult& k) {
      gp::Mesh draped;
      draped.V = k.V_draped;
      draped.F = read.mesh.F;
      draped.face_fields.push_back({"max_stretch", k.face_max_stretch});
      gp::write_mesh(out.file(name), draped);
    };
    const auto held_json = [](const gp::adapt::KeyPoseResult& k) {
      gp::OrderedJson list = gp::OrderedJson::array();
      for (const gp::adapt::HeldCloth& h : k.held_cloth) list.push_back(gp::adapt::to_json(h));
      return list;
    };
    // A pose the body holds: where, and the least opening of it that frees
    // the cloth (adapt/open_pose.h), for make fit's fallback.
    gp::OrderedJson held = nullptr;
    if (result.held_key >= 0) {
      const gp::adapt::KeyPoseResult& k = result.keys[static_cast<size_t>(result.held_key)];
      const int pose = motion.keys[static_cast<size_t>(k.key)].pose_index;
      opening_options.contact_surface = options.contact_surface;
      const gp::adapt::Opening o =
          k.held_cloth.empty() ? gp::adapt::Opening{}
                               : gp::adapt::choose_opening(interpolator, pose, k.held_cloth, garment.offset, opening_options);
      held = {{"key", k.key}, {"pose", k.pose}, {"settle_steps", k.settle_steps}, {"held_cloth", held_json(k)}};
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
    }
    gp::OrderedJson keys = gp::OrderedJson::array();
    for (const auto& k : result.keys) {
      char name[256];
      std::snprintf(name, sizeof(name), "draped_%02d_%s.ply", k.key, k.pose.c_str());
      write_drape(name, k);
      keys.push_back({{"key", k.key},
                      {"pose", k.pose},
                      {"mesh", name},
                      {"max_stretch", k.max_stretch},
                      {"p99_stretch", k.p99_stretch},
                      {"mean_stretch", k.mean_stretch},
                      {"area_fraction_above_limit", k.area_fraction_above},
                      {"deepest_penetration_m", k.deepest_penetration},
                      {"rest_area_growth", k.rest_area_growth},
                      {"rest_area_change_last_window", k.rest_area_change},
                      {"steps", k.steps},
                      {"settle_steps", k.settle_steps},
                      {"settled", k.settled},
                      {"max_speed_m_per_s", k.max_speed},
                      {"max_net_speed_m_per_s", k.max_net_speed},
                      {"crossings", gp::collision::to_json(k.crossings)},
                      {"held_by_body", k.held},
                      {"held_cloth", held_json(k)}});
    }
    gp::OrderedJson verified = nullptr;
    if (verification) {
      gp::OrderedJson poses_json = gp::OrderedJson::array();
      for (const auto& check : verification->poses) {
        const auto& k = check.figures;
        char name[256];
        // Without adaptation the run's own drapes are the fresh simulation.
        std::snprintf(name, sizeof(name), options.adapt ? "verified_%02d_%s.ply" : "draped_%02d_%s.ply", k.key,
                      k.pose.c_str());
        if (options.adapt) write_drape(name, k);
        poses_json.push_back(gp::adapt::to_json(check, name));
      }
      verified = {{"verdict", verification->passed() ? "pass" : "fail"},
                  {"criteria", gp::write_options(criteria, gp::adapt::FitCriteriaFields{})},
                  {"steps", verification->steps},
                  {"rejected_steps", verification->rejected_steps},
                  {"key_poses", poses_json}};
    }
    gp::OrderedJson report;
    report["schema"] = gp::schema_tag("simulate-adapt-report", 1);
    // The fit's options under the keys the sewn-fit check reads them back by
    // (adapt/garment_fit.h), between the inputs and the effective motion.
    report["options"] = {{"poses", poses_path}, {"motion", motion_path}, {"garment", garment_path}};
    report["options"].update(gp::write_options(fit_options, gp::adapt::FitOptionFields{}));
    report["options"]["threads"] = tool.common().threads;
    report["options"]["motion_effective"] = gp::to_json(motion);
    report["options"]["material"] = gp::to_json(garment.material);
    report["options"]["comfort_offset_m"] = garment.offset;
    if (carried) {
      report["other_body"] = {{"design_pose", garment.body.design_pose},
                              {"garment_file_sha256", design.expected},
                              {"pose_set_sha256", design.actual},
                              {"carried_with_body", carried->carried},
                              {"largest_carry_m", carried->carried ? gp::OrderedJson(carried->largest_carry)
                                                                   : gp::OrderedJson(nullptr)},
                              {"clearance", gp::to_json(carried->clearance)}};
    }
    report["counts"] = {{"garment_vertices", read.mesh.V.rows()},
                        {"garment_faces", read.mesh.F.rows()},
                        {"body_vertices", poses.V[0].rows()},
                        {"body_faces", poses.F.rows()},
                        {"body_faces_kept", result.culled_body_faces},
                        {"hull_faces", result.contact_surface.F.rows() - result.contact_surface.body_face_count}};
    gp::OrderedJson hulls = gp::OrderedJson::array();
    for (int h = 0; h < result.contact_surface.hull_count; ++h) {
      const Eigen::Vector3d& c = result.contact_surface.part_centroids[static_cast<size_t>(h)];
      hulls.push_back({{"faces", result.contact_surface.hull_faces[static_cast<size_t>(h)]},
                       {"part_vertices", result.contact_surface.part_vertices[static_cast<size_t>(h)]},
                       {"part_centroid", {c.x(), c.y(), c.z()}}});
    }
    report["hand_hulls"] = hulls;
    report["key_poses"] = keys;
    gp::OrderedJson cycles = gp::OrderedJson::array();
    for (const gp::adapt::FitCycle& c : fit.cycles) {
      cycles.push_back({{"steps", c.steps},
                        {"adaptations", c.adaptations},
                        {"rest_area_growth", c.rest_area_growth},
                        {"verified", c.verified}});
    }
    report["cycles"] = cycles;
    report["held"] = held;
    report["cycle_error"] = fit.cycle_error.empty() ? gp::OrderedJson(nullptr) : gp::OrderedJson(fit.cycle_error);
    report["verification"] = verified;
    report["run"] = {{"steps", result.steps},
                     {"rejected_steps", result.solver.rejected},
                     {"accepted_folds", result.solver.accepted_flips},
                     {"fold_streak_steps", result.solver.fold_streak_steps},
                     {"contact_constraints", result.solver.constraints},
                     {"contact_releases", result.solver.released},
                     {"pinched_contacts", result.collisions.pinched},
                     {"crease_contacts", result.collisions.creases},
                     {"initial_min_distance_m", result.initial_min_distance},
                     {"initial_crossings", gp::collision::to_json(result.initial_crossings)},
                     {"continuous_contact_active", result.continuous_contact},
                     {"pin_targets_moved", result.pins.pushed},
                     {"largest_pin_move_m", result.pins.largest_push},
                     {"closest_pin_target_m", result.pins.pushed ? gp::OrderedJson(result.pins.closest_before)
                                                                 : gp::OrderedJson(nullptr)},
                     {"adaptations", result.adaptations},
                     {"arap_converged", result.arap.converged},
                     {"all_settled", result.all_settled},
                     {"rest_area_growth", result.keys.empty() ? 1.0 : result.keys.back().rest_area_growth}};
    // Timings differ between runs, so they live apart from the report.
    const auto& t = result.times;
    const double per_step = result.steps > 0 ? 1e3 / result.steps : 0.0;
    gp::OrderedJson timing;
    timing["schema"] = gp::schema_tag("timing", 1);
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
    const gp::cloth::RejectionCounts& rc = result.solver.rejections;
    gp::OrderedJson faces = gp::OrderedJson::array();
    for (const auto& [face, count] : gp::cloth::most_inverted_faces(result.solver, 10)) {
      faces.push_back({{"face", face}, {"rejections", count}});
    }
    timing["rejections"] = {{"total", result.solver.rejected},
                            {"inverted_triangle", rc.inverted},
                            {"too_fast", rc.too_fast},
                            {"energy_growth", rc.energy_growth},
                            {"non_finite", rc.non_finite},
                            {"solve_failed", rc.solve_failed},
                            {"most_inverted_faces", faces}};
    timing["verification_s"] = verification ? verification->seconds : 0.0;
    timing["threads"] = tool.common().threads;
    timing["workers"] = options.threads;
    timing["setup_s"] = t.setup;
    timing["run_s"] = t.total;
    timing["total_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::write_json_file(out.file("timing.json"), timing);
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    tool.log().info("wrote " + tool.common().out_dir + " (" + std::to_string(result.keys.size()) + " key poses, " +
                    std::to_string(result.steps) + " steps)");
    if (!held.is_null()) {
      const gp::adapt::KeyPoseResult& k = result.keys[static_cast<size_t>(result.held_key)];
      std::string what = gp::adapt::check_pose(k, options.adaptation.delta, criteria).front();
      if (!held["open_suggestion"].is_null()) {
        const auto& o = held["open_suggestion"];
        char line[256];
        std::snprintf(line, sizeof(line), "; opening it 1/%d towards %s frees it (%.0f mm of room, the body moves "
                      "%.0f mm at most)", o["steps"].get<int>(), o["toward"].get<std::string>().c_str(),
                      o["smallest_gap_mm"].get<double>(), o["largest_body_displacement_mm"].get<double>());
        what += line;
      }
      tool.log().error(gp::ExitCode::check_failed, "key pose " + std::to_string(k.key) + " (" + k.pose + "): " + what);
      return static_cast<int>(gp::ExitCode::check_failed);
    }
    if (verification && !verification->passed()) {
      for (const auto& check : verification->poses) {
        if (check.passed()) continue;
        tool.log().error(gp::ExitCode::check_failed, "the verification fails at key pose " +
                                                         std::to_string(check.figures.key) + " (" +
                                                         check.figures.pose + "): " + check.failures.front());
        break;
      }
      return static_cast<int>(gp::ExitCode::check_failed);
    }
    return 0;
  });
}
