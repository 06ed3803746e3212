#include <catch2/catch.hpp>

#include <filesystem>

#include "core/error.h"
#include "core/sha256.h"
#include "render/text.h"
#include "report/checks.h"
#include "report/fit_report.h"
#include "report/fit_run.h"
#include "report/html_report.h"
#include "report/picture_sheet.h"
#include "report/sewn_sheet.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "testing/command.h"
#include "testing/files.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using gp::Json;
using namespace gp::report;

namespace {

// A fit run in memory with the fields the checks read: two key poses.
FitRun small_run() {
  FitRun run;
  run.delta = 0.1;
  run.poses.file = "poses/report.json";
  run.poses.json = Json::parse(R"({"schema": "register-check-report/1", "verdict": "pass"})");
  run.fit.file = "fit/report.json";
  run.fit.json = Json::parse(R"({"schema": "simulate-adapt-report/1", "options": {"delta": 0.1, "adapt": true},
    "key_poses": [
      {"key": 0, "pose": "apose", "max_stretch": 1.05, "p99_stretch": 1.04, "mean_stretch": 1.01,
       "area_fraction_above_limit": 0.0, "deepest_penetration_m": 0.0, "settle_steps": 80, "settled": true},
      {"key": 1, "pose": "tpose", "max_stretch": 1.1, "p99_stretch": 1.099, "mean_stretch": 1.03,
       "area_fraction_above_limit": 0.0, "deepest_penetration_m": 0.0, "settle_steps": 120, "settled": true}]})");
  run.keys = {{0, "apose", "a.ply", "/key_poses/0", "", ""}, {1, "tpose", "t.ply", "/key_poses/1", "", ""}};
  run.pattern.file = "pattern/report.json";
  run.pattern.json = Json::parse(R"({"schema": "export-rest-report/1", "rest_shape": {},
    "sewn_fit": {"checked": false, "why": "no fit report given"},
    "summary": {"pieces": 3, "seams": 4, "total_seam_length": 2.5, "worst_p95_error": 0.01, "worst_max_error": 0.03,
                "meets_distortion_limit": true, "limit": {"p95_error": 0.02, "max_error": 0.05}}})");
  return run;
}

int count(const std::vector<Check>& checks, CheckLevel level) {
  int n = 0;
  for (const Check& c : checks) n += c.level == level;
  return n;
}

