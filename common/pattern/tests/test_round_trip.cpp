// export-rest's round trip on a small generated scene: a cap pinned around a
// sphere body (one pose). The cap is doubly curved, so its pattern has extra
// cuts; sewn back from the flat pieces it must drape like the rest shape
// itself, and a pattern far from the rest shape must not.
#include <catch2/catch.hpp>

#include <filesystem>

#include "core/sha256.h"
#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "mesh/topology.h"
#include "pattern/make_pattern.h"
#include "pattern/layout.h"
#include "pattern/round_trip.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using namespace gp;

namespace {

struct CapScene {
  fs::path dir;
  PoseSet poses;
  GarmentFile garment;
  Mesh cap;
};

// poses.json (one pose "a": an icosphere of radius 0.2 m), garment.json and
// garment.ply: the body's faces above y = 0.1 at the comfort offset (1 cm),
// its rim pinned to the body.
CapScene write_cap_scene(const std::string& name) {
  CapScene s;
  s.dir = testing::fresh_temp_dir(name);
  const double r = 0.2, offset = 0.01;
  const Mesh body = testing::make_icosphere(3, r);
  write_mesh(s.dir / "a.ply", body);
  PoseSetManifest manifest;
  manifest.vertex_count = body.V.rows();
  manifest.face_count = body.F.rows();
  manifest.topology_sha256 = topology_checksum(body.F);
  manifest.reference = "a";
  manifest.poses = {{"a", "a.ply", sha256_file_hex(s.dir / "a.ply"), "test"}};
  write_pose_set_manifest(s.dir / "poses.json", manifest);
  s.poses = load_pose_set(s.dir / "poses.json");

  std::vector<int> cap_faces;
  for (int f = 0; f < body.F.rows(); ++f) {
    bool above = true;
    for (int k = 0; k < 3; ++k) above = above && body.V(body.F(f, k), 1) > 0.1;
    if (above) cap_faces.push_back(f);
  }
  const gp::testing::SubMesh sub = gp::testing::face_subset(body, cap_faces);
  s.cap = sub.mesh;
  s.cap.V *= (r + offset) / r;
  write_mesh(s.dir / "garment.ply", s.cap);

  GarmentFile& g = s.garment;
  g.name = "cap";
  g.mesh_file = "garment.ply";
  g.mesh_sha256 = sha256_file_hex(s.dir / "garment.ply");
  g.vertex_count = s.cap.V.rows();
  g.face_count = s.cap.F.rows();
  g.body.source = "poses.json";
  g.body.source_sha256 = sha256_file_hex(s.dir / "poses.json");
  g.body.design_pose = "a";
  g.body.vertex_count = body.V.rows();
  g.body.face_count = body.F.rows();
  g.body.topology_sha256 = manifest.topology_sha256;
  g.spec_file = "none";
  g.spec_sha256 = "none";
  g.target_edge_length = 0.05;
  g.offset = offset;
  const std::vector<std::vector<int>> loops = boundary_loops(s.cap.F);
  REQUIRE(loops.size() == 1);
  GarmentLoop loop;
  loop.name = "rim";
  loop.pinned = true;
  const std::vector<std::vector<int>> incident = vertex_faces(body.F, static_cast<int>(body.V.rows()));
  for (int v : loops[0]) {
    loop.vertex_ids.push_back(v);
    const int b = sub.vertex_ids[static_cast<size_t>(v)];
    SurfacePoint p;
    p.face = incident[static_cast<size_t>(b)][0];
    for (int k = 0; k < 3; ++k) p.bary(k) = body.F(p.face, k) == b ? 1.0 : 0.0;
    loop.binding.push_back(p);
  }
  g.loops.push_back(loop);
  g.paint.assign(static_cast<size_t>(s.cap.F.rows()), 1.0);
  write_garment_file(s.dir / "garment.json", g);
  return s;
}

}  // namespace

