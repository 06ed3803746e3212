// simulate-adapt refuses a pose set whose design pose is another body than
// the one the garment file records (same template, other shape), in one line
// with exit 5 naming the pose and both checksums, and fits it when asked
// with --other-body.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

#include "core/sha256.h"
#include "garment/design_body.h"
#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;

namespace {

// A pose set of one pose "a", a sphere of the given radius, made in `dir` by
// register-check as the pipeline makes it.
void write_body(const fs::path& dir, double radius) {
  fs::create_directories(dir);
  gp::write_mesh(dir / "a.ply", gp::testing::make_icosphere(3, radius));
  const auto r = gp::testing::run_command(gp::testing::tool_path("register-check") + " " + (dir / "a.ply").string() +
                                          " --units m --up +y --quiet --out " + (dir / "set").string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
}

// A free cap over the top of the body of `body_dir`, 1 cm out, designed on its pose "a".
void write_cap(const fs::path& dir, const fs::path& body_dir) {
  const gp::PoseSet set = gp::load_pose_set(body_dir / "set" / "poses.json");
  gp::Mesh body;
  body.V = set.V[0];
  body.F = set.F;
  std::vector<int> top;
  for (int f = 0; f < body.F.rows(); ++f)
    if (body.V(body.F(f, 0), 1) > 0.1 && body.V(body.F(f, 1), 1) > 0.1 && body.V(body.F(f, 2), 1) > 0.1)
      top.push_back(f);
  gp::Mesh cap = gp::testing::face_subset(body, top).mesh;
  const double radius = body.V.row(0).norm();
  cap.V *= (radius + 0.01) / radius;
  gp::write_mesh(dir / "garment.ply", cap);
  gp::GarmentFile g;
  g.name = "cap";
  g.mesh_sha256 = gp::sha256_file_hex(dir / "garment.ply");
  g.vertex_count = cap.V.rows();
  g.face_count = cap.F.rows();
  g.body.source = (body_dir / "set" / "poses.json").string();
  g.body.source_sha256 = gp::sha256_file_hex(body_dir / "set" / "poses.json");
  g.body.design_pose = "a";
  g.body.vertex_count = body.V.rows();
  g.body.face_count = body.F.rows();
  g.body.topology_sha256 = gp::topology_checksum(body.F);
  g.body.design_pose_sha256 = gp::vertex_checksum(body.V);
  g.spec_file = "none";
  g.spec_sha256 = "none";
  g.target_edge_length = 0.05;
  g.offset = 0.01;
  g.paint.assign(static_cast<size_t>(cap.F.rows()), 1.0);
  gp::write_garment_file(dir / "garment.json", g);
}

}  // namespace

TEST_CASE("the design pose's checksum travels in the garment file and tells another body", "[garment][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("design_body");
  write_body(dir / "same", 0.2);
  write_body(dir / "other", 0.19);  // the same template, another body
  write_cap(dir, dir / "same");
  gp::OrderedJson motion;
  motion["schema"] = gp::schema_tag("motion", 1);
  motion["steps"] = 2;
  motion["sequence"] = {"a", "a"};
  gp::write_json_file(dir / "motion.json", motion);

  const gp::GarmentFile g = gp::read_garment_file(dir / "garment.json");
  CHECK(g.body.design_pose_sha256.size() == 64);
  const gp::DesignPoseMatch same = gp::match_design_pose(g, gp::load_pose_set(dir / "same" / "set" / "poses.json"));
  CHECK(same.checked);
  CHECK(same.same);
  const gp::DesignPoseMatch other = gp::match_design_pose(g, gp::load_pose_set(dir / "other" / "set" / "poses.json"));
  CHECK(other.checked);
  CHECK_FALSE(other.same);
  CHECK(other.expected == g.body.design_pose_sha256);
  CHECK(other.actual != other.expected);

  const auto run = [&](const std::string& body, const std::string& out, const std::string& extra) {
    return gp::testing::run_command(gp::testing::tool_path("simulate-adapt") + " --poses " +
                                    (dir / body / "set" / "poses.json").string() + " --motion " +
                                    (dir / "motion.json").string() + " --garment " +
                                    (dir / "garment.json").string() + " --out " + (dir / out).string() +
                                    " --quiet --no-verify --settle-max-steps 5 " + extra);
  };
  const auto refused = run("other", "o_other", "");
  CHECK(refused.exit_code == 5);
  // One line naming the pose, both checksums and the way out; no output.
  CHECK(std::count(refused.err.begin(), refused.err.end(), '\n') == 1);
  CHECK_THAT(refused.err, Catch::StartsWith("simulate-adapt: error[geometry]: pose 'a' of the pose set is another body") &&
                              Catch::Contains(other.actual.substr(0, 16)) &&
                              Catch::Contains(other.expected.substr(0, 16)) && Catch::Contains("--other-body"));
  CHECK_FALSE(fs::exists(dir / "o_other"));

  const auto same_run = run("same", "o_same", "");
  INFO(same_run.err);
  CHECK(same_run.exit_code == 0);
  const auto deliberate = run("other", "o_deliberate", "--other-body");
  INFO(deliberate.err);
  CHECK(deliberate.exit_code == 0);
  const gp::Json report = gp::read_json_file(dir / "o_deliberate" / "report.json");
  CHECK(report["options"]["other_body"] == true);
  // Carried with the body (1 cm inwards, the radius' change) and clear of it.
  CHECK(report["other_body"]["carried_with_body"] == true);
  CHECK(report["other_body"]["largest_carry_m"].get<double>() == Approx(0.01).epsilon(0.05));
  CHECK(report["other_body"]["clearance"]["clear"] == true);
  fs::remove_all(dir);
}