bool mentions(const std::vector<Check>& checks, CheckLevel level, const std::string& text) {
  for (const Check& c : checks)
    if (c.level == level && c.text.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("a good fit fails no check, and what no stage checked is said so", "[report]") {
  const std::vector<Check> checks = fit_checks(small_run());
  CHECK(count(checks, CheckLevel::fail) == 0);
  CHECK(count(checks, CheckLevel::warning) == 0);
  CHECK(mentions(checks, CheckLevel::not_checked, "Verification"));
  CHECK(mentions(checks, CheckLevel::not_checked, "Crossings"));
  CHECK(mentions(checks, CheckLevel::not_checked, "Sewn fit"));
}

TEST_CASE("failed checks are stated in plain words with the pose and the figure", "[report]") {
  FitRun run = small_run();
  run.poses.json["verdict"] = "fail";
  run.fit.json["key_poses"][1]["deepest_penetration_m"] = 0.0042;
  run.fit.json["key_poses"][1]["area_fraction_above_limit"] = 0.034;
  run.fit.json["key_poses"][0]["settled"] = false;
  run.pattern.json["summary"]["meets_distortion_limit"] = false;
  run.pattern.json["rest_shape"]["turned_faces"] = 12;
  const std::vector<Check> checks = fit_checks(run);
  CHECK(mentions(checks, CheckLevel::fail, "register-check"));
  CHECK(mentions(checks, CheckLevel::fail, "key pose 2 (tpose), the cloth lies up to 4.2 mm inside the body"));
  CHECK(mentions(checks, CheckLevel::fail, "3.40 % of the cloth is stretched beyond 1.10"));
  CHECK(mentions(checks, CheckLevel::fail, "distorted beyond the limit"));
  CHECK(mentions(checks, CheckLevel::warning, "key pose 1 (apose), the cloth had not come to rest after 80"));
  CHECK(mentions(checks, CheckLevel::warning, "12 faces turned over"));
  bool penetration_named = false;
  for (const Check& c : checks) penetration_named |= c.id == "penetration" && c.pose == "tpose";
  CHECK(penetration_named);
}

TEST_CASE("pieces over the distortion limit name their bound, and fail only when the sewn fit does not pass", "[report]") {
  FitRun run = small_run();
  Json& summary = run.pattern.json["summary"];
  summary["meets_distortion_limit"] = false;
  summary["limit"] = {{"kind", "one-sided"}, {"compression_worst1", 0.03}, {"ease_worst5", 0.10}};
  summary["worst_compression"] = 0.067;
  summary["worst_ease"] = 0.119;
  summary["pieces_over_limit"] = {{"compression", {"upper right side", "front"}}, {"ease", {"left sleeve front"}},
                                  {"flips", Json::array()}, {"overlap", Json::array()}};
  std::vector<Check> checks = fit_checks(run);
  CHECK(mentions(checks, CheckLevel::fail, "over on compression: upper right side, front; over on ease: left sleeve front."));
  run.pattern.json["sewn_fit"] = {{"checked", true}, {"verdict", "pass"}};
  checks = fit_checks(run);
  CHECK(!mentions(checks, CheckLevel::fail, "distorted beyond the limit"));
  CHECK(mentions(checks, CheckLevel::warning, "fits every key pose (sewn-fit check)"));
  run.pattern.json["sewn_fit"] = {{"checked", true}, {"verdict", "fail"}, {"failure", "key pose 1 (tpose): p99 stretch 1.15"}};
  checks = fit_checks(run);
  CHECK(mentions(checks, CheckLevel::fail, "distorted beyond the limit"));
  CHECK(mentions(checks, CheckLevel::fail, "(sewn-fit check): key pose 1 (tpose): p99 stretch 1.15."));
}

TEST_CASE("verification, crossings and sewn fit are read where the stages write them", "[report]") {
  FitRun run = small_run();
  run.fit.json["key_poses"][0]["verification"] = {{"verdict", "pass"}, {"max_stretch", 1.08}};
  run.fit.json["verification"] = {{"key_poses", Json::array({Json::object(), {{"pass", false}}})}};
  run.fit.json["key_poses"][1]["crossings"] = {{"body_edges_through_cloth", 3}, {"cloth_edges_through_body", 2}};
  run.pattern.json["sewn_fit"] = {{"verdict", "fail"}};
  CHECK(verification_pointer(run.fit, 0) == "/key_poses/0/verification");
  CHECK(verification_pointer(run.fit, 1) == "/verification/key_poses/1");
  CHECK(crossings_pointer(run.fit, 0).empty());
  CHECK(crossings_pointer(run.fit, 1) == "/key_poses/1/crossings");
  const std::vector<Check> checks = fit_checks(run);
  CHECK(mentions(checks, CheckLevel::fail, "fails at key pose 2 (tpose)"));
  CHECK(!mentions(checks, CheckLevel::fail, "fails at key pose 1"));
  CHECK(mentions(checks, CheckLevel::fail, "cross 5 times"));
  CHECK(mentions(checks, CheckLevel::fail, "sewn from the flat pattern"));
  CHECK(!mentions(checks, CheckLevel::not_checked, "Verification"));
  CHECK(!mentions(checks, CheckLevel::not_checked, "Sewn fit"));
}

TEST_CASE("a transition whose in-between frame fails is a failed check naming the transition", "[report]") {
  FitRun run = small_run();
  Json transition = {{"transition", 0}, {"from", "apose"}, {"to", "tpose"}, {"frames_solved", 5},
                     {"frames_failed", 0}, {"verdict", "pass"},
                     {"worst_frame", {{"t", 0.4}, {"failures", Json::array()}}}};
  run.fit.json["verification"] = {{"verdict", "pass"}, {"transitions", Json::array({transition})}};
  CHECK(!mentions(fit_checks(run), CheckLevel::fail, "in-between"));
  transition["verdict"] = "fail";
  transition["frames_failed"] = 2;
  transition["worst_frame"]["t"] = 0.6;
  transition["worst_frame"]["failures"] = {"p99 stretch 1.1400 above 1.1200"};
  run.fit.json["verification"] = {{"verdict", "fail"}, {"transitions", Json::array({transition})}};
  const std::vector<Check> checks = fit_checks(run);
  CHECK(mentions(checks, CheckLevel::fail,
                 "Between apose and tpose, 2 of 5 in-between frames fail; the worst, at 0.60 of the way, p99 stretch "
                 "1.1400 above 1.1200."));
}

TEST_CASE("a design that passes between body parts with no room is named where", "[report]") {
  FitRun run = small_run();
  run.garment.file = "garment/report.json";
  run.garment.json = Json::parse(R"({"body_clearance": {"places": [
    {"body_vertex": 630, "center": [0.0076, 0.9774, 0.0326], "room": true}]}})");
  CHECK(count(fit_checks(run), CheckLevel::warning) == 0);
  StageReport extended;
  extended.file = "extended/report.json";
  extended.json = Json::parse(R"({"body_clearance": {"places": [
    {"body_vertex": 630, "center": [0.0076, 0.9774, 0.0326], "room": true},
    {"body_vertex": 2028, "center": [0.20734, 0.74242, 0.12912], "room": false},
    {"body_vertex": 2115, "center": [0.19268, 0.80877, 0.11559], "room": false}]}})");
  run.extended = extended;
  const std::vector<Check> checks = fit_checks(run);
  CHECK(count(checks, CheckLevel::warning) == 1);
  CHECK(count(checks, CheckLevel::fail) == 0);
  CHECK(mentions(checks, CheckLevel::warning, "at 2 places, near (0.207, 0.742, 0.129) m, (0.193, 0.809, 0.116) m"));
  CHECK(mentions(checks, CheckLevel::warning, "OPEN_POSE"));
}

