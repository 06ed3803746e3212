#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "io/mesh_io.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

void write_bytes(const fs::path& p, const std::string& header, const std::vector<char>& body) {
  std::ofstream out(p, std::ios::binary);
  out << header;
  out.write(body.data(), static_cast<std::streamsize>(body.size()));
}

template <class T>
void put_big_endian(std::vector<char>& buf, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (size_t i = 0; i < sizeof(T); ++i) buf.push_back(bytes[sizeof(T) - 1 - i]);
}

// Expects `f` to throw an error of category `code` whose message contains `text`.
template <class Fn>
void require_error(Fn f, gp::ExitCode code, const std::string& text) {
  try {
    f();
    FAIL("no error thrown; expected: " << text);
  } catch (const gp::Error& e) {
    CHECK(e.code() == code);
    CHECK_THAT(e.message(), Catch::Contains(text));
  }
}

}  // namespace

TEST_CASE("binary PLY round trip keeps vertex order, values and scalar fields", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_ply");
  gp::Mesh m = gp::testing::make_torus(12, 8);
  m.V.row(3) << 1e-300, -1e300, 0.1;  // extreme values survive as doubles
  m.vertex_fields.push_back({"weight", Eigen::VectorXd::LinSpaced(m.V.rows(), 0, 1)});
  m.face_fields.push_back({"stretch", Eigen::VectorXd::LinSpaced(m.F.rows(), 1, 2)});
  gp::write_mesh(dir / "t.ply", m);
  const gp::MeshReadResult r = gp::read_mesh(dir / "t.ply");
  CHECK(r.format == "ply-binary-le");
  CHECK(r.vertex_order_preserved);
  CHECK(r.warnings.empty());
  CHECK(r.mesh.V == m.V);
  CHECK(r.mesh.F == m.F);
  REQUIRE(gp::find_field(r.mesh.vertex_fields, "weight"));
  CHECK(gp::find_field(r.mesh.vertex_fields, "weight")->values == m.vertex_fields[0].values);
  REQUIRE(gp::find_field(r.mesh.face_fields, "stretch"));
  CHECK(gp::find_field(r.mesh.face_fields, "stretch")->values == m.face_fields[0].values);

  // Single precision halves the file and rounds to float.
  gp::MeshWriteOptions single;
  single.double_precision = false;
  gp::write_mesh(dir / "f.ply", m, single);
  const gp::Mesh f = gp::read_mesh(dir / "f.ply").mesh;
  CHECK((f.V.row(0) - m.V.row(0)).norm() < 1e-6);
  fs::remove_all(dir);
}

