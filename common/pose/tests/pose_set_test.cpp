#include <catch2/catch.hpp>

#include <cmath>
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

TEST_CASE("vertex checksums tell bodies apart but not round-off", "[pose]") {
  const gp::Mesh body = gp::testing::make_icosphere(3, 0.9);
  const std::string sum = gp::vertex_checksum(body.V);
  CHECK(sum.size() == 64);
  // The same body through centimetres and back, and through a file.
  const Eigen::MatrixXd via_cm = (body.V * 100.0) * 0.01;
  CHECK((via_cm - body.V).cwiseAbs().maxCoeff() < 1e-15);
  CHECK(gp::vertex_checksum(via_cm) == sum);
  const fs::path dir = gp::testing::fresh_temp_dir("vertex_checksum");
  gp::write_mesh(dir / "body.ply", body);
  CHECK(gp::vertex_checksum(gp::read_mesh(dir / "body.ply").mesh.V) == sum);
  // One vertex moved by 5 micrometres, the body 1 % larger, two vertices swapped.
  Eigen::MatrixXd moved = body.V;
  moved(7, 1) += 5e-6;
  CHECK(gp::vertex_checksum(moved) != sum);
  CHECK(gp::vertex_checksum(body.V * 1.01) != sum);
  Eigen::MatrixXd swapped = body.V;
  swapped.row(0).swap(swapped.row(1));
  CHECK(gp::vertex_checksum(swapped) != sum);
  // Non-finite coordinates hash without undefined behaviour.
  Eigen::MatrixXd nan = body.V;
  nan(0, 0) = std::nan("");
  CHECK(gp::vertex_checksum(nan) != sum);
  fs::remove_all(dir);
}