TEST_CASE("an opened pose is reported only while it is the registered one", "[report]") {
  const fs::path dir = gp::testing::fresh_temp_dir("report_opened");
  fs::create_directories(dir / "opened" / "poses");
  fs::create_directories(dir / "poses");
  gp::testing::write_file(dir / "opened" / "report.json", R"({"schema": "interp-poses-report/1",
    "motion": {"steps": 20, "sequence": [{"pose": "apose"}, {"pose": "tpose", "steps": 20}]}})");
  gp::testing::write_file(dir / "opened" / "poses" / "apose.ply", "the opened body");
  const fs::path manifest = dir / "poses" / "poses.json";
  auto registered = [&](const std::string& sha) {
    gp::testing::write_file(manifest, R"({"poses": [{"name": "tpose", "sha256": "x"}, {"name": "apose", "sha256": ")" +
                                          sha + R"("}]})");
  };
  registered(gp::sha256_file_hex(dir / "opened" / "poses" / "apose.ply"));
  const std::optional<OpenedPose> opened = read_opened_stage(dir, manifest);
  REQUIRE(opened.has_value());
  FitRun run = small_run();
  run.opened = opened;
  const std::vector<Check> checks = fit_checks(run);
  CHECK(count(checks, CheckLevel::warning) == 1);
  CHECK(mentions(checks, CheckLevel::warning, "The fit is for apose opened 1/20 of the way towards tpose"));
  // Registered from another file (a folder left from an earlier run): not reported.
  registered(gp::sha256_file_hex(manifest));
  CHECK_FALSE(read_opened_stage(dir, manifest).has_value());
  fs::remove_all(dir / "opened");
  CHECK_FALSE(read_opened_stage(dir, manifest).has_value());
}

