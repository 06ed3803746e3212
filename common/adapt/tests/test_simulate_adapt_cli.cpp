// simulate-adapt as a user runs it: a cap garment pinned around a sphere body
// whose top grows by 25 % in the second pose. With adaptation the cap's rest
// shape grows and the stretch stays near 1.1; --no-adapt shows the stretch;
// runs are byte-identical; bad inputs give the documented exit codes.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/sha256.h"
#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "mesh/topology.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Writes poses.json (poses "a" and "b"), motion.json and garment.json/.ply into dir.
// The cap garment sits at radius r + start_distance (the offset by default).
void write_scene(const fs::path& dir, double start_distance = 0.01) {
  const double r = 0.2, offset = 0.01;
  const gp::Mesh body = gp::testing::make_icosphere(3, r);
  gp::Mesh grown = body;
  for (int v = 0; v < grown.V.rows(); ++v) {
    if (grown.V(v, 1) > 0.0) grown.V(v, 1) *= 1.4;
  }
  gp::write_mesh(dir / "a.ply", body);
  gp::write_mesh(dir / "b.ply", grown);
  gp::PoseSetManifest manifest;
  manifest.vertex_count = body.V.rows();
  manifest.face_count = body.F.rows();
  manifest.topology_sha256 = gp::topology_checksum(body.F);
  manifest.reference = "a";
  manifest.poses = {{"a", "a.ply", gp::sha256_file_hex(dir / "a.ply"), "test"},
                    {"b", "b.ply", gp::sha256_file_hex(dir / "b.ply"), "test"}};
  gp::write_pose_set_manifest(dir / "poses.json", manifest);

  gp::OrderedJson motion;
  motion["schema"] = gp::schema_tag("motion", 1);
  motion["steps"] = 20;
  motion["sequence"] = {"a", "b", "a"};
  gp::write_json_file(dir / "motion.json", motion);

  // The cap: body faces above y = 0.1, pushed out to the offset.
  std::vector<int> cap_faces;
  for (int f = 0; f < body.F.rows(); ++f) {
    bool above = true;
    for (int k = 0; k < 3; ++k) above = above && body.V(body.F(f, k), 1) > 0.1;
    if (above) cap_faces.push_back(f);
  }
  const gp::testing::SubMesh sub = gp::testing::face_subset(body, cap_faces);
  gp::Mesh cap = sub.mesh;
  cap.V *= (r + start_distance) / r;
  gp::write_mesh(dir / "garment.ply", cap);

  gp::GarmentFile g;
  g.name = "cap";
  g.mesh_file = "garment.ply";
  g.mesh_sha256 = gp::sha256_file_hex(dir / "garment.ply");
  g.vertex_count = cap.V.rows();
  g.face_count = cap.F.rows();
  g.body.source = "poses.json";
  g.body.source_sha256 = gp::sha256_file_hex(dir / "poses.json");
  g.body.design_pose = "a";
  g.body.vertex_count = body.V.rows();
  g.body.face_count = body.F.rows();
  g.body.topology_sha256 = manifest.topology_sha256;
  g.spec_file = "none";
  g.spec_sha256 = "none";
  g.target_edge_length = 0.05;
  g.offset = offset;
  const std::vector<std::vector<int>> loops = gp::boundary_loops(cap.F);
  REQUIRE(loops.size() == 1);
  gp::GarmentLoop loop;
  loop.name = "rim";
  loop.pinned = true;
  const std::vector<std::vector<int>> incident = gp::vertex_faces(body.F, static_cast<int>(body.V.rows()));
  for (int v : loops[0]) {
    loop.vertex_ids.push_back(v);
    const int b = sub.vertex_ids[static_cast<size_t>(v)];
    gp::SurfacePoint p;
    p.face = incident[static_cast<size_t>(b)][0];
    for (int k = 0; k < 3; ++k) p.bary(k) = body.F(p.face, k) == b ? 1.0 : 0.0;
    loop.binding.push_back(p);
  }
  g.loops.push_back(loop);
  g.paint.assign(static_cast<size_t>(cap.F.rows()), 1.0);
  gp::write_garment_file(dir / "garment.json", g);
}

std::string command(const fs::path& dir, const std::string& out, const std::string& extra = "") {
  return gp::testing::tool_path("simulate-adapt") + " --poses " + (dir / "poses.json").string() + " --motion " +
         (dir / "motion.json").string() + " --garment " + (dir / "garment.json").string() + " --out " +
         (dir / out).string() + " --quiet --settle-max-steps 200 " + extra;
}

}  // namespace

