#include "adapt/motion_cli.h"

#include <thread>

namespace gp::adapt {

void add_solver_and_contact_options(CLI::App& app, MotionRunOptions& options, MotionChoices& c) {
  // A number or a choice, with its default shown by --help.
  const auto option = [&app](const char* name, auto& value, const CLI::Validator& check, const char* help) {
    app.add_option(name, value, help)->capture_default_str()->check(check);
  };
  option("--solver", c.equilibrium, CLI::IsMember({"static", "dynamic"}), "How a key pose reaches its rest state: "
         "dynamic (damped time steps until the cloth is slow, the --settle options) or static (its equilibrium "
         "solved by Newton's method with contact as a barrier or an active set, --static-contact, to --static-tolerance, the rest shape adapted every "
         "--adapt-every iterations; it keeps every cloth vertex out of the body but not yet every body edge out of "
         "the cloth, see adapt/README.md). The transitions are time-stepped either way");
  option("--static-tolerance", options.settle.statics.tolerance, CLI::PositiveNumber, "Static solve: force residual of an "
         "equilibrium, the RMS unbalanced force per free vertex in mean vertex weights [1]");
  option("--static-max-iterations", options.settle.statics.max_iterations, CLI::Range(1, 10000000), "Static solve: Newton "
         "iterations at most at one key pose, adaptations included [count]");
  option("--static-adapt-displacement", options.settle.statics.adapt_displacement, CLI::PositiveNumber, "Static solve with "
         "adaptation: the rest shape is adapted every --adapt-every iterations once no vertex moved more than this "
         "over the last of them [m]");
  option("--static-held-iterations", options.settle.statics.held_iterations, CLI::Range(1, 10000000), "Static solve: cloth "
         "stretched beyond --held-stretch whose largest stretch has not fallen by 1 % for this many iterations is "
         "held by the body [count]");
  option("--barrier-pressure", options.settle.statics.barrier_pressure, CLI::PositiveNumber, "Static solve: stiffness of "
         "the contact barrier, about the contact pressure at half its band [Pa]");
  option("--barrier-band", options.settle.statics.barrier_band, CLI::PositiveNumber, "Static solve: width of the band, "
         "centred on the comfort offset, where the contact barrier acts [m]");
  option("--static-max-displacement", options.settle.statics.max_displacement, CLI::PositiveNumber, "Static solve: largest "
         "move of a vertex near the body in one iteration, so that no step passes through a body part [m]");
  option("--static-contact", c.static_contact, CLI::IsMember({"barrier", "active_set"}), "Static solve: how the cloth "
         "meets the body: barrier (a barrier on the distance to the body, --barrier-pressure and --barrier-band) or "
         "active_set (a vertex at its comfort offset is held there along the body's normal in the Newton step, "
         "free along the body, and released when its contact force pulls it towards the body by more than "
         "--static-release-force)");
  option("--static-release-force", options.settle.statics.release_force, CLI::NonNegativeNumber, "Static solve with "
         "--static-contact active_set: a held vertex is released when the body would have to pull it by more than "
         "this [mean vertex weights]");
  option("--reach", options.contact.reach, CLI::NonNegativeNumber, "Body faces farther than this from the garment are culled "
         "[m]");
  option("--linear-solver", c.linear_solver, CLI::IsMember({"pcg", "refactor"}), "Linear solver of the time steps (and of the static solve, which always factors afresh): refactor (a CHOLMOD factor every "
         "step, CG with it) or pcg (CG with a reused, rotated factor)");
  option("--cg-tolerance", options.solver.cg_tolerance, CLI::PositiveNumber, "Relative residual of the "
         "conjugate-gradient solve [1]");
  option("--contact", c.contact, CLI::IsMember({"velocity", "projection"}), "Body contact: velocity (constraints inside "
         "the implicit solve, then projection) or projection (position projection after the step only)");
  option("--pinch-gaps", c.pinch_gaps, CLI::IsMember({"facing", "ray"}), "Where two body parts are closer than twice "
         "the offset, the cloth keeps half the gap from each: the gap along the contact's normal (ray) or to the "
         "nearest body surface facing it in any direction, never less than the contact thickness (facing)");
  option("--continuous-contact", c.continuous, CLI::IsMember({"on", "off"}), "Intersection-free contact in both "
         "directions: body vertices and edges push the cloth out of their way and nothing passes through the other "
         "surface within a step (on; active when the garment starts clear of the body) or cloth vertices against the "
         "body only (off)");
  c.thickness = app.add_option("--contact-thickness", options.contact.sweep.thickness, "Separation kept between "
         "the cloth and body vertices and edges by the continuous contact, and the least offset a pinch leaves; "
         "default: the garment fabric's thickness, 1 mm where it gives none [m]")->check(CLI::PositiveNumber);
  option("--pin-clearance", options.contact.pin_clearance, CLI::Range(0.0, 1.0), "Keep the pinned vertices' targets at least "
         "this fraction of the comfort offset from the body in every frame, moving them out where another body part "
         "rises beside their bound point; 0: they follow their binding alone [fraction]");
  option("--hand-hulls", c.hand_hulls, CLI::IsMember({"on", "off"}), "Collide the cloth also with the convex hull of "
         "each hand (each thin body part at least --hull-min-extent long), so that fingers push the cloth and never "
         "hook it (on), or with the body's own surface only (off)");
  option("--hull-thin", options.contact.surface.thin, CLI::PositiveNumber, "A body vertex is in a thin part when the "
         "body along its inward normal is thinner than this [m]");
  option("--hull-min-extent", options.contact.surface.min_extent, CLI::NonNegativeNumber, "Thin parts with a shorter "
         "bounding-box diagonal (ears, the nose) keep their own shape [m]");
  // A second thread prepares body frames and adaptations, where the machine
  // has a second core.
  options.schedule.threads = std::thread::hardware_concurrency() >= 2 ? 2 : 1;
  option("--workers", options.schedule.threads, CLI::Range(1, 256), "Worker threads of the run: 2 or more prepare the body "
         "frames and the lagging adaptations and query half the body contacts on a second thread while the cloth "
         "steps; 1 runs everything in turn. The outputs are the same for any count. Default: 2 where the machine has "
         "two cores [count]");

}

void apply_choices(const MotionChoices& c, MotionRunOptions& options) {
  options.settle.equilibrium = c.equilibrium == "dynamic" ? Equilibrium::dynamic : Equilibrium::static_solve;
  options.settle.statics.contact =
      c.static_contact == "active_set" ? cloth::StaticContact::active_set : cloth::StaticContact::barrier;
  options.contact.velocity_constraints = c.contact == "velocity";
  options.contact.continuous = c.continuous == "on";
  options.contact.facing_gaps = c.pinch_gaps == "facing";
  options.contact.surface.hulls = c.hand_hulls == "on";
  options.solver.strategy =
      c.linear_solver == "pcg" ? cloth::SolverStrategy::pcg_reused_factor : cloth::SolverStrategy::refactor_every_step;
}

}  // namespace gp::adapt