TEST_CASE("figures are printed in the formats the page documents", "[report]") {
  CHECK(format_figure(Json(1.09996), "fixed3") == "1.100");
  CHECK(format_figure(Json(0.01234), "percent2") == "1.23 %");
  CHECK(format_figure(Json(0.0042), "mm2") == "4.20 mm");
  CHECK(format_figure(Json(1.39551), "times3") == "\xc3\x97" "1.396");
  CHECK(format_figure(Json(25.378), "metres2") == "25.38 m");
  CHECK(format_figure(Json(45), "integer") == "45");
  CHECK(format_figure(Json(true), "yesno") == "yes");
  CHECK(format_figure(Json("apose"), "text") == "apose");
  CHECK_THROWS_AS(format_figure(Json("x"), "fixed3"), gp::SpecError);
  CHECK_THROWS_AS(format_figure(Json(1.0), "nonsense"), gp::UsageError);
}

TEST_CASE("reading a fit folder names the missing file or the bad field", "[report]") {
  const fs::path dir = gp::testing::fresh_temp_dir("report_fit_run");
  try {
    read_fit_run(dir / "nowhere");
    FAIL("no error");
  } catch (const gp::InputError& e) {
    CHECK_THAT(e.where(), Catch::Contains("nowhere"));
  }
  try {
    read_fit_run(dir);
    FAIL("no error");
  } catch (const gp::InputError& e) {
    CHECK_THAT(e.where(), Catch::EndsWith("poses/report.json"));
  }
  fs::create_directories(dir / "poses");
  gp::testing::write_file(dir / "poses" / "report.json", R"({"schema": "make-garment-report/1"})");
  CHECK_THROWS_AS(read_fit_run(dir), gp::SpecError);
  gp::testing::write_file(dir / "poses" / "report.json", R"({"schema": "register-check-report/1"})");
  for (const char* stage : {"garment", "fit", "pattern"}) fs::create_directories(dir / stage);
  gp::testing::write_file(dir / "garment" / "report.json", R"({"schema": "make-garment-report/1"})");
  gp::testing::write_file(dir / "fit" / "report.json", R"({"schema": "simulate-adapt-report/1"})");
  gp::testing::write_file(dir / "pattern" / "report.json", R"({"schema": "export-rest-report/1"})");
  try {
    read_fit_run(dir);
    FAIL("no error");
  } catch (const gp::SpecError& e) {
    CHECK_THAT(e.where(), Catch::EndsWith("poses/report.json: /verdict"));
  }
  StageReport r;
  r.path = "x.json";
  r.json = Json::parse(R"({"a": {"b": [1, "two"]}})");
  CHECK(require(r, "/a/b/0", "integer") == 1);
  CHECK_THROWS_AS(require(r, "/a/b/1", "number"), gp::SpecError);
  CHECK_THROWS_AS(require(r, "/a/c", "number"), gp::SpecError);
  CHECK(lookup(r, "/a/b/5") == nullptr);
  CHECK(lookup(r, "not a pointer") == nullptr);
}

TEST_CASE("a picture sheet is the same for any thread count", "[report]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(3);
  Eigen::MatrixXf colours = Eigen::MatrixXf::Constant(sphere.F.rows(), 3, 0.5f);
  colours.col(0) = Eigen::VectorXf::LinSpaced(sphere.F.rows(), 0.0f, 1.0f);
  gp::render::MeshLayer layer{&sphere.V, &sphere.F, &colours, nullptr, {}};
  SheetOptions options;
  options.view_width = 80;
  options.view_height = 120;
  Eigen::AlignedBox3d box(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1));
  const auto cameras = frame_views(box, options);
  REQUIRE(cameras.size() == 3);
  // The cube fits the narrower side: 2 m * (1 + margin) across 80 pixels.
  CHECK(cameras[0].pixels_per_metre == Approx(80.0 / (2.0 * (1.0 + options.margin))));
  CHECK(cameras[0].width == 80);
  // A wide box fills the height and takes the width it needs, up to view_width.
  options.view_width = 400;
  const auto wide = frame_views(Eigen::AlignedBox3d(Eigen::Vector3d(-2, -1, -0.5), Eigen::Vector3d(2, 1, 0.5)), options);
  CHECK(wide[0].pixels_per_metre == Approx(120.0 / (2.0 * (1.0 + options.margin))));
  CHECK(wide[0].width == 240);  // front: 4 m wide
  CHECK(wide[1].width == 64);   // side: 1 m deep would be 60; no view is narrower than 64
  options.view_width = 80;
  const gp::render::Font font(gp::render::default_font_path());
  const auto scale = gp::render::stretch_scale(0.1);
  options.threads = 1;
  const gp::render::Image one = picture_sheet("t", {{"a", {layer}}, {"b", {layer}}}, cameras, scale, font, options);
  options.threads = 3;
  const gp::render::Image three = picture_sheet("t", {{"a", {layer}}, {"b", {layer}}}, cameras, scale, font, options);
  CHECK(one.width == 3 * 80 + 2 * 6);
  CHECK(one.pixels == three.pixels);
}

