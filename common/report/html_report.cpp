#include "report/html_report.h"

#include <cstdio>

#include "core/error.h"
#include "core/text_format.h"
#include "render/colour_scale.h"
#include "spec/spec_object.h"
#include "report/report_assets.h"

namespace gp::report {
namespace {


// A figure of `report` at `pointer`, or "not checked" where it is absent.
std::string figure(const StageReport& report, const std::string& pointer, const std::string& format) {
  const Json* v = pointer.empty() ? nullptr : lookup(report, pointer);
  const std::string attrs = " data-src=\"" + escape_xml(report.file) + "\" data-ptr=\"" + escape_xml(pointer) +
                            "\" data-format=\"" + format + "\"";
  if (!v || v->is_null()) return "<span class=\"figure absent\"" + attrs + ">not checked</span>";
  try {
    return "<span class=\"figure\"" + attrs + ">" + escape_xml(format_figure(*v, format)) + "</span>";
  } catch (const SpecError& e) {
    throw SpecError(e.what(), report.path.string() + ": " + pointer);
  }
}

// A figure that may be absent without meaning "not checked" (e.g. an
// optional detail of a present check): an empty cell then.
std::string optional_figure(const StageReport& report, const std::string& pointer, const std::string& format) {
  const Json* v = lookup(report, pointer);
  return v && !v->is_null() ? figure(report, pointer, format) : "&ndash;";
}

std::string verdict_cell(const StageReport& report, const std::string& pointer) {
  if (pointer.empty()) return figure(report, "", "text");
  const Json* obj = lookup(report, pointer);
  if (obj->contains("verdict")) return figure(report, pointer + "/verdict", "text");
  if (obj->contains("pass")) return figure(report, pointer + "/pass", "yesno");
  return "(no verdict given)";
}

// A crossing count as a fitter reads it: "none", or how many and where (the
// first example of each kind), never the report's field names.
std::string crossings_cell(const StageReport& fit, const std::string& pointer) {
  if (pointer.empty()) return figure(fit, "", "integer");
  const Json* j = lookup(fit, pointer);
  if (j->is_number()) return j->get<long long>() == 0 ? "none" : figure(fit, pointer, "integer");
  if (!j->is_object()) return "(no counts)";
  auto count = [&](const char* key) -> long long {
    return j->contains(key) && (*j)[key].is_number_integer() ? (*j)[key].get<long long>() : 0;
  };
  const long long body = count("body_edge_crossings"), cloth = count("cloth_edge_crossings");
  if (body == 0 && cloth == 0) return "none";
  std::string out;
  auto where = [&](const char* examples) -> std::string {
    if (!j->contains(examples) || !(*j)[examples].is_array() || (*j)[examples].empty()) return "";
    const Json& e = (*j)[examples][0];
    if (!e.contains("edge") || !e.contains("face")) return "";
    return " (first: edge " + e["edge"][0].dump() + "&ndash;" + e["edge"][1].dump() + " through triangle " + e["face"].dump() + ")";
  };
  if (body > 0)
    out += figure(fit, pointer + "/body_edge_crossings", "integer") + " body edges through the cloth" + where("body_edge_examples");
  if (cloth > 0)
    out += std::string(out.empty() ? "" : "; ") + figure(fit, pointer + "/cloth_edge_crossings", "integer") +
           " cloth edges through the body" + where("cloth_edge_examples");
  return out;
}

void section(std::string& h, const std::string& id, const std::string& heading) {
  h += "<section id=\"" + id + "\">\n<h2>" + heading + "</h2>\n";
}

// The page's head, its title and the first paragraph: the counts and the limit.
void head_and_lead(std::string& h, const FitRun& run, const std::string& title, const std::string& limit) {
  const StageReport& fit = run.fit;
  h += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += "<title>Fit report: " + escape_xml(title) + "</title>\n<style>\n" + std::string(report_css()) + "</style>\n</head>\n<body>\n";
  h += "<h1>Fit report: " + escape_xml(title) + "</h1>\n";
  h += "<p class=\"lead\">" + std::to_string(run.keys.size()) + " key poses, garment of " +
       figure(fit, "/counts/garment_vertices", "integer") + " vertices, body of " +
       optional_figure(fit, "/counts/body_vertices", "integer") + " vertices. Stretch limit of the adaptation: 1 + " +
       "&delta; = " + limit + " (delta " + figure(fit, "/options/delta", "fixed3") + "). Rest shape adapted: " +
       figure(fit, "/options/adapt", "yesno") + ".</p>\n";
}

// Checks first, in plain words: the failed ones, those worth a look, those not checked.
void checks_section(std::string& h, const std::vector<Check>& checks) {
  section(h, "checks", "Checks");
  int failed = 0;
  for (const Check& c : checks) failed += c.level == CheckLevel::fail;
  if (failed == 0) h += "<p class=\"ok\">No check failed.</p>\n";
  for (CheckLevel level : {CheckLevel::fail, CheckLevel::warning, CheckLevel::not_checked}) {
    std::string items;
    for (const Check& c : checks)
      if (c.level == level) items += "<li>" + escape_xml(c.text) + "</li>\n";
    if (items.empty()) continue;
    const char* cls = level == CheckLevel::fail ? "fail" : level == CheckLevel::warning ? "warning" : "unchecked";
    const char* head = level == CheckLevel::fail      ? "Failed"
                       : level == CheckLevel::warning ? "Worth a look"
                                                      : "Not checked";
    h += "<div class=\"checks " + std::string(cls) + "\"><h3>" + head + "</h3>\n<ul>\n" + items + "</ul></div>\n";
  }
  h += "</section>\n";
}

// Where the body held the cloth: its patches and the sheet that rings them.
void held_pose_block(std::string& h, const HeldPose& held, const ReportFiles& files) {
  h += "<div class=\"pose\" id=\"held\">\n<h3>Where the body held the cloth: " + escape_xml(held.pose) + "</h3>\n<p>";
  h += held.folder == "fit"
           ? "The run stopped at this pose: the cloth stopped improving while stretched beyond what it can settle from."
           : "As captured, this pose held the cloth, and the run stopped there (fit-held/); the fit above and below "
             "is for the pose opened a little.";
  h += " The held faces are magenta, and each place the body holds them is ringed:</p>\n<ul>\n";
  for (const HeldPatch& p : held.patches)
    h += "<li>" + escape_xml(p.region) + " at (" + format_fixed(p.position[0], 3) + ", " + format_fixed(p.position[1], 3) +
         ", " + format_fixed(p.position[2], 3) + ") m: " + std::to_string(p.faces.size()) +
         (p.faces.size() == 1 ? " face" : " faces") +
         " stretched up to " + format_fixed(p.max_stretch, 3) +
         (p.gap_mm >= 0.0 ? ", " + format_fixed(p.gap_mm, 1) + " mm of room along the body's normal" : std::string()) +
         "</li>\n";
  h += "</ul>\n<img class=\"sheet\" src=\"" + escape_xml(files.held_sheet) + "\" alt=\"" + escape_xml(held.pose) +
       ": where the body held the cloth\">\n</div>\n";
}

// One key pose: its figures, its picture sheet, the sewn garment where export-rest measured it, its 3D view.
void key_pose_block(std::string& h, const FitRun& run, const ReportFiles& files, size_t i, const std::string& limit) {
  const StageReport& fit = run.fit;
  const ReportFiles::Pose& f = files.poses[i];
  const std::string p = run.keys[i].pointer;
  h += "<div class=\"pose\" id=\"pose-" + std::to_string(i + 1) + "\">\n<h3>Key pose " + std::to_string(i + 1) +
       ": " + escape_xml(run.keys[i].pose) + "</h3>\n";
  h += "<p>max stretch " + figure(fit, p + "/max_stretch", "fixed3") + ", p99 " + figure(fit, p + "/p99_stretch", "fixed3") +
       ", area above " + limit + ": " + figure(fit, p + "/area_fraction_above_limit", "percent2") + ".</p>\n";
  h += "<img class=\"sheet\" src=\"" + escape_xml(f.sheet) + "\" alt=\"" + escape_xml(run.keys[i].pose) +
       ": front, side and back, coloured by stretch\">\n";
  if (!f.sewn_sheet.empty()) {
    // The garment sewn from the pattern against the designed drape (export-rest's sewn-fit check).
    const Json* sewn_keys = lookup(run.pattern, "/sewn_fit/key_poses");
    std::string q;
    for (size_t j = 0; sewn_keys && j < sewn_keys->size(); ++j)
      if ((*sewn_keys)[j].value("key", -1) == run.keys[i].key) q = "/sewn_fit/key_poses/" + std::to_string(j);
    // The settled distance where export-rest measured it (its default), as the sheet shows.
    const Json* settled = q.empty() ? nullptr : lookup(run.pattern, q + "/settled_from_reference/sewn");
    const std::string d = settled ? q + "/settled_from_reference/sewn" : q + "/distance_to_verified";
    h += "<p>Sewn from the flat pattern: " +
         figure(run.pattern, (settled ? q + "/settled_from_reference" : d) + "/verdict", "text") +
         (settled ? "; settled at this pose alone from the designed drape, distance from it: mean "
                  : "; distance from the designed drape after the motion: mean ") + figure(run.pattern, d + "/mean_m", "mm2") + ", p95 " +
         figure(run.pattern, d + "/p95_m", "mm2") + ", max " + figure(run.pattern, d + "/max_m", "mm2") +
         "; p99 stretch " + figure(run.pattern, q + "/p99_stretch", "fixed3") + ", area above " + limit + ": " +
         figure(run.pattern, q + "/area_fraction_above_limit", "percent2") + ".</p>\n";
    h += "<img class=\"sheet\" src=\"" + escape_xml(f.sewn_sheet) + "\" alt=\"" + escape_xml(run.keys[i].pose) +
         ": the sewn garment against the designed drape, coloured by their distance\">\n";
  }
  h += "<div class=\"viewer\" data-model=\"" + escape_xml(f.model_id) + "\" data-front=\"" + escape_xml(files.front) +
       "\"><canvas width=\"640\" height=\"480\"></canvas>"
       "<label><input type=\"checkbox\" class=\"show-body\" checked> show the body</label> "
       "<a href=\"" + escape_xml(f.glb) + "\" download>" + escape_xml(f.glb) + "</a></div>\n</div>\n";
}

// Pictures and 3D views per pose.
void renders_section(std::string& h, const FitRun& run, const ReportFiles& files, const std::string& limit) {
  section(h, "renders", "The garment on the body");
  const render::ColourScale stretch = render::stretch_scale(run.delta);
  h += "<p>Colour: the largest principal stretch of each triangle on a fixed scale from " +
       format_fixed(stretch.min_value(), 1) + " to " + format_fixed(stretch.max_value(), 1) + "; the limit " +
       limit + " is marked on the legend. Compression shows as 1.0. The body is grey. In the 3D views drag to "
       "turn, scroll to zoom, right-drag to move.</p>\n";
  if (run.held && !files.held_sheet.empty()) held_pose_block(h, *run.held, files);
  for (size_t i = 0; i < run.keys.size(); ++i) key_pose_block(h, run, files, i, limit);
  h += "</section>\n";
}

// The pattern and what the shop floor takes of it.
void pattern_section(std::string& h, const ReportFiles& files) {
  section(h, "pattern", "The sewing pattern");
  h += "<p>The pattern at 1:1 in millimetres (" + escape_xml(files.pattern_svg) + "; as a picture: <a href=\"" +
       escape_xml(files.pattern_png) + "\">" + escape_xml(files.pattern_png) + "</a>).</p>\n";
  h += "<img class=\"pattern\" src=\"" + escape_xml(files.pattern_svg) + "\" alt=\"sewing pattern\">\n";
  h += "<img class=\"pattern-png\" src=\"" + escape_xml(files.pattern_png) + "\" alt=\"sewing pattern as a picture\">\n";

  if (!files.downloads.empty()) {
    h += "<p>For the shop floor:</p>\n<ul class=\"downloads\">\n";
    for (const ReportFiles::Download& d : files.downloads)
      h += "<li><a href=\"" + escape_xml(d.path) + "\" download>" + escape_xml(d.path) + "</a>: " + escape_xml(d.what) + "</li>\n";
    h += "</ul>\n";
  }
  h += "</section>\n";
}

// The marker: the fabric to buy.
void marker_section(std::string& h, const StageReport& m, const ReportFiles& files) {
  section(h, "marker", "The marker: how much fabric to buy");
  h += "<p>The pieces nested on a fabric " + figure(m, "/fabric_width", "metres2") + " wide: " +
       figure(m, "/length", "metres2") + " of fabric, utilisation " + figure(m, "/utilisation", "percent2") + ", " +
       figure(m, "/pieces", "integer") + " pieces, grain along the length.</p>\n";
  if (!files.marker_svg.empty())
    h += "<img class=\"marker\" src=\"" + escape_xml(files.marker_svg) + "\" alt=\"the marker\">\n";
  h += "</section>\n";
}

// The key poses' table, and the verification's where the fit verified.
void key_pose_tables(std::string& h, const FitRun& run, const std::string& limit) {
  const StageReport& fit = run.fit;
  section(h, "key-poses", "Key poses");
  h += "<p>Figures at the end of each key pose of the adaptation (largest principal stretch of each triangle "
       "against the rest shape). The verification simulates the final rest shape afresh, without adaptation.</p>\n";
  h += "<table class=\"figures\" id=\"key-pose-table\">\n<tr><th>#</th><th>pose</th><th>max stretch</th><th>p99</th>"
       "<th>area above " + limit + "</th><th>deepest penetration</th><th>crossings</th><th>verification</th>"
       "<th>steps</th><th>settle steps</th><th>settled</th><th>rest area growth</th></tr>\n";
  for (size_t i = 0; i < run.keys.size(); ++i) {
    const std::string p = run.keys[i].pointer;
    h += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + figure(fit, p + "/pose", "text") + "</td><td>" +
         figure(fit, p + "/max_stretch", "fixed3") + "</td><td>" + figure(fit, p + "/p99_stretch", "fixed3") +
         "</td><td>" + figure(fit, p + "/area_fraction_above_limit", "percent2") + "</td><td>" +
         figure(fit, p + "/deepest_penetration_m", "mm2") + "</td><td>" +
         crossings_cell(fit, crossings_pointer(fit, i)) + "</td><td>" +
         verdict_cell(fit, verification_pointer(fit, i)) + "</td><td>" + figure(fit, p + "/steps", "integer") +
         "</td><td>" + figure(fit, p + "/settle_steps", "integer") + "</td><td>" + figure(fit, p + "/settled", "yesno") +
         "</td><td>" + figure(fit, p + "/rest_area_growth", "times3") + "</td></tr>\n";
  }
  h += "</table>\n";
  bool any_verification = false;
  for (size_t i = 0; i < run.keys.size(); ++i) any_verification |= !verification_pointer(fit, i).empty();
  if (any_verification) {
    h += "<h3>Verification: the final rest shape through the motion, no adaptation</h3>\n"
         "<table class=\"figures\" id=\"verification-table\">\n<tr><th>#</th><th>pose</th><th>verdict</th>"
         "<th>max stretch</th><th>p99</th><th>mean</th><th>area above " + limit + "</th><th>deepest penetration</th></tr>\n";
    for (size_t i = 0; i < run.keys.size(); ++i) {
      const std::string v = verification_pointer(fit, i);
      const std::string p = v.empty() ? "" : v + "/";
      h += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + escape_xml(run.keys[i].pose) + "</td><td>" +
           verdict_cell(fit, v) + "</td><td>" + figure(fit, v.empty() ? "" : p + "max_stretch", "fixed3") + "</td><td>" +
           figure(fit, v.empty() ? "" : p + "p99_stretch", "fixed3") + "</td><td>" +
           figure(fit, v.empty() ? "" : p + "mean_stretch", "fixed3") + "</td><td>" +
           figure(fit, v.empty() ? "" : p + "area_fraction_above_limit", "percent2") + "</td><td>" +
           figure(fit, v.empty() ? "" : p + "deepest_penetration_m", "mm2") + "</td></tr>\n";
    }
    // Each transition's worst in-between frame (solved to equilibrium), beside the key poses.
    const Json* transitions = lookup(fit, "/verification/transitions");
    for (size_t t = 0; transitions && transitions->is_array() && t < transitions->size(); ++t) {
      const std::string q = "/verification/transitions/" + std::to_string(t);
      if (!lookup(fit, q + "/worst_frame")) continue;
      const std::string w = q + "/worst_frame/";
      h += "<tr class=\"in-between\"><td></td><td>" + figure(fit, q + "/from", "text") + " to " +
           figure(fit, q + "/to", "text") + ": worst of " + figure(fit, q + "/frames_solved", "integer") +
           " in-between frames (at " + figure(fit, w + "t", "fixed3") + "; " + figure(fit, q + "/frames_failed", "integer") +
           " fail)</td><td>" + figure(fit, q + "/verdict", "text") + "</td><td>" + figure(fit, w + "max_stretch", "fixed3") +
           "</td><td>" + figure(fit, w + "p99_stretch", "fixed3") + "</td><td>" + figure(fit, w + "mean_stretch", "fixed3") +
           "</td><td>" + figure(fit, w + "area_fraction_above_limit", "percent2") + "</td><td>" +
           figure(fit, w + "deepest_penetration_m", "mm2") + "</td></tr>\n";
    }
    h += "</table>\n";
  }
  h += "</section>\n";
}

// The design simulated without adaptation against the adapted garment (fit-noadapt/).
void before_after_section(std::string& h, const FitRun& run, const ReportFiles& files, const std::string& limit) {
  const StageReport& fit = run.fit;
  section(h, "before-after", "What the adaptation does: the design against the adapted garment");
  h += "<p>Top row: the garment as designed, simulated through the same motion without adaptation "
       "(fit-noadapt/). Bottom row: the adapted garment. Same colour scale.</p>\n";
  h += "<table class=\"figures\" id=\"before-after-table\">\n<tr><th>#</th><th>pose</th><th>max stretch as designed</th>"
       "<th>adapted</th><th>area above " + limit + " as designed</th><th>adapted</th></tr>\n";
  for (size_t i = 0; i < run.keys.size(); ++i) {
    const std::string p = run.keys[i].pointer, q = run.keys_no_adapt[i].pointer;
    h += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + escape_xml(run.keys[i].pose) + "</td><td>" +
         figure(*run.fit_no_adapt, q + "/max_stretch", "fixed3") + "</td><td>" + figure(fit, p + "/max_stretch", "fixed3") +
         "</td><td>" + figure(*run.fit_no_adapt, q + "/area_fraction_above_limit", "percent2") + "</td><td>" +
         figure(fit, p + "/area_fraction_above_limit", "percent2") + "</td></tr>\n";
  }
  h += "</table>\n";
  for (size_t i = 0; i < run.keys.size(); ++i)
    h += "<h3>Key pose " + std::to_string(i + 1) + ": " + escape_xml(run.keys[i].pose) + "</h3>\n<img class=\"sheet\" src=\"" +
         escape_xml(files.poses[i].before_after) + "\" alt=\"" + escape_xml(run.keys[i].pose) + ": as designed and adapted\">\n";
  h += "</section>\n";
}

// The rest shape against the design.
void rest_shape_section(std::string& h, const FitRun& run, const ReportFiles& files) {
  const StageReport& fit = run.fit;
  const StageReport& pattern = run.pattern;
  section(h, "rest-shape", "The rest shape against the design");
  const std::string last = run.keys.back().pointer;
  h += "<p>Top row: the garment as designed. Bottom row: the adapted rest shape (the garment's unstretched "
       "shape, off the body), each triangle coloured by its area over the design's.</p>\n";
  h += "<table class=\"figures\" id=\"rest-table\">\n";
  h += "<tr><th>rest area growth</th><td>" + figure(fit, last + "/rest_area_growth", "times3") + "</td></tr>\n";
  h += "<tr><th>face area growth, 95th percentile</th><td>" + optional_figure(pattern, "/rest_shape/face_growth_p95", "times3") + "</td></tr>\n";
  h += "<tr><th>face area growth, largest</th><td>" + optional_figure(pattern, "/rest_shape/face_growth_max", "times3") + "</td></tr>\n";
  h += "<tr><th>faces turned over (tucks)</th><td>" + optional_figure(pattern, "/rest_shape/turned_faces", "integer") + "</td></tr>\n";
  h += "<tr><th>cone points (design)</th><td>" + optional_figure(pattern, "/rest_shape/cone_points", "integer") + " (" +
       optional_figure(pattern, "/rest_shape/cone_points_design", "integer") + ")</td></tr>\n";
  h += "<tr><th>sum of |angle defect| [rad] (design)</th><td>" +
       optional_figure(pattern, "/rest_shape/abs_angle_defect_sum_rad", "fixed2") + " (" +
       optional_figure(pattern, "/rest_shape/abs_angle_defect_sum_design_rad", "fixed2") + ")</td></tr>\n";
  // Where the registration stretches the body's skin most (register-check's surface growth): a
  // garment resting there grows with it, and cloth grown next to a loop is a frill no pattern
  // flattens within its limit (BENCHMARKS.md, "The bulk's ease, and sleeves opened under the arm").
  std::string grown;
  double most = 0.0;
  if (const Json* poses = lookup(run.poses, "/poses"); poses && poses->is_array())
    for (size_t i = 0; i < poses->size(); ++i) {
      const std::string p = "/poses/" + std::to_string(i);
      const Json* f = lookup(run.poses, p + "/surface_growth/largest/factor");
      if (f && f->is_number() && f->get<double>() > most) {
        most = f->get<double>();
        grown = p;
      }
    }
  h += "<tr><th>the body's skin grown most between its poses by the registration (neighbourhood radius; pose)</th><td>" +
       (grown.empty() ? std::string("&ndash;")
                      : figure(run.poses, grown + "/surface_growth/largest/factor", "times3") + " (" +
                            figure(run.poses, grown + "/surface_growth/radius_m", "metres2") + "; " +
                            figure(run.poses, grown + "/name", "text") + ")") +
       "</td></tr>\n";
  h += "</table>\n<img class=\"sheet\" src=\"" + escape_xml(files.rest_sheet) + "\" alt=\"the design and the adapted rest shape\">\n";
  h += "<p>3D: <a href=\"" + escape_xml(files.rest_glb) + "\" download>" + escape_xml(files.rest_glb) + "</a>, <a href=\"" +
       escape_xml(files.design_glb) + "\" download>" + escape_xml(files.design_glb) + "</a></p>\n</section>\n";
}

// The sewing pattern's figures, and the sewn fit's per key pose.
void pattern_figures_section(std::string& h, const StageReport& pattern, const std::string& limit) {
  section(h, "pattern-figures", "The sewing pattern: figures");
  h += "<table class=\"figures\" id=\"pattern-table\">\n";
  h += "<tr><th>pieces</th><td>" + figure(pattern, "/summary/pieces", "integer") + "</td></tr>\n";
  h += "<tr><th>seams</th><td>" + figure(pattern, "/summary/seams", "integer") + "</td></tr>\n";
  h += "<tr><th>cuts added for distortion</th><td>" + optional_figure(pattern, "/summary/added_cuts", "integer") + "</td></tr>\n";
  h += "<tr><th>seam length</th><td>" + figure(pattern, "/summary/total_seam_length", "metres2") + "</td></tr>\n";
  const Json* limit_kind = lookup(pattern, "/summary/limit/kind");
  if (limit_kind && limit_kind->is_string() && limit_kind->get<std::string>() == "one-sided") {
    h += "<tr><th>darts</th><td>" + optional_figure(pattern, "/summary/darts", "integer") + "</td></tr>\n";
    h += "<tr><th>worst compression over a piece's worst 1 % (limit)</th><td>" +
         figure(pattern, "/summary/worst_compression", "percent2") + " (" +
         figure(pattern, "/summary/limit/compression_worst1", "percent2") + ")</td></tr>\n";
    h += "<tr><th>worst ease over a piece's worst 5 % (limit)</th><td>" + figure(pattern, "/summary/worst_ease", "percent2") +
         " (" + figure(pattern, "/summary/limit/ease_worst5", "percent2") + ")</td></tr>\n";
  } else {
    h += "<tr><th>worst p95 distortion (limit)</th><td>" + figure(pattern, "/summary/worst_p95_error", "percent2") + " (" +
         figure(pattern, "/summary/limit/p95_error", "percent2") + ")</td></tr>\n";
    h += "<tr><th>worst distortion (limit)</th><td>" + figure(pattern, "/summary/worst_max_error", "percent2") + " (" +
         figure(pattern, "/summary/limit/max_error", "percent2") + ")</td></tr>\n";
  }
  h += "<tr><th>seams whose two sewn edges match within 1 mm (worst difference)</th><td>" +
            optional_figure(pattern, "/summary/seams_matched_1mm", "integer") + " of " +
            figure(pattern, "/summary/seams", "integer") + " (" + optional_figure(pattern, "/summary/worst_seam_mismatch", "mm2") +
            ")</td></tr>\n";
  h += "<tr><th>within the limit</th><td>" + figure(pattern, "/summary/meets_distortion_limit", "yesno") + "</td></tr>\n";
  // The bulk's ease, which the sewn garment carries and the limit's tails do not show (pattern README,
  // "Ease in the bulk"); absent from reports before it.
  h += "<tr><th>ease of the median triangle, the most eased piece</th><td>" +
       optional_figure(pattern, "/summary/worst_median_ease", "percent2") + "</td></tr>\n";
  h += "<tr><th>sheet</th><td>" + optional_figure(pattern, "/summary/sheet_width", "metres2") + " &times; " +
       optional_figure(pattern, "/summary/sheet_height", "metres2") + "</td></tr>\n";
  const std::string sewn = sewn_fit_pointer(pattern);
  h += "<tr><th>sewn fit in every key pose</th><td>" + verdict_cell(pattern, sewn) + "</td></tr>\n";
  // The sewn garment's figures per key pose, where export-rest checked them.
  if (const Json* poses = sewn.empty() ? nullptr : lookup(pattern, sewn + "/key_poses"); poses && poses->is_array()) {
    for (size_t i = 0; i < poses->size(); ++i) {
      const std::string p = sewn + "/key_poses/" + std::to_string(i);
      h += "<tr><th>sewn fit at " + figure(pattern, p + "/pose", "text") + ": verdict, p99 stretch, area above the limit, deepest penetration</th><td>" +
           figure(pattern, p + "/verdict", "text") + ", " + figure(pattern, p + "/p99_stretch", "fixed3") + ", " +
           figure(pattern, p + "/area_fraction_above_limit", "percent2") + ", " +
           figure(pattern, p + "/deepest_penetration_m", "mm2") + "</td></tr>\n";
    }
  }
  h += "</table>\n";
  h += "</section>\n";
}

// The timings' table, which timing.js fills, and the page's scripts.
void timings_and_scripts(std::string& h, const ReportFiles& files) {
  section(h, "timings", "Timings");
  h += "<p>Wall-clock seconds of each stage, from its timing.json (they differ from run to run).</p>\n"
       "<table class=\"figures\" id=\"timings-table\"><tr><th>stage</th><th>total [s]</th><th>phases [s]</th></tr></table>\n"
       "</section>\n";

  for (const std::string& s : files.scripts) h += "<script src=\"" + escape_xml(s) + "\"></script>\n";
  h += "</body>\n</html>\n";
}

}  // namespace

std::string format_figure(const Json& v, const std::string& format) {
  if (format == "text") return v.is_string() ? v.get<std::string>() : v.dump();
  if (format == "yesno") {
    if (!v.is_boolean()) throw SpecError("expected a boolean for a yes/no figure, found " + json_type_name(v));
    return v.get<bool>() ? "yes" : "no";
  }
  if (!v.is_number()) throw SpecError("expected a number for a figure, found " + json_type_name(v));
  const double x = v.get<double>();
  if (format == "integer") return std::to_string(v.get<long long>());
  if (format == "fixed2") return format_fixed(x, 2);
  if (format == "fixed3") return format_fixed(x, 3);
  if (format == "percent2") return format_fixed(100.0 * x, 2) + " %";
  if (format == "mm2") return format_fixed(1e3 * x, 2) + " mm";
  if (format == "times3") return "\xc3\x97" + format_fixed(x, 3);
  if (format == "metres2") return format_fixed(x, 2) + " m";
  throw UsageError("unknown figure format '" + format + "'");
}

std::string html_report(const FitRun& run, const ReportFiles& files, const std::vector<Check>& checks,
                        const std::string& title) {
  const std::string limit = format_fixed(1.0 + run.delta, 2);
  std::string h;
  head_and_lead(h, run, title, limit);
  checks_section(h, checks);
  renders_section(h, run, files, limit);
  pattern_section(h, files);
  if (run.marker) marker_section(h, *run.marker, files);
  // The tables, after the pictures, with plain cells.
  key_pose_tables(h, run, limit);
  if (run.fit_no_adapt) before_after_section(h, run, files, limit);
  rest_shape_section(h, run, files);
  pattern_figures_section(h, run.pattern, limit);
  timings_and_scripts(h, files);
  return h;
}

std::string timing_script(const FitRun& run) {
  OrderedJson list = OrderedJson::array();
  for (const StageReport* s : run.stages())
    if (!s->timing.is_null()) list.push_back({{"stage", s->stage}, {"file", s->stage + "/timing.json"}, {"timing", s->timing}});
  return "window.GP_TIMINGS = " + list.dump() + ";\n";
}

}  // namespace gp::report