TEST_CASE("simulate-adapt grows the rest shape where the body stretches the cloth", "[cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("simulate_adapt_cli");
  write_scene(dir);

  const auto run = gp::testing::run_command(command(dir, "adapted"));
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const gp::Json report = gp::read_json_file(dir / "adapted" / "report.json");
  CHECK(report["schema"] == "simulate-adapt-report/1");
  REQUIRE(report["key_poses"].size() == 3);
  const gp::Json& up = report["key_poses"][1];
  INFO("adapted pose b: max " << up["max_stretch"] << " p99 " << up["p99_stretch"] << " growth "
                             << up["rest_area_growth"] << " deepest " << up["deepest_penetration_m"]);
  CHECK(up["pose"] == "b");
  CHECK(up["rest_area_growth"].get<double>() > 1.005);
  CHECK(up["p99_stretch"].get<double>() <= 1.12);
  CHECK(up["area_fraction_above_limit"].get<double>() < 0.01);
  for (const auto& k : report["key_poses"]) {
    CHECK(k["deepest_penetration_m"].get<double>() <= 0.002);
    // Settled means the rest shape reached its fixed point: under 0.1 % area
    // change over the last 100 settle steps.
    CHECK(k["settled"] == true);
    CHECK(k["settle_steps"].get<int>() >= 100);
    CHECK(k["rest_area_change_last_window"].get<double>() < 1e-3);
    // Settled also means no vertex moved on at more than --settle-speed
    // (default 0.05 m/s) over the last check.
    CHECK(k["max_net_speed_m_per_s"].get<double>() < 0.05);
    CHECK(k["max_speed_m_per_s"].get<double>() >= 0.0);
  }
  CHECK(report["run"]["arap_converged"] == true);
  CHECK(fs::exists(dir / "adapted" / "rest.ply"));
  CHECK(fs::exists(dir / "adapted" / "timing.json"));
  const gp::MeshReadResult draped = gp::read_mesh(dir / "adapted" / "draped_01_b.ply");
  REQUIRE(gp::find_field(draped.mesh.face_fields, "max_stretch") != nullptr);

  // The design does not fit pose b: the verdict fails (exit 8), and the
  // report is written all the same.
  const auto fixed = gp::testing::run_command(command(dir, "fixed", "--no-adapt"));
  INFO(fixed.err);
  REQUIRE(fixed.exit_code == 8);
  CHECK(fixed.err.find("error[check]") != std::string::npos);
  const gp::Json fixed_report = gp::read_json_file(dir / "fixed" / "report.json");
  CHECK(fixed_report["verification"]["verdict"] == "fail");
  INFO("fixed pose b: max " << fixed_report["key_poses"][1]["max_stretch"]);
  CHECK(fixed_report["key_poses"][1]["max_stretch"].get<double>() > 1.15);
  CHECK(fixed_report["key_poses"][1]["rest_area_growth"].get<double>() == 1.0);

  // Same inputs, same outputs, byte for byte.
  const auto again = gp::testing::run_command(command(dir, "again"));
  REQUIRE(again.exit_code == 0);
  CHECK(read_bytes(dir / "adapted" / "report.json") == read_bytes(dir / "again" / "report.json"));
  CHECK(read_bytes(dir / "adapted" / "rest.ply") == read_bytes(dir / "again" / "rest.ply"));
  CHECK(read_bytes(dir / "adapted" / "draped_01_b.ply") == read_bytes(dir / "again" / "draped_01_b.ply"));
}

TEST_CASE("simulate-adapt reports bad inputs with their exit codes", "[cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("simulate_adapt_errors");
  write_scene(dir);
  const auto unknown = gp::testing::run_command(command(dir, "o1", "--no-such-flag"));
  CHECK(unknown.exit_code == 2);
  const auto negative_lag = gp::testing::run_command(command(dir, "o4", "--adaptation-lag -1"));
  CHECK(negative_lag.exit_code == 2);
  CHECK(negative_lag.err.find("--adaptation-lag") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "o4"));
  const auto missing = gp::testing::run_command(gp::testing::tool_path("simulate-adapt") + " --poses " +
                                                (dir / "poses.json").string() + " --motion " +
                                                (dir / "motion.json").string() + " --garment " +
                                                (dir / "nothere.json").string() + " --out " + (dir / "o2").string());
  CHECK(missing.exit_code == 3);
  CHECK(missing.err.find("simulate-adapt: error[") != std::string::npos);
  gp::OrderedJson bad;
  bad["schema"] = gp::schema_tag("motion", 1);
  bad["sequence"] = {"a", "nope"};
  gp::write_json_file(dir / "motion.json", bad);
  const auto spec = gp::testing::run_command(command(dir, "o3"));
  CHECK(spec.exit_code == 4);
  CHECK(spec.err.find("sequence") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "o3"));
}

TEST_CASE("simulate-adapt pushes a garment that starts inside the body out gradually", "[cli]") {
  // The cap starts 1 cm inside the sphere, 2 cm short of its offset: one
  // projection would tear it; the ramped offsets push it out over steps.
  const fs::path dir = gp::testing::fresh_temp_dir("simulate_adapt_cli_inside");
  write_scene(dir, -0.01);
  const auto run = gp::testing::run_command(command(dir, "adapted"));
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const gp::Json report = gp::read_json_file(dir / "adapted" / "report.json");
  CHECK(report["run"]["initial_min_distance_m"].get<double>() < -0.005);
  for (const auto& k : report["key_poses"]) {
    CHECK(k["deepest_penetration_m"].get<double>() <= 0.002);
    CHECK(k["settled"] == true);
  }
}
