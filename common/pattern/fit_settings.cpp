#include "pattern/fit_settings.h"

#include <vector>

#include "core/error.h"
#include "spec/json_file.h"
#include "spec/spec_object.h"

namespace gp {

FitSettings read_fit_settings(const std::filesystem::path& report) {
  const std::string file = report.string();
  const Json root = read_json_file(report);
  check_schema(root, "simulate-adapt-report", {1}, file);
  FitSettings s;
  s.report = file;
  // A report, not a spec: only the fields that shape the simulation are
  // read, the others (figures, effective motion) are left alone.
  const SpecObject o = SpecObject(root, file).object("options");
  auto required_choice = [&o](const std::string& key, const std::vector<std::string>& choices) {
    if (!o.raw(key)) throw SpecError("missing field", o.where(key));
    return o.choice(key, choices.front(), choices);
  };
  s.poses = o.required_string("poses");
  s.motion = o.required_string("motion");
  adapt::MotionRunOptions& r = s.run;
  r.adapt = false;
  r.solver.dt = o.required_number("dt_s", Range::positive());
  r.substeps = static_cast<int>(o.required_integer("substeps", Range::between(1, 1e6)));
  r.adaptation.delta = o.required_number("delta", Range::non_negative());
  r.settle_speed = o.required_number("settle_speed_m_per_s", Range::positive());
  r.settle_stretch_change = o.required_number("settle_stretch_change", Range::non_negative());
  r.settle_max_steps = static_cast<int>(o.required_integer("settle_max_steps", Range::between(0, 1e9)));
  r.settle_damping = o.required_number("settle_damping", Range::between(0.0, 1.0));
  r.reach = o.required_number("reach_m", Range::non_negative());
  r.velocity_contacts = required_choice("contact", {"velocity", "projection"}) == "velocity";
  r.contact_band = o.required_number("contact_band_m", Range::non_negative());
  r.continuous_contact = required_choice("continuous_contact", {"on", "off"}) == "on";
  r.contact.thickness = o.required_number("contact_thickness_m", Range::positive());
  r.contact_surface.hulls = required_choice("hand_hulls", {"on", "off"}) == "on";
  r.contact_surface.thin = o.required_number("hull_thin_m", Range::positive());
  r.contact_surface.min_extent = o.required_number("hull_min_extent_m", Range::non_negative());
  r.initial_push_speed = o.required_number("initial_push_speed_m_per_s", Range::positive());
  r.solver.contact_release_fraction = o.required_number("contact_release_fraction", Range::non_negative());
  const std::string solver = required_choice("solver", {"refactor_every_step", "pcg_reused_factor", "pcg_jacobi"});
  r.solver.strategy = solver == "pcg_reused_factor" ? cloth::SolverStrategy::pcg_reused_factor
                      : solver == "pcg_jacobi"      ? cloth::SolverStrategy::pcg_jacobi
                                                    : cloth::SolverStrategy::refactor_every_step;
  r.solver.cg_tolerance = o.required_number("cg_tolerance", Range::positive());
  r.solver.cg_max_iterations = static_cast<int>(o.required_integer("cg_max_iterations", Range::between(1, 1e9)));
  r.solver.fresh_factor_max_iterations =
      static_cast<int>(o.required_integer("fresh_factor_max_iterations", Range::between(1, 1e9)));
  r.solver.factorization_cost = o.required_number("factorization_cost", Range::non_negative());
  if (!o.raw("warp_preconditioner")) throw SpecError("missing field", o.where("warp_preconditioner"));
  r.solver.warp_preconditioner = o.boolean("warp_preconditioner", true);
  // The verification's bounds; a fit run with --no-verify has none.
  const Json* v = root.contains("verification") ? &root.at("verification") : nullptr;
  if (v && v->is_object()) {
    const SpecObject c = SpecObject(root, file).object("verification").object("criteria");
    s.criteria.max_area_above = c.required_number("max_area_fraction_above_limit", Range::between(0.0, 1.0));
    s.criteria.p99_margin = c.required_number("p99_margin", Range::non_negative());
    s.criteria.max_penetration = c.required_number("max_penetration_m", Range::non_negative());
    s.criteria.max_crossings = c.required_integer("max_crossings", Range::non_negative());
  }
  return s;
}

}  // namespace gp
