#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>

#include "core/sha256.h"
#include "interp_fixtures.h"
#include "pose/pose_set.h"
#include "io/mesh_io.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"

namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

// Two poses of a small generated body and a motion between them in `dir`.
void write_inputs(const fs::path& dir) {
  const gp::Mesh rest = interp_test::make_scarecrow(40, 12);
  gp::Mesh down = rest, up = rest;
  down.V = interp_test::pose_scarecrow(rest.V, -50.0);
  up.V = interp_test::pose_scarecrow(rest.V, 70.0);
  gp::write_mesh(dir / "down.ply", down);
  gp::write_mesh(dir / "up.ply", up);
  write_text(dir / "motion.json",
             R"({"schema": "motion/1", "steps": 4, "sequence": ["down", "up", {"pose": "down", "steps": 2}]})");
}

std::string tool() { return gp::testing::tool_path("interp-poses"); }

}  // namespace

TEST_CASE("interp-poses writes frames, a manifest and a report", "[interp][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("interp_cli_ok");
  write_inputs(dir);
  const std::string inputs = "'" + (dir / "down.ply").string() + "' '" + (dir / "up.ply").string() + "'";
  const std::string motion = " --motion '" + (dir / "motion.json").string() + "'";
  const auto r = gp::testing::run_command(tool() + " " + inputs + motion + " --out '" +
                                          (dir / "out").string() + "' -q");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::Json manifest = gp::read_json_file(dir / "out" / "motion.json");
  CHECK(manifest["schema"] == "motion-frames/1");
  CHECK(manifest["frame_count"] == 7);
  CHECK(manifest["frames"][4]["key"] == "up");
  CHECK(manifest["frames"][2]["t"] == 0.5);
  for (int i = 0; i < 7; ++i) CHECK(fs::exists(dir / "out" / manifest["frames"][i]["file"].get<std::string>()));
  // The key frame reproduces the pose file.
  const gp::Mesh up = gp::read_mesh(dir / "up.ply").mesh;
  const gp::Mesh frame4 = gp::read_mesh(dir / "out" / "frame_00004.ply").mesh;
  CHECK((frame4.V - up.V).cwiseAbs().maxCoeff() < 1e-6 * interp_test::height(up.V));
  CHECK(frame4.F == up.F);
  const gp::Json report = gp::read_json_file(dir / "out" / "report.json");
  CHECK(report["schema"] == "interp-poses-report/1");
  CHECK(report["options"]["method"] == "nonlinear");
  CHECK(report["motion"]["steps"] == 4);
  CHECK_FALSE(report.contains("timing"));
  CHECK(report["frames"].size() == 7);
  CHECK(report["summary"]["volume_excess_max"].get<double>() < 0.02);
  CHECK(report["summary"]["linear_vs_nonlinear"]["edge_deviation_max"].get<double>() > 0.05);

  // Same inputs, same bytes.
  const auto again = gp::testing::run_command(tool() + " " + inputs + motion + " --out '" +
                                              (dir / "out2").string() + "' -q");
  REQUIRE(again.exit_code == 0);
  for (const char* name : {"motion.json", "report.json", "frame_00002.ply", "frame_00006.ply"})
    CHECK(gp::testing::read_file(dir / "out" / name) == gp::testing::read_file(dir / "out2" / name));

  // Only selected frames; timing in its own file; linear method.
  const auto keys = gp::testing::run_command(tool() + " " + inputs + motion + " --keys-only --method linear --out '" +
                                             (dir / "keys").string() + "' -q");
  REQUIRE(keys.exit_code == 0);
  const gp::Json kman = gp::read_json_file(dir / "keys" / "motion.json");
  CHECK(kman["frames_written"] == 3);
  CHECK(kman["frames"][1]["file"].is_null());
  CHECK(fs::exists(dir / "keys" / "frame_00006.ply"));
  CHECK_FALSE(fs::exists(dir / "keys" / "frame_00001.ply"));
  const gp::Json kreport = gp::read_json_file(dir / "keys" / "report.json");
  CHECK(kreport["options"]["method"] == "linear");
  const gp::Json ktiming = gp::read_json_file(dir / "keys" / "timing.json");
  CHECK(ktiming["schema"] == "timing/1");
  CHECK(ktiming["ms_per_frame_mean"].get<double>() >= 0.0);

  const auto some = gp::testing::run_command(tool() + " " + inputs + motion + " --frames 1,5 --out '" +
                                             (dir / "some").string() + "' -q");
  REQUIRE(some.exit_code == 0);
  CHECK(gp::read_json_file(dir / "some" / "motion.json")["frames_written"] == 2);
  CHECK(fs::exists(dir / "some" / "frame_00005.ply"));

  // An existing output folder is kept without --force.
  const auto exists = gp::testing::run_command(tool() + " " + inputs + motion + " --out '" +
                                               (dir / "out").string() + "' -q");
  CHECK(exists.exit_code == 2);
  fs::remove_all(dir);
}

