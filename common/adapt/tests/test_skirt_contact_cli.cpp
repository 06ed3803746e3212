// The case that was missed, as a user runs it: a generated body with its
// arms hanging beside the hips, a flared skirt designed through the hands and
// the seat, arms up and back. extend-boundary starts the skirt outside the
// body; simulate-adapt keeps it there at every key pose (no crossing in
// either direction, no cloth vertex inside), and the skirt's rest shape does
// not grow from being snagged.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"
#include "testing/skirt_scene.h"

namespace fs = std::filesystem;
using gp::testing::run_command;
using gp::testing::tool_path;

TEST_CASE("a skirt through the hands starts outside the body and stays outside through arms up and back",
          "[adapt][cli][avatar][contact]") {
  const gp::testing::SkirtScene scene = gp::testing::make_skirt_scene();
  const fs::path dir = gp::testing::fresh_temp_dir("skirt_contact_cli");
  const std::string d = dir.string();
  std::ofstream(dir / "avatar.json") << gp::Json({{"schema", "avatar-spec/1"},
                                                  {"poses", {{{"name", "armsdown"},
                                                              {"joints", {{"l_shoulder", {0, 0, -22}},
                                                                          {"r_shoulder", {0, 0, 22}},
                                                                          {"l_elbow", {0, 0, -15}},
                                                                          {"r_elbow", {0, 0, 15}}}}}}}})
                                            .dump(2);
  std::ofstream(dir / "top.json") << scene.top_spec.dump(2);
  std::ofstream(dir / "extend.json") << scene.extend_spec.dump(2);
  std::ofstream(dir / "motion.json")
      << gp::Json({{"schema", "motion/1"}, {"steps", 30}, {"sequence", {"armsdown", "armsup", "armsdown"}}}).dump(2);

  auto run = [](const std::string& command) {
    const auto r = run_command(command);
    INFO(command << "\n" << r.err);
    REQUIRE(r.exit_code == 0);
  };
  run(tool_path("make-avatar") + " " + d + "/avatar.json --poses apose,armsdown,armsup --out " + d + "/body -q");
  run(tool_path("register-check") + " " + d + "/body --reference armsdown --out " + d + "/poses -q");
  run(tool_path("make-garment") + " " + d + "/top.json --poses " + d + "/poses/poses.json --out " + d + "/garment -q");
  run(tool_path("extend-boundary") + " " + d + "/garment/garment.json " + d + "/extend.json --out " + d + "/extended -q");
  const gp::Json extended = gp::read_json_file(dir / "extended" / "report.json");
  const gp::Json& clearance = extended["body_clearance"];
  CHECK(clearance["before"]["cloth_vertices_inside"].get<long>() > 0);
  CHECK(clearance["clear"].get<bool>());
  CHECK(clearance["after"]["intersection_free"].get<bool>());

  run(tool_path("simulate-adapt") + " --poses " + d + "/poses/poses.json --motion " + d + "/motion.json --garment " + d +
      "/extended/garment.json --settle-max-steps 150 --out " + d + "/fit -q");
  const gp::Json report = gp::read_json_file(dir / "fit" / "report.json");
  CHECK(report["run"]["continuous_contact_active"].get<bool>());
  REQUIRE(report["key_poses"].size() == 3);
  for (const gp::Json& key : report["key_poses"]) {
    INFO("key pose " << key["key"] << " " << key["pose"]);
    const gp::Json& c = key["crossings"];
    CHECK(c["body_edge_crossings"].get<long>() == 0);
    CHECK(c["cloth_edge_crossings"].get<long>() == 0);
    CHECK(c["cloth_vertices_inside"].get<long>() == 0);
    CHECK(c["deepest_cloth_vertex_m"].get<double>() <= 1e-3);
    CHECK(c["intersection_free"].get<bool>());
  }
  CHECK(report["run"]["rest_area_growth"].get<double>() < 1.2);
  fs::remove_all(dir);
}
