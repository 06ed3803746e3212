#include "report/fit_run.h"

#include "core/error.h"
#include "core/sha256.h"
#include "spec/spec_object.h"

namespace fs = std::filesystem;

namespace gp::report {
namespace {

StageReport read_stage(const fs::path& dir, const std::string& stage, const std::string& schema) {
  StageReport r;
  r.stage = stage;
  r.file = stage + "/report.json";
  r.path = dir / stage / "report.json";
  if (!fs::is_regular_file(r.path))
    throw InputError("missing " + stage + "/report.json: has the " + stage + " stage run?", r.path.string());
  r.json = read_json_file(r.path);
  check_schema(r.json, schema, {1}, r.path.string());
  const fs::path timing = dir / stage / "timing.json";
  if (fs::is_regular_file(timing)) r.timing = read_json_file(timing);
  return r;
}

std::optional<StageReport> read_optional_stage(const fs::path& dir, const std::string& stage,
                                               const std::string& schema) {
  if (!fs::exists(dir / stage)) return std::nullopt;
  return read_stage(dir, stage, schema);
}

fs::path require_file(const fs::path& path) {
  if (!fs::is_regular_file(path)) throw InputError("missing file", path.string());
  return path;
}

std::vector<KeyPoseRun> read_keys(const StageReport& fit, const fs::path& folder) {
  const Json& keys = require(fit, "/key_poses", "array");
  if (keys.empty()) throw SpecError("no key poses", fit.path.string() + ": /key_poses");
  std::vector<KeyPoseRun> out;
  for (size_t i = 0; i < keys.size(); ++i) {
    const std::string p = "/key_poses/" + std::to_string(i);
    KeyPoseRun k;
    k.pointer = p;
    k.key = require(fit, p + "/key", "integer").get<int>();
    k.pose = require(fit, p + "/pose", "string").get<std::string>();
    k.mesh = require_file(folder / require(fit, p + "/mesh", "string").get<std::string>());
    for (const char* number : {"max_stretch", "p99_stretch", "mean_stretch", "area_fraction_above_limit",
                               "deepest_penetration_m", "rest_area_growth"})
      require(fit, p + "/" + number, "number");
    require(fit, p + "/steps", "integer");
    require(fit, p + "/settle_steps", "integer");
    require(fit, p + "/settled", "boolean");
    const std::string v = "/verification/key_poses/" + std::to_string(i);
    if (const Json* entry = lookup(fit, v); entry && entry->is_object() && entry->contains("mesh")) {
      k.verified_pointer = v;
      k.verified_mesh = require_file(folder / require(fit, v + "/mesh", "string").get<std::string>());
      for (const char* number : {"max_stretch", "p99_stretch", "area_fraction_above_limit"})
        require(fit, v + "/" + number, "number");
    }
    out.push_back(k);
  }
  return out;
}

}  // namespace

const Json* lookup(const StageReport& report, const std::string& pointer) {
  try {
    const Json::json_pointer p(pointer);
    if (!report.json.contains(p)) return nullptr;
    return &report.json.at(p);
  } catch (const Json::exception&) {
    return nullptr;  // a malformed pointer or one through a non-container
  }
}

const Json& require(const StageReport& report, const std::string& pointer, const std::string& kind) {
  const std::string where = report.path.string() + ": " + pointer;
  const Json* v = lookup(report, pointer);
  if (!v) throw SpecError("missing required field", where);
  const bool ok = kind == "number"    ? v->is_number()
                  : kind == "integer" ? v->is_number_integer()
                  : kind == "boolean" ? v->is_boolean()
                  : kind == "string"  ? v->is_string()
                  : kind == "object"  ? v->is_object()
                  : kind == "array"   ? v->is_array()
                  : kind == "any"     ? true
                                      : false;
  if (!ok) throw SpecError("expected " + kind + ", found " + json_type_name(*v), where);
  return *v;
}

// The opening was make fit's fallback when fit-held/ (the held run's
// simulate-adapt report) proposed exactly it.
void mark_automatic(const fs::path& dir, OpenedPose& opened) {
  const std::optional<StageReport> held = read_optional_stage(dir, "fit-held", "simulate-adapt-report");
  if (!held) return;
  const Json* o = lookup(*held, "/held/open_suggestion");
  if (!o || !o->is_object() || o->value("pose", "") != opened.pose || o->value("toward", "") != opened.toward ||
      o->value("steps", 0LL) != opened.steps)
    return;
  opened.automatic = true;
  opened.largest_displacement_mm = o->value("largest_body_displacement_mm", 0.0);
  const Json* where = lookup(*held, "/held/held_cloth/0/region");
  if (where && where->is_string()) opened.held_at = where->get<std::string>();
}

std::optional<OpenedPose> read_opened_stage(const fs::path& dir, const fs::path& poses_manifest) {
  const std::optional<StageReport> stage = read_optional_stage(dir, "opened", "interp-poses-report");
  if (!stage) return std::nullopt;
  OpenedPose opened;
  opened.pose = require(*stage, "/motion/sequence/0/pose", "string").get<std::string>();
  opened.toward = require(*stage, "/motion/sequence/1/pose", "string").get<std::string>();
  opened.steps = require(*stage, "/motion/steps", "integer").get<long long>();
  const fs::path file = dir / "opened" / "poses" / (opened.pose + ".ply");
  if (!fs::is_regular_file(file)) return std::nullopt;
  const Json manifest = read_json_file(poses_manifest);
  for (const Json& p : manifest.value("poses", Json::array()))
    if (p.value("name", "") == opened.pose) {
      if (p.value("sha256", "") != sha256_file_hex(file)) return std::nullopt;
      mark_automatic(dir, opened);
      return opened;
    }
  return std::nullopt;
}

std::optional<HeldPose> read_held(const StageReport& stage, const fs::path& dir, const fs::path& poses_manifest) {
  const Json* h = lookup(stage, "/held");
  if (!h || h->is_null()) return std::nullopt;
  HeldPose held;
  held.folder = stage.stage;
  held.key = require(stage, "/held/key", "integer").get<int>();
  held.pose = require(stage, "/held/pose", "string").get<std::string>();
  held.settle_steps = require(stage, "/held/settle_steps", "integer").get<long long>();
  const Json& keys = require(stage, "/key_poses", "array");
  for (size_t i = 0; i < keys.size(); ++i)
    if (keys[i].value("key", -1) == held.key)
      held.drape = require_file(dir / stage.stage /
                                require(stage, "/key_poses/" + std::to_string(i) + "/mesh", "string").get<std::string>());
  if (held.drape.empty()) throw SpecError("the held key pose has no entry in /key_poses", stage.path.string() + ": /held/key");
  held.rest = require_file(dir / stage.stage / "rest.ply");
  if (stage.stage == "fit") {
    const Json manifest = read_json_file(poses_manifest);
    for (const Json& p : manifest.value("poses", Json::array()))
      if (p.value("name", "") == held.pose) held.body = poses_manifest.parent_path() / p.value("file", "");
  } else if (const fs::path body = dir / stage.stage / ("body_" + held.pose + ".ply"); fs::is_regular_file(body)) {
    held.body = body;
  }
  const Json& patches = require(stage, "/held/held_cloth", "array");
  for (size_t i = 0; i < patches.size(); ++i) {
    const std::string p = "/held/held_cloth/" + std::to_string(i);
    HeldPatch patch;
    patch.region = require(stage, p + "/region", "string").get<std::string>();
    const Json& x = require(stage, p + "/position_m", "array");
    if (x.size() != 3 || !x[0].is_number() || !x[1].is_number() || !x[2].is_number())
      throw SpecError("expected 3 numbers", stage.path.string() + ": " + p + "/position_m");
    for (int c = 0; c < 3; ++c) patch.position[static_cast<size_t>(c)] = x[static_cast<size_t>(c)].get<double>();
    const Json& gap = require(stage, p + "/gap_mm", "any");
    patch.gap_mm = gap.is_number() ? gap.get<double>() : -1.0;
    patch.max_stretch = require(stage, p + "/max_stretch", "number").get<double>();
    for (const Json& f : require(stage, p + "/faces", "array")) {
      if (!f.is_number_integer()) throw SpecError("expected face ids", stage.path.string() + ": " + p + "/faces");
      patch.faces.push_back(f.get<int>());
    }
    held.patches.push_back(std::move(patch));
  }
  return held;
}

std::vector<const StageReport*> FitRun::stages() const {
  std::vector<const StageReport*> out;
  if (body) out.push_back(&*body);
  out.push_back(&poses);
  out.push_back(&garment);
  if (extended) out.push_back(&*extended);
  out.push_back(&fit);
  if (fit_no_adapt) out.push_back(&*fit_no_adapt);
  out.push_back(&pattern);
  if (marker) out.push_back(&*marker);
  return out;
}

FitRun read_fit_run(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw InputError("no such fit folder", dir.string());
  FitRun run;
  run.dir = dir;
  run.body = read_optional_stage(dir, "body", "make-avatar-report");
  run.poses = read_stage(dir, "poses", "register-check-report");
  run.garment = read_stage(dir, "garment", "make-garment-report");
  run.extended = read_optional_stage(dir, "extended", "extend-boundary-report");
  run.fit = read_stage(dir, "fit", "simulate-adapt-report");
  run.fit_no_adapt = read_optional_stage(dir, "fit-noadapt", "simulate-adapt-report");
  run.pattern = read_stage(dir, "pattern", "export-rest-report");
  run.marker = read_optional_stage(dir, "marker", "make-marker-report");
  if (run.marker) {
    for (const char* p : {"/length", "/utilisation", "/fabric_width"}) require(*run.marker, p, "number");
    require(*run.marker, "/pieces", "integer");
    require_file(dir / "marker" / "marker.svg");
  }

  require(run.poses, "/verdict", "string");
  run.poses_manifest = require_file(dir / "poses" / "poses.json");
  run.opened = read_opened_stage(dir, run.poses_manifest);
  const fs::path garment_dir = dir / (run.extended ? "extended" : "garment");
  run.garment_file = require_file(garment_dir / "garment.json");
  run.design_mesh = require_file(garment_dir / "garment.ply");
  run.rest_mesh = require_file(dir / "fit" / "rest.ply");
  run.pattern_svg = require_file(dir / "pattern" / "pattern.svg");

  run.delta = require(run.fit, "/options/delta", "number").get<double>();
  if (!(run.delta > 0.0 && run.delta < 0.3))
    throw SpecError("the fit report's stretch scale needs 0 < delta < 0.3, got " + std::to_string(run.delta),
                    run.fit.path.string() + ": /options/delta");
  require(run.fit, "/options/adapt", "boolean");
  run.keys = read_keys(run.fit, dir / "fit");
  run.held = read_held(run.fit, dir, run.poses_manifest);
  if (!run.held && run.opened && run.opened->automatic)
    if (const std::optional<StageReport> held = read_optional_stage(dir, "fit-held", "simulate-adapt-report"))
      run.held = read_held(*held, dir, run.poses_manifest);
  for (const char* p : {"/counts/garment_vertices", "/counts/garment_faces"}) require(run.fit, p, "integer");
  for (const char* p : {"/summary/pieces", "/summary/seams"}) require(run.pattern, p, "integer");
  // The pattern's distortion limit: one-sided (compression and ease) or symmetric.
  const Json* kind = lookup(run.pattern, "/summary/limit/kind");
  if (kind && kind->is_string() && kind->get<std::string>() == "one-sided") {
    for (const char* p : {"/summary/total_seam_length", "/summary/worst_compression", "/summary/worst_ease",
                          "/summary/limit/compression_worst1", "/summary/limit/ease_worst5"})
      require(run.pattern, p, "number");
  } else {
    for (const char* p : {"/summary/total_seam_length", "/summary/worst_p95_error", "/summary/worst_max_error",
                          "/summary/limit/p95_error", "/summary/limit/max_error"})
      require(run.pattern, p, "number");
  }
  require(run.pattern, "/summary/meets_distortion_limit", "boolean");
  require(run.pattern, "/rest_shape", "object");
  require(run.pattern, "/sewn_fit/checked", "boolean");

  if (run.fit_no_adapt) {
    if (require(*run.fit_no_adapt, "/options/adapt", "boolean").get<bool>())
      throw SpecError("fit-noadapt/ holds a run with adaptation; expected simulate-adapt --no-adapt",
                      run.fit_no_adapt->path.string() + ": /options/adapt");
    run.keys_no_adapt = read_keys(*run.fit_no_adapt, dir / "fit-noadapt");
    bool same = run.keys_no_adapt.size() == run.keys.size();
    for (size_t i = 0; same && i < run.keys.size(); ++i) same = run.keys[i].pose == run.keys_no_adapt[i].pose;
    if (!same)
      throw SpecError("the run without adaptation has other key poses than fit/", run.fit_no_adapt->path.string() +
                                                                                     ": /key_poses");
  }
  return run;
}

}  // namespace gp::report