TEST_CASE("sewn back from its flat pieces, a cap drapes like its rest shape", "[round_trip]") {
  const CapScene s = write_cap_scene("export-rest-round-trip");
  const Pattern pattern = make_pattern(s.cap.V, s.cap.F, {}, PatternOptions{});
  REQUIRE(pattern.pieces.size() >= 1);
  CHECK(pattern.seams.size() >= 1);  // doubly curved: darts or seams
  const Layout layout = layout_pattern(pattern, LayoutOptions{});

  // The sewn triangles are the pieces' triangles (a rest face that a cut
  // splits has its parts' mean metric): about the flattening's area.
  const auto sewn = sewn_rest_triangles(pattern, layout, static_cast<int>(s.cap.F.rows()));
  double flat_area = 0.0, piece_area = 0.0;
  for (const auto& t : sewn) flat_area += t.area;
  for (const auto& p : pattern.pieces) piece_area += p.flat.stats.area_2d;
  CHECK(flat_area == Approx(piece_area).epsilon(1e-3));

  RoundTripOptions options;
  options.settle_max_steps = 400;
  const RoundTripResult trip = round_trip(s.poses, s.garment, s.cap.V, s.cap.F, pattern, layout, options);
  INFO("distance max " << trip.max_distance << " mean " << trip.mean_distance << " p95 " << trip.p95_distance
                       << " sewn stretch max " << trip.sewn_drape_stretch.max_s1 << " p95 "
                       << trip.sewn_drape_stretch.p95_s1 << " steps " << trip.rest_run.settle_steps << "/"
                       << trip.sewn_run.settle_steps);
  CHECK(trip.pose == "a");
  CHECK(trip.rest_run.settled);
  CHECK(trip.sewn_run.settled);
  // Pieces close to the rest shape (a little ease, little compression): the drapes agree within millimetres.
  CHECK(trip.p95_distance < 0.003);
  CHECK(trip.max_distance < 0.006);
  CHECK(trip.sewn_drape_stretch.p95_s1 < 1.05);
  CHECK(trip.sewn_drape_stretch.max_s1 < 1.15);

  // A pattern 10 % too small everywhere (every flat piece scaled by 0.9) is
  // stretched over the body, one 10 % too large sags away from it: the round
  // trip must see both.
  Layout shrunk = layout, grown = layout;
  for (auto& lp : shrunk.pieces) lp.UV *= 0.9;
  for (auto& lp : grown.pieces) lp.UV *= 1.1;
  const RoundTripResult tight = round_trip(s.poses, s.garment, s.cap.V, s.cap.F, pattern, shrunk, options);
  const RoundTripResult loose = round_trip(s.poses, s.garment, s.cap.V, s.cap.F, pattern, grown, options);
  INFO("shrunk: sewn stretch p95 " << tight.sewn_drape_stretch.p95_s1 << "; grown: distance max "
                                   << loose.max_distance << " p95 " << loose.p95_distance);
  CHECK(tight.sewn_drape_stretch.p95_s1 > 1.05);
  CHECK(loose.p95_distance > 3.0 * trip.p95_distance);
  CHECK(loose.max_distance > 2.0 * trip.max_distance);
}

TEST_CASE("export-rest --round-trip reports the drape distance and the sewn stretch", "[round_trip][cli]") {
  const CapScene s = write_cap_scene("export-rest-round-trip-cli");
  const std::string base = testing::tool_path("export-rest") + " " + (s.dir / "garment.ply").string() +
                           " --garment " + (s.dir / "garment.json").string() + " -q --round-trip-steps 400";
  const auto run = testing::run_command(base + " --round-trip " + (s.dir / "poses.json").string() + " --out " +
                                        (s.dir / "out").string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const Json report = read_json_file(s.dir / "out" / "report.json");
  const Json& trip = report["round_trip"];
  CHECK(trip["checked"] == true);
  CHECK(trip["pose"] == "a");
  CHECK(trip["distance_mm"]["p95"].get<double>() >= 0.0);
  CHECK(trip["distance_mm"]["p95"].get<double>() <= trip["distance_mm"]["max"].get<double>());
  CHECK(trip["distance_mm"]["max"].get<double>() < 6.0);
  CHECK(trip["sewn_stretch_against_flat_pieces"]["p95_s1"].get<double>() < 1.05);
  CHECK(trip["rest_drape"]["settle_steps"].get<int>() > 0);
  CHECK(fs::exists(s.dir / "out" / "round_trip_sewn_drape.ply"));
  // Same inputs, same output files.
  const auto again = testing::run_command(base + " --round-trip " + (s.dir / "poses.json").string() + " --out " +
                                          (s.dir / "again").string());
  REQUIRE(again.exit_code == 0);
  for (const char* name : {"report.json", "round_trip_rest_drape.ply", "round_trip_sewn_drape.ply"})
    CHECK(testing::read_file(s.dir / "out" / name) == testing::read_file(s.dir / "again" / name));
  // Off by default; and it needs the garment file.
  const auto plain = testing::run_command(testing::tool_path("export-rest") + " " + (s.dir / "garment.ply").string() +
                                          " --garment " + (s.dir / "garment.json").string() + " -q --out " +
                                          (s.dir / "plain").string());
  REQUIRE(plain.exit_code == 0);
  CHECK(read_json_file(s.dir / "plain" / "report.json")["round_trip"]["checked"] == false);
  const auto no_garment = testing::run_command(testing::tool_path("export-rest") + " " +
                                               (s.dir / "garment.ply").string() + " -q --round-trip " +
                                               (s.dir / "poses.json").string() + " --out " + (s.dir / "x").string());
  CHECK(no_garment.exit_code == 2);
  CHECK(no_garment.err.find("--round-trip") != std::string::npos);
}
