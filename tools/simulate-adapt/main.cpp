// simulate-adapt: simulates the garment on the body moving through a motion's
// key poses and adapts its rest shape wherever the cloth stretches more than
// 1 + delta (Wolff et al. 2023); --no-adapt evaluates the fixed design instead.
// Writes rest.ply, draped_<k>_<pose>.ply (face field max_stretch), timing.json
// and report.json (written last) into --out (adapt/simulate_report.h).
#include <chrono>

#include "adapt/fit_inputs.h"
#include "adapt/garment_fit.h"
#include "adapt/motion_cli.h"
#include "adapt/motion_progress.h"
#include "adapt/simulate_report.h"
#include "cli/tool.h"
#include "core/atomic_file.h"
#include "io/mesh_io.h"

int main(int argc, char** argv) {
  gp::Tool tool("simulate-adapt", "Simulate a garment on the moving body and adapt its rest shape");
  std::string poses_path, motion_path, garment_path;
  gp::adapt::FitOptions fit_options;
  gp::adapt::MotionRunOptions& options = fit_options.motion;
  gp::adapt::FitCriteria& criteria = fit_options.criteria;
  bool no_adapt = false, no_verify = false, allow_unsettled = false;
  auto& app = tool.app();
  // A number or a choice, with its default shown by --help.
  const auto option = [&app](const char* name, auto& value, const CLI::Validator& check, const char* help) {
    app.add_option(name, value, help)->capture_default_str()->check(check);
  };
  app.add_option("--poses", poses_path, "Pose set manifest (poses.json, pose-set/1)")->required();
  app.add_option("--motion", motion_path, "Motion spec (motion/1): key poses and frames per transition")->required();
  app.add_option("--garment", garment_path, "Garment file (garment.json, garment/1); its mesh sits beside "
                 "it")->required();
  app.add_flag("--no-adapt", no_adapt, "Keep the rest shape fixed (evaluate a single-pose design)");
  app.add_flag("--other-body", fit_options.other_body, "Fit the garment to a pose set whose design pose is another "
               "body than the one it was designed on (by default that is refused, exit 5)");
  app.add_flag("--no-verify", no_verify, "Skip the verification pass (the final rest shape simulated afresh through "
               "the motion without adaptation; a failing key pose exits 8) and adapt in one cycle");
  option("--cycles", fit_options.max_cycles, CLI::Range(1, 100), "Adaptation cycles at most: another cycle through "
         "the motion, from the garment as designed with the rest shape so far, while the verification fails [count]");
  option("--verify-frame-stride", fit_options.frame_stride, CLI::Range(0, 1000000), "Verification: also solve every "
         "n-th in-between frame of each transition to its static equilibrium and judge it by the key poses' bounds; a "
         "further cycle adapts at the frames that fail (0: the key poses only) [frames]");
  option("--verify-max-area", criteria.max_area_above, CLI::Range(0.0, 1.0), "Verification: a key pose fails when "
         "this fraction of the area or more is stretched above 1+delta [1]");
  option("--verify-p99-margin", criteria.p99_margin, CLI::NonNegativeNumber, "Verification: a key pose fails when its "
         "p99 stretch exceeds 1+delta plus this [1]");
  option("--verify-max-penetration", criteria.max_penetration, CLI::NonNegativeNumber, "Verification: a key pose "
         "fails when a cloth vertex lies deeper inside the body [m]");
  option("--verify-max-crossings", criteria.max_crossings, CLI::NonNegativeNumber, "Verification: a key pose fails "
         "when more body edges pass through cloth triangles and cloth edges through body triangles [count]");
  option("--verify-tear-stretch", criteria.tear_stretch, CLI::Range(1.0, 100.0), "Verification: cloth stretched "
         "beyond this would tear [ratio]");
  option("--verify-max-torn-area", criteria.max_torn_area, CLI::Range(0.0, 1.0), "Verification: a key pose fails when "
         "more than this fraction of the area is stretched beyond the tear stretch [1]");
  app.add_flag("--verify-allow-unsettled", allow_unsettled, "Verification: judge a key pose whose cloth still moves "
               "at the settle cap by its figures alone (by default such a pose fails: its figures are a snapshot of "
               "moving cloth)");
  option("--dt", options.solver.dt, CLI::PositiveNumber, "Simulation time step [s]");
  option("--substeps", options.schedule.substeps, CLI::Range(1, 1000), "Simulation steps per interpolation frame [count]");
  option("--adapt-every", options.adaptation.every, CLI::Range(1, 100000), "Simulation steps between adaptations [count]");
  option("--delta", options.adaptation.adapter.delta, CLI::Range(0.0, 10.0), "Stretch limit of the fit: the verification "
         "fails cloth above 1+delta; the adaptation clips below it (see --margin) [1]");
  option("--margin", options.adaptation.adapter.margin, CLI::Range(0.0, 1.0), "The adaptation clips stretch at "
         "1+delta-margin, below the fit's limit, so that a fresh simulation of the rest shape stays within 1+delta "
         "(0: the paper's rule at 1+delta) [1]");
  option("--hysteresis", options.adaptation.adapter.hysteresis, CLI::Range(0.0, 1.0), "A face stretched beyond 1+delta-margin "
         "is clipped to 1+delta-margin-hysteresis, so that cloth the body holds stretched is not adapted again at "
         "every hair above the limit [1]");
  option("--arap-tolerance", options.adaptation.adapter.arap.tolerance, CLI::PositiveNumber, "ARAP stitching tolerance: "
         "largest edge-length change per iteration / mean edge length [1]");
  option("--arap-stretch-tolerance", options.adaptation.adapter.arap.stretch_tolerance, CLI::NonNegativeNumber, "ARAP "
         "stitching stops instead when no face's principal stretch changes by more than this in one iteration (0: the "
         "edge rule of --arap-tolerance) [1]");
  option("--smoothing-length", options.adaptation.adapter.smoothing_length, CLI::NonNegativeNumber, "The rest shape's "
         "stitching resists changes of its form shorter than this, so that growth makes smooth bulges rather than "
         "tucks (0: plain ARAP) [m]");
  option("--adapt-rounds", options.adaptation.adapter.rounds, CLI::Range(1, 100), "Clip-and-stitch rounds per adaptation "
         "against the same cloth positions [count]");
  app.add_flag("--adapt-during-transitions", options.adaptation.during_transitions, "Adapt also while the body moves "
               "between key poses (the paper), not only while the cloth settles at a key pose");
  option("--adaptation-lag", options.schedule.adaptation_lag, CLI::Range(0, 99999), "Steps after which an adaptation computed "
         "from the current positions is applied, so that it runs beside those steps (0: at once; at most "
         "--adapt-every minus 1) [count]");
  option("--adapt-speed", options.adaptation.speed, CLI::PositiveNumber, "At a key pose, adapt once the cloth's largest "
         "net vertex speed over a settle check falls below this [m/s]");
  option("--max-face-growth", options.adaptation.adapter.max_face_growth, CLI::Range(1.0, 1000.0), "A face's rest area is "
         "kept within this multiple of its design area (where the body holds the cloth, growth cannot relieve the "
         "stretch) [1]");
  option("--max-area-growth", options.adaptation.max_area_growth, CLI::Range(1.0, 1000.0), "A run fails when the rest area "
         "exceeds this multiple of the design's (a runaway adaptation) [1]");
  option("--settle-speed", options.settle.speed, CLI::PositiveNumber, "Largest net vertex speed of a settled cloth, "
         "over each settle check of --adapt-every steps [m/s]");
  option("--settle-stretch-change", options.settle.stretch_change, CLI::PositiveNumber, "Largest change of the max "
         "stretch between settle checks [1]");
  option("--settle-max-steps", options.settle.max_steps, CLI::Range(0, 10000000), "Cap on settling steps at each key "
         "pose [count]");
  option("--settle-damping", options.settle.damping, CLI::Range(0.0, 1.0), "Damping while settling at a key pose, as "
         "a fraction of the material's [1]");
  option("--held-steps", options.settle.held_steps, CLI::Range(0, 10000000), "A key pose whose cloth is stretched beyond "
         "--held-stretch and has not improved by 1 % for this many settling steps is held by the body: the fit stops "
         "there, names the places and proposes an opening of the pose (0: settle to the cap) [count]");
  option("--held-stretch", options.settle.held_stretch, CLI::Range(1.0, 100.0), "Stretch beyond which cloth the body holds "
         "counts as torn [1]");
  gp::adapt::OpeningOptions opening_options;
  option("--open-clearance", opening_options.clearance, CLI::PositiveNumber, "A proposed opening of a held pose "
         "leaves at least this many comfort offsets of room where the cloth was held [1]");
  gp::adapt::MotionChoices choices;
  gp::adapt::add_solver_and_contact_options(app, options, choices);

  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    options.adaptation.enabled = !no_adapt;
    options.schedule.adaptation_lag = gp::adapt::applied_adaptation_lag(options);  // recorded as run
    fit_options.verify = !no_verify;
    criteria.require_settled = !allow_unsettled;
    gp::adapt::apply_choices(choices, options);
    const auto in = gp::adapt::read_fit_inputs(poses_path, motion_path, garment_path, fit_options.other_body);
    for (const std::string& w : in.warnings) tool.log().warning(w);
    // The cloth's own thickness keeps it off the body (the report records it).
    if (!choices.thickness_given()) options.contact.sweep.thickness = gp::contact_thickness(in.garment.material);
    gp::PoseInterpolator interpolator(in.poses, {gp::InterpolationMethod::nonlinear, in.motion.anchor});

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
    const gp::adapt::FitResult fit = gp::adapt::fit_garment(interpolator, in.motion, in.mesh.V, in.mesh.F,
                                                            in.garment, fit_options, progress_callback);
    tool.log().progress_done();
    for (const std::string& w : gp::adapt::fit_warnings(fit, options)) tool.log().warning(w);

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    for (const auto& [name, mesh] : gp::adapt::fit_meshes(fit, in.mesh.F, options.adaptation.enabled)) {
      gp::write_mesh(out.file(name), mesh);
    }
    const gp::OrderedJson report = gp::adapt::simulate_report(
        {poses_path, motion_path, garment_path, tool.common().threads}, in, fit_options, fit,
        gp::adapt::held_json(fit, in.motion, interpolator, in.garment, options, opening_options));
    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::write_json_file(out.file("timing.json"), gp::adapt::simulate_timing(fit, tool.common().threads,
                                                                            options.schedule.threads, total_s));
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    tool.log().info("wrote " + tool.common().out_dir + " (" + std::to_string(fit.run.keys.size()) + " key poses, " +
                    std::to_string(fit.run.steps) + " steps)");
    if (const auto failure = gp::adapt::fit_failure(fit, report["held"], fit_options)) {
      tool.log().error(gp::ExitCode::check_failed, *failure);
      return static_cast<int>(gp::ExitCode::check_failed);
    }
    return 0;
  });
}