TEST_CASE("interp-poses reads a poses.json manifest", "[interp][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("interp_cli_manifest");
  write_inputs(dir);
  const gp::Mesh down = gp::read_mesh(dir / "down.ply").mesh;
  gp::PoseSetManifest m;
  m.vertex_count = down.V.rows();
  m.face_count = down.F.rows();
  m.topology_sha256 = gp::topology_checksum(down.F);
  m.reference = "down";
  for (const char* name : {"down", "up"})
    m.poses.push_back({name, std::string(name) + ".ply", gp::sha256_file_hex(dir / (std::string(name) + ".ply")), "test"});
  gp::write_pose_set_manifest(dir / "poses.json", m);
  const auto r = gp::testing::run_command(tool() + " '" + (dir / "poses.json").string() + "' --motion '" +
                                          (dir / "motion.json").string() + "' --keys-only --out '" +
                                          (dir / "out").string() + "' -q");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::Json manifest = gp::read_json_file(dir / "out" / "motion.json");
  CHECK(manifest["pose_set"]["names"] == gp::Json::array({"down", "up"}));
  CHECK(manifest["pose_set"]["topology_sha256"] == m.topology_sha256);
  CHECK(manifest["frames_written"] == 3);
  fs::remove_all(dir);
}

TEST_CASE("interp-poses exits with the category's code on bad input", "[interp][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("interp_cli_bad");
  write_inputs(dir);
  const std::string inputs = "'" + (dir / "down.ply").string() + "' '" + (dir / "up.ply").string() + "'";
  auto run = [&](const std::string& motion_text, const std::string& extra = "") {
    write_text(dir / "bad.json", motion_text);
    return gp::testing::run_command(tool() + " " + inputs + " --motion '" + (dir / "bad.json").string() +
                                    "' --out '" + (dir / "out").string() + "' " + extra);
  };
  {
    const auto r = run(R"({"schema": "motion/1", "sequence": ["down", "waving"]})");
    CHECK(r.exit_code == 4);
    CHECK_THAT(r.err, Catch::Contains("interp-poses: error[spec]: unknown pose 'waving'") &&
                          Catch::Contains("/sequence/1"));
  }
  {
    const auto r = run(R"({"schema": "motion/1", "steps": 0, "sequence": ["down", "up"]})");
    CHECK(r.exit_code == 4);
    CHECK_THAT(r.err, Catch::Contains("error[spec]") && Catch::Contains("/steps"));
  }
  {
    const auto r = run(R"({"schema": "motion/1", "sequence": ["down", {"pose": "up", "steps": 0}]})");
    CHECK(r.exit_code == 4);
    CHECK_THAT(r.err, Catch::Contains("/sequence/1/steps"));
  }
  {
    const auto r = run(R"({"schema": "motion/1", "sequence": ["down", "up"])");
    CHECK(r.exit_code == 3);  // malformed JSON is an input error
  }
  {
    const auto r = run(R"({"schema": "motion/1", "sequence": ["down", "up"]})", "--frames 99");
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("--frames"));
  }
  {
    const auto r = run(R"({"schema": "motion/1", "sequence": ["down", "up"]})", "--method cubic");
    CHECK(r.exit_code == 2);
  }
  {
    // Poses with different connectivity.
    gp::Mesh other = interp_test::make_scarecrow(40, 10);
    gp::write_mesh(dir / "other.ply", other);
    write_text(dir / "ok.json", R"({"schema": "motion/1", "sequence": ["down", "other"]})");
    const auto r = gp::testing::run_command(tool() + " '" + (dir / "down.ply").string() + "' '" +
                                            (dir / "other.ply").string() + "' --motion '" +
                                            (dir / "ok.json").string() + "' --out '" + (dir / "out").string() + "'");
    CHECK(r.exit_code == 5);
    CHECK_THAT(r.err, Catch::Contains("error[geometry]") && Catch::Contains("other.ply"));
  }
  {
    const auto r = gp::testing::run_command(tool() + " '" + (dir / "missing.ply").string() + "' --motion '" +
                                            (dir / "motion.json").string() + "' --out '" +
                                            (dir / "out").string() + "'");
    CHECK(r.exit_code == 3);
  }
  CHECK_FALSE(fs::exists(dir / "out"));  // no partial output after any failure
  fs::remove_all(dir);
}