TEST_CASE("fit-report: --help lists its options, a missing folder exits 3 naming the file", "[report][cli]") {
  const auto help = gp::testing::run_command(gp::testing::tool_path("fit-report") + " --help");
  CHECK(help.exit_code == 0);
  for (const char* option : {"--view-width", "--view-height", "--supersampling", "--front", "--pattern-width",
                             "--three-dir", "--font", "--out", "--threads", "--workers", "[pixels]"})
    CHECK_THAT(help.out, Catch::Contains(option));
  const fs::path dir = gp::testing::fresh_temp_dir("report_cli");
  fs::create_directories(dir / "fit");
  const auto missing = gp::testing::run_command(gp::testing::tool_path("fit-report") + " " + dir.string() +
                                                " --out " + (dir / "report").string());
  CHECK(missing.exit_code == 3);
  CHECK_THAT(missing.err, Catch::StartsWith("fit-report: error[input]: missing poses/report.json"));
  CHECK_THAT(missing.err, Catch::Contains((dir / "poses" / "report.json").string()));
  CHECK(std::count(missing.err.begin(), missing.err.end(), '\n') == 1);
  CHECK(!fs::exists(dir / "report"));
}

TEST_CASE("fit-report's options are recorded by their field list and read back strictly", "[report]") {
  FitReportOptions options;
  options.sheet.view_width = 300;
  options.sheet.supersampling = 2;
  options.sheet.margin = 0.1;
  options.pattern_width = 900;
  const gp::OrderedJson written = gp::write_options(options, FitReportOptionFields{});
  CHECK(written["sheet"]["view_width_px"] == 300);
  CHECK(written["pattern_width_px"] == 900);
  FitReportOptions back;
  gp::read_options(gp::SpecObject(Json::parse(written.dump()), "report.json", "/options"), true, back,
                   FitReportOptionFields{});
  CHECK(back.sheet.view_width == 300);
  CHECK(back.sheet.view_height == SheetOptions{}.view_height);
  CHECK(back.sheet.supersampling == 2);
  CHECK(back.sheet.margin == 0.1);
  CHECK(back.pattern_width == 900);
  // Out of the range the command line accepts, or missing: named by file and JSON pointer.
  const auto error_of = [&back](const Json& j) -> std::string {
    try {
      gp::read_options(gp::SpecObject(j, "report.json", "/options"), true, back, FitReportOptionFields{});
    } catch (const gp::SpecError& e) {
      return e.message();
    }
    return "";
  };
  Json bad = Json::parse(written.dump());
  bad["sheet"]["supersampling"] = 9;
  CHECK_THAT(error_of(bad), Catch::Contains("report.json") && Catch::Contains("/options/sheet/supersampling") &&
                                Catch::Contains("out of range"));
  bad = Json::parse(written.dump());
  bad.erase("pattern_width_px");
  CHECK_THAT(error_of(bad), Catch::Contains("missing field") && Catch::Contains("/options/pattern_width_px"));
}

