#include "report/checks.h"

#include <cstdio>

#include "core/text_format.h"

namespace gp::report {
namespace {


double number_at(const StageReport& r, const std::string& p) { return lookup(r, p)->get<double>(); }

// A count at `pointer`: a number, or the sum of an object's numeric fields.
long long count_of(const Json* j) {
  if (!j) return 0;
  if (j->is_number()) return j->get<long long>();
  long long sum = 0;
  if (j->is_object())
    for (const auto& kv : j->items())
      if (kv.value().is_number_integer()) sum += kv.value().get<long long>();
  return sum;
}

}  // namespace

const char* check_level_name(CheckLevel level) {
  switch (level) {
    case CheckLevel::fail: return "fail";
    case CheckLevel::warning: return "warning";
    case CheckLevel::not_checked: return "not checked";
  }
  return "?";
}

std::string verification_pointer(const StageReport& fit, size_t i) {
  const std::string a = "/key_poses/" + std::to_string(i) + "/verification";
  if (const Json* j = lookup(fit, a); j && j->is_object()) return a;
  const std::string b = "/verification/key_poses/" + std::to_string(i);
  if (const Json* j = lookup(fit, b); j && j->is_object()) return b;
  return "";
}

std::string crossings_pointer(const StageReport& fit, size_t i) {
  const std::string a = "/key_poses/" + std::to_string(i) + "/crossings";
  if (lookup(fit, a)) return a;
  const std::string v = verification_pointer(fit, i);
  if (!v.empty() && lookup(fit, v + "/crossings")) return v + "/crossings";
  return "";
}

std::string sewn_fit_pointer(const StageReport& pattern) {
  const Json* j = lookup(pattern, "/sewn_fit");
  if (!j || !j->is_object()) return "";
  // export-rest writes {"checked": false, "why": ...} when it did not check.
  const auto checked = j->find("checked");
  if (checked != j->end() && checked->is_boolean() && !checked->get<bool>()) return "";
  return "/sewn_fit";
}

// "; over on compression: front, back; over on ease: left sleeve" from the
// pattern summary's pieces_over_limit, where export-rest gives it.
std::string pieces_over(const Json& summary) {
  const auto it = summary.find("pieces_over_limit");
  if (it == summary.end() || !it->is_object()) return "";
  std::string out;
  for (const auto& [bound, names] : it->items()) {
    if (!names.is_array() || names.empty()) continue;
    out += "; over on " + bound + ":";
    for (size_t i = 0; i < names.size(); ++i)
      out += (i ? ", " : " ") + (names[i].is_string() ? names[i].get<std::string>() : names[i].dump());
  }
  return out;
}

// ": key pose 2 (armsup): ..." from the sewn-fit check's failure line, where it gives one.
std::string sewn_fit_detail(const StageReport& pattern, const std::string& pointer) {
  const Json* f = lookup(pattern, pointer + "/failure");
  return f && f->is_string() ? ": " + f->get<std::string>() : "";
}

// " at 3 places, near (0.207, 0.742, 0.129) m, ..." from the places where
// make-garment or extend-boundary cleared the design of the body and found no
// room for the offset; "" where there are none.
std::string held_places(const FitRun& run) {
  std::string near;
  int count = 0;
  for (const StageReport* stage : {&run.garment, run.extended ? &*run.extended : nullptr}) {
    const Json* places = stage ? lookup(*stage, "/body_clearance/places") : nullptr;
    if (!places || !places->is_array()) continue;
    for (const Json& place : *places) {
      if (!place.is_object() || place.value("room", true)) continue;
      const Json& c = place["center"];
      if (count++ < 3 && c.is_array() && c.size() == 3)
        near += std::string(near.empty() ? ", near (" : ", (") + format_fixed(c[0].get<double>(), 3) + ", " +
                format_fixed(c[1].get<double>(), 3) + ", " + format_fixed(c[2].get<double>(), 3) + ") m";
    }
  }
  if (count == 0) return "";
  return " at " + std::to_string(count) + (count == 1 ? " place" : " places") + near + (count > 3 ? ", ..." : "");
}

std::string verdict_of(const Json* object) {
  if (!object || !object->is_object()) return "";
  const auto v = object->find("verdict");
  if (v != object->end() && v->is_string()) return v->get<std::string>();
  const auto p = object->find("pass");
  if (p != object->end() && p->is_boolean()) return p->get<bool>() ? "pass" : "fail";
  return "";
}

std::vector<Check> fit_checks(const FitRun& run, const FitThresholds& t) {
  std::vector<Check> out;
  auto add = [&out](CheckLevel level, const char* id, const std::string& pose, std::string text) {
    out.push_back({level, id, pose, std::move(text)});
  };
  const std::string limit = format_fixed(1.0 + run.delta, 2);

  const std::string body_verdict = lookup(run.poses, "/verdict")->get<std::string>();
  if (body_verdict != "pass")
    add(CheckLevel::fail, "body_check", "", "The body check (register-check) gave the verdict '" + body_verdict + "'.");
  if (const auto& o = run.opened)
    add(CheckLevel::warning, "opened_pose", o->pose,
        "The fit is for " + o->pose + " opened 1/" + std::to_string(o->steps) + " of the way towards " + o->toward +
            (o->automatic ? " (opened automatically: as captured, the body held the cloth at " + o->held_at +
                                "; the body moves " + format_fixed(o->largest_displacement_mm, 0) +
                                " mm at most; fit-held/ has that run's report; AUTO_OPEN=0 turns this off)"
                          : std::string(" (make fit's OPEN_POSE)")) +
            ", not for that pose as captured.");
  if (const std::string held = held_places(run); !held.empty())
    add(CheckLevel::warning, "no_room", "",
        "The design meets the body with no room for its comfort offset" + held +
            ". Where two body parts nearly touch there (a hand on the thigh over a skirt), the body holds the cloth, "
            "and no rest shape can relieve it: fit a pose opened a little (make fit's OPEN_POSE).");

  bool any_verification = false, any_crossings = false;
  for (size_t i = 0; i < run.keys.size(); ++i) {
    const KeyPoseRun& k = run.keys[i];
    const std::string p = k.pointer;
    const std::string name = "key pose " + std::to_string(i + 1) + " (" + k.pose + ")";
    const double above = number_at(run.fit, p + "/area_fraction_above_limit");
    const double p99 = number_at(run.fit, p + "/p99_stretch");
    const double depth = number_at(run.fit, p + "/deepest_penetration_m");
    if (above >= t.area_above_limit)
      add(CheckLevel::fail, "area_above_limit", k.pose, "At " + name + ", " + format_fixed(100.0 * above, 2) + " % of the cloth is stretched beyond " +
                                limit + " (allowed: under " + format_fixed(100.0 * t.area_above_limit, 0) + " %).");
    if (p99 > 1.0 + run.delta + t.p99_margin)
      add(CheckLevel::fail, "p99_stretch", k.pose, "At " + name + ", the 99th percentile of the stretch is " + format_fixed(p99, 3) +
                                " (allowed: " + format_fixed(1.0 + run.delta + t.p99_margin, 2) + ").");
    if (depth > t.penetration)
      add(CheckLevel::fail, "penetration", k.pose, "At " + name + ", the cloth lies up to " + format_fixed(1e3 * depth, 1) +
                                " mm inside the body (allowed: " + format_fixed(1e3 * t.penetration, 0) + " mm).");
    if (!lookup(run.fit, p + "/settled")->get<bool>())
      add(CheckLevel::warning, "settled", k.pose, "At " + name + ", the cloth had not come to rest after " +
                                   std::to_string(lookup(run.fit, p + "/settle_steps")->get<long long>()) +
                                   " settling steps: its figures may not be final.");
    const std::string v = verification_pointer(run.fit, i);
    if (!v.empty()) {
      any_verification = true;
      if (verdict_of(lookup(run.fit, v)) == "fail")
        add(CheckLevel::fail, "verification", k.pose, "The verification (the final rest shape simulated afresh) fails at " + name + ".");
    }
    const std::string c = crossings_pointer(run.fit, i);
    if (!c.empty()) {
      any_crossings = true;
      const long long n = count_of(lookup(run.fit, c));
      if (n > 0)
        add(CheckLevel::fail, "crossings", k.pose, "At " + name + ", the body and the cloth cross " + std::to_string(n) +
                                  " times (body edges through cloth triangles or cloth edges through body triangles).");
    }
  }
  // The movement between the key poses: each transition's in-between frames solved to equilibrium.
  if (const Json* transitions = lookup(run.fit, "/verification/transitions"); transitions && transitions->is_array()) {
    for (const Json& t : *transitions) {
      if (t.value("verdict", "pass") != "fail") continue;
      const Json& w = t.at("worst_frame");
      const std::vector<std::string> failures = w.value("failures", std::vector<std::string>{});
      add(CheckLevel::fail, "verification", t.value("from", "") + " to " + t.value("to", ""),
          "Between " + t.value("from", "") + " and " + t.value("to", "") + ", " +
              std::to_string(t.value("frames_failed", 0)) + " of " + std::to_string(t.value("frames_solved", 0)) +
              " in-between frames fail; the worst, at " + format_fixed(w.value("t", 0.0), 2) + " of the way, " +
              (failures.empty() ? std::string("exceeds a bound") : failures.front()) + ".");
    }
  }
  if (const Json* overall = lookup(run.fit, "/verification"); overall && verdict_of(overall) == "fail")
    add(CheckLevel::fail, "verification", "", "The verification of the fit (the final rest shape simulated afresh) fails.");

  const Json& summary = *lookup(run.pattern, "/summary");
  // The distortion limit is the cutter's means; the sewn-fit check is the
  // verdict on the pattern. Pieces over the limit of a pattern whose sewn
  // garment fits every key pose are worth a look, not a failure.
  const std::string sewn_check = sewn_fit_pointer(run.pattern);
  const bool sewn_fits = !sewn_check.empty() && verdict_of(lookup(run.pattern, sewn_check)) == "pass";
  const CheckLevel distortion_level = sewn_fits ? CheckLevel::warning : CheckLevel::fail;
  const std::string sewn_note = sewn_fits ? " The garment sewn from it fits every key pose (sewn-fit check)." : "";
  if (!summary["meets_distortion_limit"].get<bool>()) {
    const Json& bound = summary["limit"];
    if (bound.value("kind", "symmetric") == "one-sided")
      add(distortion_level, "pattern_distortion", "", "The pattern pieces are distorted beyond the limit: worst compression " +
                                format_fixed(100.0 * summary["worst_compression"].get<double>(), 2) +
                                " % over a piece's worst 1 % (limit " +
                                format_fixed(100.0 * bound["compression_worst1"].get<double>(), 2) + " %), worst ease " +
                                format_fixed(100.0 * summary["worst_ease"].get<double>(), 2) + " % over its worst 5 % (limit " +
                                format_fixed(100.0 * bound["ease_worst5"].get<double>(), 2) + " %)" +
                                pieces_over(summary) + "." + sewn_note);
    else
      add(distortion_level, "pattern_distortion", "", "The pattern pieces are distorted beyond the limit: worst p95 " +
                                format_fixed(100.0 * summary["worst_p95_error"].get<double>(), 2) + " % (limit " +
                                format_fixed(100.0 * bound["p95_error"].get<double>(), 2) + " %), worst " +
                                format_fixed(100.0 * summary["worst_max_error"].get<double>(), 2) + " % (limit " +
                                format_fixed(100.0 * bound["max_error"].get<double>(), 2) + " %)." + sewn_note);
  }
  if (const Json* j = lookup(run.pattern, "/summary/overlapping_pieces"); j && j->is_number() && j->get<double>() > 0)
    add(CheckLevel::fail, "pattern_overlaps", "", std::to_string(j->get<long long>()) + " pattern pieces overlap themselves when laid flat.");
  if (const Json* j = lookup(run.pattern, "/summary/flipped_triangles"); j && j->is_number() && j->get<double>() > 0)
    add(CheckLevel::fail, "pattern_flips", "", std::to_string(j->get<long long>()) + " triangles of the pattern are turned over when laid flat.");
  if (const Json* j = lookup(run.pattern, "/summary/seams_within_tolerance"); j && j->is_boolean() && !j->get<bool>())
    add(CheckLevel::fail, "seam_lengths", "", "Some seams have sides of different lengths beyond the tolerance.");
  const std::string sewn = sewn_fit_pointer(run.pattern);
  if (!sewn.empty() && verdict_of(lookup(run.pattern, sewn)) == "fail")
    add(CheckLevel::fail, "sewn_fit", "", "The garment sewn from the flat pattern does not fit every key pose (sewn-fit check)" +
                                  sewn_fit_detail(run.pattern, sewn) + ".");
  if (const Json* j = lookup(run.pattern, "/rest_shape/turned_faces"); j && j->is_number() && j->get<double>() > 0)
    add(CheckLevel::warning, "tucks", "", "The adapted rest shape has " + std::to_string(j->get<long long>()) +
                                 " faces turned over against the design (tucks); they are hard to sew.");

  if (!any_verification)
    add(CheckLevel::not_checked, "verification", "", "Verification: the final rest shape was not simulated afresh through the motion, "
                                 "so the fit of the earlier poses is not confirmed (the key-pose figures above come "
                                 "from the adaptation itself, which clips stretch at " + limit + ").");
  if (!any_crossings)
    add(CheckLevel::not_checked, "crossings", "", "Crossings: no stage counted body edges through the cloth; the penetration figure "
                                 "only sees cloth vertices inside the body.");
  if (sewn.empty())
    add(CheckLevel::not_checked, "sewn_fit", "", "Sewn fit: the garment sewn from the flat pattern was not simulated on the poses.");
  return out;
}

}  // namespace gp::report
