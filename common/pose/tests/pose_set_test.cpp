#include <catch2/catch.hpp>

#include <filesystem>

#include "core/error.h"
#include "core/sha256.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;

TEST_CASE("pose-set manifests round-trip and guard their files", "[pose]") {
  const fs::path dir = gp::testing::fresh_temp_dir("pose_set");
  gp::Mesh a = gp::testing::make_icosphere(1);
  gp::Mesh b = a;
  b.V *= 1.1;
  gp::write_mesh(dir / "a.ply", a);
  gp::write_mesh(dir / "b.ply", b);
  gp::PoseSetManifest m;
  m.vertex_count = a.V.rows();
  m.face_count = a.F.rows();
  m.topology_sha256 = gp::topology_checksum(a.F);
  m.reference = "a";
  m.poses = {{"a", "a.ply", gp::sha256_file_hex(dir / "a.ply"), "test"},
             {"b", "b.ply", gp::sha256_file_hex(dir / "b.ply"), "test"}};
  gp::write_pose_set_manifest(dir / "poses.json", m);
  const gp::PoseSet set = gp::load_pose_set(dir / "poses.json");
  REQUIRE(set.names.size() == 2);
  CHECK(set.V[1] == b.V);
  CHECK(set.index_of("b", "x") == 1);
  CHECK_THROWS_AS(set.index_of("c", "x"), gp::SpecError);

  // A pose file edited after the manifest was written is caught.
  b.V *= 1.01;
  gp::write_mesh(dir / "b.ply", b);
  CHECK_THROWS_AS(gp::load_pose_set(dir / "poses.json"), gp::InputError);

  // A pose with other connectivity is a geometry error.
  gp::Mesh c = gp::testing::make_icosphere(2);
  gp::write_mesh(dir / "c.ply", c);
  CHECK_THROWS_AS(gp::load_pose_files({dir / "a.ply", dir / "c.ply"}), gp::GeometryError);
  fs::remove_all(dir);
}

TEST_CASE("pose names are checked", "[pose]") {
  CHECK(gp::is_valid_pose_name("arms-up_2"));
  CHECK_FALSE(gp::is_valid_pose_name(""));
  CHECK_FALSE(gp::is_valid_pose_name("arms up"));
  CHECK_FALSE(gp::is_valid_pose_name("../x"));
}