// The held pose is read where the run stopped (fit/) or from the run make fit
// kept (fit-held/, with the body that held the cloth), and a malformed entry
// is named by its pointer.
TEST_CASE("where the body held the cloth is read with its places, faces and the body that held it", "[report]") {
  const fs::path dir = gp::testing::fresh_temp_dir("report_held");
  for (const char* sub : {"fit-held", "poses"}) fs::create_directories(dir / sub);
  const fs::path manifest = dir / "poses" / "poses.json";
  gp::testing::write_file(manifest, R"({"poses": [{"name": "apose", "file": "apose.ply", "sha256": "x"}]})");
  for (const char* f : {"draped_00_apose.ply", "rest.ply", "body_apose.ply"}) gp::testing::write_file(dir / "fit-held" / f, "mesh");
  const std::string held = R"({"schema": "simulate-adapt-report/1",
    "key_poses": [{"key": 0, "pose": "apose", "mesh": "draped_00_apose.ply"}],
    "held": {"key": 0, "pose": "apose", "settle_steps": 280,
             "held_cloth": [{"region": "body vertex 2750", "position_m": [0.17, 0.79, 0.135], "gap_mm": null,
                             "max_stretch": 1.5, "faces": [7028, 7029]}]}})";
  StageReport stage;
  stage.stage = "fit-held";
  stage.path = dir / "fit-held" / "report.json";
  stage.json = Json::parse(held);
  const std::optional<HeldPose> h = read_held(stage, dir, manifest);
  REQUIRE(h.has_value());
  CHECK(h->pose == "apose");
  CHECK(h->settle_steps == 280);
  CHECK(h->drape == dir / "fit-held" / "draped_00_apose.ply");
  CHECK(h->body == dir / "fit-held" / "body_apose.ply");
  REQUIRE(h->patches.size() == 1);
  CHECK(h->patches[0].region == "body vertex 2750");
  CHECK(h->patches[0].position[2] == Approx(0.135));
  CHECK(h->patches[0].gap_mm < 0.0);  // no facing body part found: unknown, not 0 mm
  CHECK(h->patches[0].faces == std::vector<int>{7028, 7029});
  // Stopped in fit/ itself: the body is the registered pose.
  fs::create_directories(dir / "fit");
  for (const char* f : {"draped_00_apose.ply", "rest.ply"}) gp::testing::write_file(dir / "fit" / f, "mesh");
  stage.stage = "fit";
  CHECK(read_held(stage, dir, manifest)->body == dir / "poses" / "apose.ply");
  // Not held: nothing.
  stage.json.erase("held");
  CHECK_FALSE(read_held(stage, dir, manifest).has_value());
  // A place without its position is refused, naming the pointer.
  stage.json = Json::parse(held);
  stage.json["held"]["held_cloth"][0]["position_m"] = Json::array({0.1, 0.2});
  try {
    read_held(stage, dir, manifest);
    FAIL("a position of two numbers was accepted");
  } catch (const gp::SpecError& e) {
    CHECK_THAT(e.where(), Catch::EndsWith("report.json: /held/held_cloth/0/position_m"));
  }
}