TEST_CASE("ASCII and big-endian PLY read the same mesh", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_ply_ascii");
  write_text(dir / "a.ply",
             "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\n"
             "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
             "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 9\n3 0 1 2\n3 0 2 3\n");
  gp::Mesh a = gp::read_mesh(dir / "a.ply").mesh;
  REQUIRE(a.V.rows() == 4);
  CHECK(a.V.row(2) == Eigen::RowVector3d(1, 1, 0));
  CHECK(a.F.row(1) == Eigen::RowVector3i(0, 2, 3));
  CHECK(gp::find_field(a.vertex_fields, "red")->values(3) == 9);

  std::vector<char> body;
  const float pts[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  for (const auto& p : pts)
    for (float c : p) put_big_endian(body, c);
  for (int t = 0; t < 2; ++t) {
    body.push_back(3);
    const int corners[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int c : corners[t]) put_big_endian(body, static_cast<int32_t>(c));
  }
  write_bytes(dir / "b.ply",
              "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\n"
              "property float y\nproperty float z\nelement face 2\n"
              "property list uchar int vertex_indices\nend_header\n",
              body);
  const gp::Mesh b = gp::read_mesh(dir / "b.ply").mesh;
  CHECK(b.V == a.V);
  CHECK(b.F == a.F);
  fs::remove_all(dir);
}

TEST_CASE("polygons are split only when asked", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_ngon");
  write_text(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  require_error([&] { gp::read_mesh(dir / "quad.obj"); }, gp::ExitCode::geometry,
                "face has 4 corners; the pipeline needs triangles (pass --triangulate");
  gp::MeshReadOptions o;
  o.triangulate = true;
  const gp::MeshReadResult r = gp::read_mesh(dir / "quad.obj", o);
  CHECK(r.mesh.F.rows() == 2);
  REQUIRE(r.warnings.size() == 1);
  CHECK_THAT(r.warnings[0], Catch::Contains("split 1 polygons"));
  fs::remove_all(dir);
}

TEST_CASE("OBJ reader handles slashes, negative indices and keeps order", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_obj");
  write_text(dir / "m.obj",
             "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nvt 0 0\nvn 0 0 1\nv 0 1 0\n"
             "usemtl a\nf 1/1/1 2/1/1 3/1/1\nv 1 1 0\nf -3//1 -1//1 -2//1\n");
  const gp::Mesh m = gp::read_mesh(dir / "m.obj").mesh;
  REQUIRE(m.V.rows() == 4);
  CHECK(m.F.row(0) == Eigen::RowVector3i(0, 1, 2));
  CHECK(m.F.row(1) == Eigen::RowVector3i(1, 3, 2));

  gp::Mesh sphere = gp::testing::make_icosphere(1);
  sphere.V *= 1.0 / 3.0;  // values without a short decimal form
  gp::write_mesh(dir / "s.obj", sphere);
  const gp::Mesh back = gp::read_mesh(dir / "s.obj").mesh;
  CHECK(back.V == sphere.V);  // shortest round-trip text: exact
  CHECK(back.F == sphere.F);
  fs::remove_all(dir);
}

TEST_CASE("malformed files are input errors naming file and element", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_bad");
  write_text(dir / "empty.ply", "");
  require_error([&] { gp::read_mesh(dir / "empty.ply"); }, gp::ExitCode::input, "empty file");
  write_text(dir / "nohdr.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");
  require_error([&] { gp::read_mesh(dir / "nohdr.ply"); }, gp::ExitCode::input, "no end_header");
  write_text(dir / "noy.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n");
  require_error([&] { gp::read_mesh(dir / "noy.ply"); }, gp::ExitCode::input, "no scalar property 'y'");
  write_text(dir / "short.ply",
             "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
             "property float z\nend_header\n0 0 0\n1 1\n");
  require_error([&] { gp::read_mesh(dir / "short.ply"); }, gp::ExitCode::input,
                "line has too few values (" + (dir / "short.ply").string() + ": vertex 1)");
  write_text(dir / "word.obj", "v 0 zero 0\n");
  require_error([&] { gp::read_mesh(dir / "word.obj"); }, gp::ExitCode::input,
                "expected a number, found 'zero' (" + (dir / "word.obj").string() + ": line 1)");
  write_text(dir / "range.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
  require_error([&] { gp::read_mesh(dir / "range.ply"); }, gp::ExitCode::input,
                "vertex index 5 out of range [0, 3) (" + (dir / "range.ply").string() + ": face 0)");
  require_error([&] { gp::read_mesh(dir / "absent.ply"); }, gp::ExitCode::input, "no such file");
  // Found by fuzzing: an element without properties and two billion
  // instances was skipped instance by instance without reading a byte (a
  // hang); a count beyond the file's bytes is refused before any allocation.
  const std::string triangle =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\n";
  write_text(dir / "empty_element.ply", triangle + "element junk 2182178764\nend_header\n" + std::string(36, '\0'));
  require_error([&] { gp::read_mesh(dir / "empty_element.ply"); }, gp::ExitCode::input,
                "element 'junk' has 2182178764 instances but no properties");
  write_text(dir / "huge_count.ply",
             "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
             "property float y\nproperty float z\nend_header\n" + std::string(36, '\0'));
  require_error([&] { gp::read_mesh(dir / "huge_count.ply"); }, gp::ExitCode::input,
                "element 'vertex' declares 2000000000 instances, more than the 36 bytes after the header");
  fs::remove_all(dir);
}

TEST_CASE("other formats go through assimp with a vertex-order warning", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_assimp");
  // An ASCII STL tetrahedron: assimp joins the repeated corners into 4 vertices.
  write_text(dir / "tet.stl",
             "solid t\n"
             "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
             "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
             "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
             "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
             "endsolid t\n");
  const gp::MeshReadResult r = gp::read_mesh(dir / "tet.stl");
  CHECK(r.mesh.F.rows() == 4);
  CHECK(r.mesh.V.rows() == 4);
  CHECK_FALSE(r.vertex_order_preserved);
  REQUIRE_FALSE(r.warnings.empty());
  CHECK_THAT(r.warnings.back(), Catch::Contains("does not promise the vertex order"));
  write_text(dir / "junk.stl", "this is not a mesh");
  require_error([&] { gp::read_mesh(dir / "junk.stl"); }, gp::ExitCode::input, "cannot read mesh");
  fs::remove_all(dir);
}

TEST_CASE("writers refuse unknown formats and leave no partial file", "[io]") {
  const fs::path dir = gp::testing::fresh_temp_dir("io_write");
  const gp::Mesh m = gp::testing::make_icosphere(0);
  require_error([&] { gp::write_mesh(dir / "m.xyz", m); }, gp::ExitCode::output, "unsupported output format");
  require_error([&] { gp::write_mesh(dir / "missing_folder" / "m.ply", m); }, gp::ExitCode::output,
                "cannot create file");
  gp::Mesh bad = m;
  bad.face_fields.push_back({"short", Eigen::VectorXd::Zero(3)});
  require_error([&] { gp::write_mesh(dir / "m.ply", bad); }, gp::ExitCode::output, "wrong length");
  CHECK(fs::is_empty(dir));
  fs::remove_all(dir);
}
