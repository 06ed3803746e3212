// make-avatar as a user runs it: outputs, manifest, determinism, exit codes.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "avatar/skeleton.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"

namespace fs = std::filesystem;

namespace {

fs::path write_spec(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

std::string run_tool(const std::string& args) { return gp::testing::tool_path("make-avatar") + " " + args; }

}  // namespace

TEST_CASE("make-avatar writes a pose set that later stages load", "[avatar][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("make_avatar_cli");
  const fs::path out = dir / "body";
  const std::string args = "--resolution small --poses tpose,apose,seated --out '" + out.string() + "'";
  const auto r = gp::testing::run_command(run_tool(args));
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  for (const char* f :
       {"apose.ply", "tpose.ply", "seated.ply", "poses.json", "skeleton.json", "report.json", "timing.json"})
    CHECK(fs::exists(out / f));
  // The manifest's checksums and shared connectivity are verified on load.
  const gp::PoseSet ps = gp::load_pose_set(out / "poses.json");
  CHECK(ps.names == std::vector<std::string>{"apose", "tpose", "seated"});
  CHECK(ps.reference == "apose");
  CHECK(ps.V[0].rows() <= 2000);
  const gp::PoseSetManifest m = gp::read_pose_set_manifest(out / "poses.json");
  CHECK(m.topology_sha256 == gp::topology_checksum(ps.F));

  const gp::Json sk = gp::read_json_file(out / "skeleton.json");
  CHECK(sk["schema"] == "skeleton/1");
  CHECK(sk["joints"].size() == static_cast<size_t>(gp::kJointCount));
  CHECK(sk["joints"][0]["parent"].is_null());
  CHECK(sk["joints"][gp::kLElbow]["parent"] == "l_shoulder");
  CHECK(sk["poses"].size() == 3);
  CHECK(sk["poses"][1]["positions"].size() == static_cast<size_t>(gp::kJointCount));

  const gp::Json rep = gp::read_json_file(out / "report.json");
  CHECK(rep["schema"] == "make-avatar-report/1");
  CHECK(rep["measurements"]["height"] == 1.7);
  CHECK(rep["options"]["target_vertices"] == 2000);
  CHECK(rep["mesh"]["vertex_count"] == ps.V[0].rows());
  CHECK(rep["girths"].size() == 11);
  CHECK(rep["max_girth_error_m"].get<double>() < 0.01);
  CHECK(rep["max_pairwise_volume_change"].get<double>() < 0.03);

  SECTION("an existing output folder is replaced only with --force") {
    const auto again = gp::testing::run_command(run_tool(args));
    CHECK(again.exit_code == 2);
    const auto forced = gp::testing::run_command(run_tool(args + " --force"));
    REQUIRE(forced.exit_code == 0);
  }
  SECTION("same inputs give byte-identical files") {
    const fs::path out2 = dir / "body2";
    const auto r2 = gp::testing::run_command(
        run_tool("--resolution small --poses tpose,apose,seated --out '" + out2.string() + "'"));
    REQUIRE(r2.exit_code == 0);
    for (const char* f :
         {"apose.ply", "tpose.ply", "seated.ply", "poses.json", "skeleton.json", "report.json"})
      CHECK(gp::testing::read_file(out / f) == gp::testing::read_file(out2 / f));
  }
}

TEST_CASE("make-avatar rejects bad specs with exit 4 naming the field", "[avatar][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("make_avatar_bad");
  struct Case {
    const char* text;
    const char* field;
  };
  const Case cases[] = {
      {R"({"schema": "avatar-spec/1", "measurements": {"waist": -0.76}})", "/measurements/waist"},
      {R"({"schema": "avatar-spec/1", "measurements": {"height": 1.7, "waist": 1.9}})",
       "/measurements/waist"},
      {R"({"schema": "avatar-spec/1", "measurements": {"hips": 0.98}})", "/measurements/hips"},
      {R"({"schema": "avatar-spec/3"})", "/schema"},
      {R"({"schema": "avatar-spec/1", "poses": [{"name": "p", "joints": {"tail": [0, 0, 0]}}]})",
       "/poses/0/joints/tail"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const fs::path spec = write_spec(dir, "bad" + std::to_string(i++) + ".json", c.text);
    const auto r = gp::testing::run_command(
        run_tool("'" + spec.string() + "' --resolution small --out '" + (dir / "out").string() + "'"));
    INFO(c.text << "\n" << r.err);
    CHECK(r.exit_code == 4);
    CHECK(r.err.find("make-avatar: error[spec]") != std::string::npos);
    CHECK(r.err.find(c.field) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
  SECTION("unreadable or malformed input is an input error") {
    const fs::path broken = write_spec(dir, "broken.json", "{\"schema\": ");
    CHECK(gp::testing::run_command(run_tool("'" + broken.string() + "' --out '" + (dir / "o").string() + "'"))
              .exit_code == 3);
    CHECK(gp::testing::run_command(
              run_tool("'" + (dir / "missing.json").string() + "' --out '" + (dir / "o").string() + "'"))
              .exit_code == 3);
  }
  SECTION("an unknown pose is a spec error, a bad option a usage error") {
    const auto r =
        gp::testing::run_command(run_tool("--poses apose,cartwheel --out '" + (dir / "o").string() + "'"));
    CHECK(r.exit_code == 4);
    CHECK(r.err.find("cartwheel") != std::string::npos);
    CHECK(gp::testing::run_command(run_tool("--resolution huge --out '" + (dir / "o").string() + "'"))
              .exit_code == 2);
    CHECK(
        gp::testing::run_command(run_tool("--vertices 10 --out '" + (dir / "o").string() + "'")).exit_code ==
        2);
  }
}

TEST_CASE("make-avatar --help lists options with defaults and units", "[avatar][cli]") {
  const auto r = gp::testing::run_command(run_tool("--help"));
  CHECK(r.exit_code == 0);
  for (const char* s :
       {"--resolution", "default", "[preset]", "--vertices", "[vertices]", "--poses", "--out"})
    CHECK(r.out.find(s) != std::string::npos);
}

TEST_CASE("the generated pose set passes register-check", "[avatar][cli]") {
  const std::string rc = gp::testing::tool_path("register-check");
  if (!fs::exists(rc.substr(1, rc.size() - 2))) {
    WARN("skipped: register-check is not built");
    return;
  }
  const fs::path dir = gp::testing::fresh_temp_dir("make_avatar_rc");
  const fs::path spec = gp::testing::source_dir() / "testdata" / "avatars" / "maternity.json";
  const auto made = gp::testing::run_command(
      run_tool("'" + spec.string() + "' --resolution small --out '" + (dir / "body").string() + "'"));
  REQUIRE(made.exit_code == 0);
  std::string files;
  for (const char* p : {"apose", "tpose", "armsup", "armsforward", "elbowsbent", "stepforward", "seated", "handsonthighs"})
    files += " '" + (dir / "body" / (std::string(p) + ".ply")).string() + "'";
  const auto r = gp::testing::run_command(rc + files + " --out '" + (dir / "checked").string() + "'");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  const gp::Json rep = gp::read_json_file(dir / "checked" / "report.json");
  for (const auto& p : rep["poses"]) {
    INFO(p["name"]);
    CHECK(p["checks"]["self_intersecting_pairs"] == 0);
    CHECK(p["checks"]["nonmanifold_edges"] == 0);
    CHECK(p["checks"]["boundary_loops"] == 0);
    CHECK(p["checks"]["components"] == 1);
  }
}