TEST_CASE("the sewn drape is drawn beside its reference, coloured by their distance", "[report]") {
  // The scale: white at 0, the goal's bounds marked, clamped beyond 30 mm.
  const gp::render::ColourScale scale = drape_distance_scale();
  CHECK(scale.min_value() == 0.0);
  CHECK(scale.max_value() == 30.0);
  int marked = 0;
  for (const auto& t : scale.ticks()) marked += t.marked;
  CHECK(marked == 2);
  CHECK(scale.colour(45.0).r == scale.colour(30.0).r);
  CHECK(scale.colour(0.0).g > scale.colour(15.0).g);
  // A face takes the mean of its corners.
  const gp::Mesh sphere = gp::testing::make_icosphere(2, 0.2);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(sphere.V.rows());
  d(sphere.F(0, 0)) = 0.003;
  CHECK(face_mean_of_vertices(d, sphere.F)(0) == Approx(0.001));

  // A fit folder with one key pose measured: the fit's verified drape, and
  // the sewn drape 10 mm above it with its distance field.
  const fs::path dir = gp::testing::fresh_temp_dir("report-sewn-sheet");
  fs::create_directories(dir / "fit");
  fs::create_directories(dir / "pattern");
  fs::create_directories(dir / "out");
  gp::Mesh verified = sphere;
  verified.V *= 1.05;
  gp::write_mesh(dir / "fit" / "verified_00_apose.ply", verified);
  gp::Mesh sewn = verified;
  sewn.V.col(1).array() += 0.01;
  sewn.vertex_fields.push_back({"distance_to_verified", Eigen::VectorXd::Constant(sewn.V.rows(), 0.01)});
  gp::write_mesh(dir / "pattern" / "sewn_00_apose.ply", sewn);
  FitRun run = small_run();
  run.dir = dir;
  run.pattern.path = dir / "pattern" / "report.json";
  run.pattern.json["sewn_fit"] = Json::parse(R"({"checked": true, "verdict": "fail",
    "drape": {"reference": "the fit's verified drapes"},
    "key_poses": [{"key": 0, "pose": "apose", "mesh": "sewn_00_apose.ply",
      "distance_to_verified": {"verdict": "fail", "verified_mesh": "verified_00_apose.ply", "verified_mesh_in": "fit",
                               "mean_m": 0.01, "p95_m": 0.01, "max_m": 0.01}}]})");
  gp::PoseSet poses;
  poses.names = {"apose", "tpose"};
  poses.V = {sphere.V * 0.8, sphere.V * 0.8};
  poses.F = sphere.F;
  SheetOptions options;
  options.view_width = 80;
  options.view_height = 100;
  options.supersampling = 1;
  const gp::render::Font font(gp::render::default_font_path());
  const std::vector<std::string> files = write_sewn_sheets(run, poses, sphere.F, font, options, dir / "out");
  REQUIRE(files.size() == 2);
  CHECK(files[0] == "renders/sewn_00_apose.png");
  CHECK(files[1].empty());  // the sewn fit measured no drape at tpose
  CHECK(fs::is_regular_file(dir / "out" / files[0]));
  // No distance field: a geometry error naming the file; a missing reference: an input error.
  gp::Mesh plain = sewn;
  plain.vertex_fields.clear();
  gp::write_mesh(dir / "pattern" / "sewn_00_apose.ply", plain);
  CHECK_THROWS_AS(write_sewn_sheets(run, poses, sphere.F, font, options, dir / "out"), gp::GeometryError);
  fs::remove(dir / "fit" / "verified_00_apose.ply");
  CHECK_THROWS_AS(write_sewn_sheets(run, poses, sphere.F, font, options, dir / "out"), gp::InputError);
}

TEST_CASE("the page names where the registration grows the body's skin most, and a dash without it", "[report]") {
  FitRun run = small_run();
  ReportFiles files;
  files.poses.resize(run.keys.size());
  const std::string row = "the body's skin grown most between its poses";
  auto row_of = [&](const std::string& page) {
    const size_t at = page.find(row);
    REQUIRE(at != std::string::npos);
    return page.substr(at, page.find("</tr>", at) - at);
  };
  CHECK(row_of(html_report(run, files, {}, "t")).find("&ndash;") != std::string::npos);
  run.poses.json = Json::parse(R"({"schema": "register-check-report/1", "verdict": "pass", "poses": [
    {"name": "apose", "surface_growth": null},
    {"name": "tpose", "surface_growth": {"radius_m": 0.05, "largest": {"factor": 1.25, "vertex": 3, "at_m": [0, 1, 0]}}},
    {"name": "armsup", "surface_growth": {"radius_m": 0.05, "largest": {"factor": 1.99, "vertex": 7, "at_m": [0, 1, 0]}}}]})");
  const std::string grown = row_of(html_report(run, files, {}, "t"));
  INFO(grown);
  CHECK(grown.find("1.990") != std::string::npos);
  CHECK(grown.find("armsup") != std::string::npos);
  CHECK(grown.find("tpose") == std::string::npos);
}
