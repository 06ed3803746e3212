#include "export/fit_settings.h"

#include "adapt/garment_fit.h"
#include "core/error.h"
#include "spec/json_file.h"
#include "spec/option_fields.h"
#include "spec/spec_object.h"

namespace gp {

FitSettings read_fit_settings(const std::filesystem::path& report) {
  const std::string file = report.string();
  const Json root = read_json_file(report);
  check_schema(root, "simulate-adapt-report", {1}, file);
  FitSettings s;
  s.report = file;
  // A report, not a spec: the fit's options are read strictly by the list
  // that wrote them (adapt::FitOptionFields); the inputs and the effective
  // motion beside them are left alone.
  const SpecObject o = SpecObject(root, file).object("options");
  s.poses = o.required_string("poses");
  s.motion = o.required_string("motion");
  adapt::FitOptions fit;
  read_options(o, true, fit, adapt::FitOptionFields{});
  s.run = fit.motion;
  s.frame_stride = fit.frame_stride;
  s.run.adaptation.enabled = false;
  s.run.schedule.threads = 1;
  // The verification's bounds; a fit run with --no-verify has none.
  const Json* v = root.contains("verification") ? &root.at("verification") : nullptr;
  if (v && v->is_object()) {
    const SpecObject c = SpecObject(root, file).object("verification").object("criteria");
    read_options(c, true, s.criteria, adapt::FitCriteriaFields{});
    // The drapes the fit verified its rest shape by: the sewn garment's
    // drapes are compared with these (sewn_fit.h, compare_with_verified).
    const SpecObject vo = SpecObject(root, file).object("verification");
    if (vo.has("key_poses")) {
      const SpecArray keys = vo.array("key_poses");
      for (size_t i = 0; i < keys.size(); ++i) {
        const SpecObject k = keys.object(i);
        FitSettings::VerifiedDrape d;
        d.key = static_cast<int>(k.required_integer("key", Range::non_negative()));
        d.pose = k.required_string("pose");
        d.mesh = k.required_string("mesh");
        d.path = report.parent_path() / d.mesh;
        s.verified.push_back(d);
      }
    }
  }
  return s;
}

}  // namespace gp
