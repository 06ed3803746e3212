#include <catch2/catch.hpp>

#include <cstring>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "io/gltf_writer.h"
#include "testing/test_meshes.h"

namespace {

std::uint32_t u32(const std::vector<std::uint8_t>& b, size_t at) {
  return std::uint32_t{b[at]} | std::uint32_t{b[at + 1]} << 8 | std::uint32_t{b[at + 2]} << 16 |
         std::uint32_t{b[at + 3]} << 24;
}

struct Glb {
  nlohmann::json json;
  std::vector<std::uint8_t> bin;
};

// Splits a .glb into its JSON and binary chunks, checking the container.
Glb parse(const std::vector<std::uint8_t>& b) {
  REQUIRE(b.size() >= 28);
  REQUIRE(u32(b, 0) == 0x46546C67);
  REQUIRE(u32(b, 4) == 2);
  REQUIRE(u32(b, 8) == b.size());
  const std::uint32_t json_length = u32(b, 12);
  REQUIRE(u32(b, 16) == 0x4E4F534A);
  REQUIRE(json_length % 4 == 0);
  Glb g;
  g.json = nlohmann::json::parse(std::string(b.begin() + 20, b.begin() + 20 + json_length));
  const size_t bin_at = 20 + json_length;
  const std::uint32_t bin_length = u32(b, bin_at);
  REQUIRE(u32(b, bin_at + 4) == 0x004E4942);
  REQUIRE(bin_length % 4 == 0);
  REQUIRE(bin_at + 8 + bin_length == b.size());
  g.bin.assign(b.begin() + bin_at + 8, b.end());
  return g;
}

template <class T>
T read_at(const Glb& g, int accessor, size_t element) {
  const auto& a = g.json["accessors"][accessor];
  const auto& v = g.json["bufferViews"][a["bufferView"].get<int>()];
  T x;
  std::memcpy(&x, g.bin.data() + v["byteOffset"].get<size_t>() + element * sizeof(T), sizeof(T));
  return x;
}

gp::GltfMesh named(const std::string& name, const gp::Mesh& mesh) {
  gp::GltfMesh m;
  m.name = name;
  m.V = mesh.V;
  m.F = mesh.F;
  return m;
}

}  // namespace

TEST_CASE("a glb holds named meshes with positions, normals, colours and custom attributes", "[io][gltf]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(2);
  gp::GltfMesh body = named("body", sphere);
  body.N = sphere.V;  // unit sphere: normals are the positions
  gp::GltfMesh garment = named("garment", sphere);
  garment.V *= 1.1;
  garment.colours = Eigen::MatrixXf::Constant(sphere.V.rows(), 3, 1.0f);
  garment.colours.col(1).setConstant(0.5f);
  Eigen::VectorXf stretch = Eigen::VectorXf::LinSpaced(sphere.V.rows(), 1.0f, 1.3f);
  garment.attributes.push_back({"MAX_STRETCH", stretch});

  const std::vector<std::uint8_t> bytes = gp::glb_bytes({body, garment}, "test");
  CHECK(bytes == gp::glb_bytes({body, garment}, "test"));  // deterministic
  const Glb g = parse(bytes);
  REQUIRE(g.json["nodes"].size() == 2);
  CHECK(g.json["nodes"][0]["name"] == "body");
  CHECK(g.json["nodes"][1]["name"] == "garment");
  CHECK(g.json["asset"]["version"] == "2.0");
  const auto& a0 = g.json["meshes"][0]["primitives"][0]["attributes"];
  const auto& a1 = g.json["meshes"][1]["primitives"][0]["attributes"];
  CHECK(a0.contains("POSITION"));
  CHECK(a0.contains("NORMAL"));
  CHECK(!a0.contains("COLOR_0"));
  CHECK(a1.contains("COLOR_0"));
  REQUIRE(a1.contains("_MAX_STRETCH"));

  // Positions and their bounds (the bounds must be the float values' own).
  const int pos = a1["POSITION"].get<int>();
  const auto& acc = g.json["accessors"][pos];
  CHECK(acc["count"] == sphere.V.rows());
  float lo = 1e9f;
  for (Eigen::Index v = 0; v < sphere.V.rows(); ++v) lo = std::min(lo, read_at<float>(g, pos, static_cast<size_t>(3 * v)));
  CHECK(acc["min"][0].get<double>() == static_cast<double>(lo));
  CHECK(read_at<float>(g, pos, 3) == static_cast<float>(garment.V(1, 0)));

  // The custom attribute carries the numbers; colours are linear (sRGB 0.5 -> 0.214).
  const int s = a1["_MAX_STRETCH"].get<int>();
  CHECK(g.json["accessors"][s]["type"] == "SCALAR");
  CHECK(read_at<float>(g, s, 7) == stretch(7));
  CHECK(read_at<float>(g, a1["COLOR_0"].get<int>(), 1) == Approx(0.2140).epsilon(1e-3));

  // Small meshes use 16-bit indices, each triangle as written.
  const int idx = g.json["meshes"][0]["primitives"][0]["indices"].get<int>();
  CHECK(g.json["accessors"][idx]["componentType"] == 5123);
  CHECK(read_at<std::uint16_t>(g, idx, 5) == sphere.F(1, 2));
  // Every buffer view starts 4-byte aligned.
  for (const auto& v : g.json["bufferViews"]) CHECK(v["byteOffset"].get<size_t>() % 4 == 0);
}

TEST_CASE("meshes past 65534 vertices get 32-bit indices", "[io][gltf]") {
  const gp::Mesh grid = gp::testing::make_grid(260, 260);  // 68,121 vertices
  const Glb g = parse(gp::glb_bytes({named("grid", grid)}, "test"));
  const int idx = g.json["meshes"][0]["primitives"][0]["indices"].get<int>();
  CHECK(g.json["accessors"][idx]["componentType"] == 5125);
  CHECK(read_at<std::uint32_t>(g, idx, 3 * static_cast<size_t>(grid.F.rows()) - 1) ==
        static_cast<std::uint32_t>(grid.F(grid.F.rows() - 1, 2)));
}

TEST_CASE("degenerate normals are written as unit vectors", "[io][gltf]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(0);
  gp::GltfMesh m = named("m", sphere);
  m.N = Eigen::MatrixXd::Zero(sphere.V.rows(), 3);
  m.N(0, 0) = std::nan("");
  const Glb g = parse(gp::glb_bytes({m}, "test"));
  const int n = g.json["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].get<int>();
  CHECK(read_at<float>(g, n, 1) == 1.0f);
  CHECK(read_at<float>(g, n, 0) == 0.0f);
}

TEST_CASE("the glb writer rejects bad meshes", "[io][gltf]") {
  const gp::Mesh sphere = gp::testing::make_icosphere(0);
  const gp::GltfMesh m = named("m", sphere);
  gp::GltfMesh bad = m;
  bad.F(0, 0) = static_cast<int>(m.V.rows());
  CHECK_THROWS_AS(gp::glb_bytes({bad}, "t"), gp::UsageError);
  bad = m;
  bad.V(2, 1) = std::nan("");
  CHECK_THROWS_AS(gp::glb_bytes({bad}, "t"), gp::UsageError);
  bad = m;
  bad.attributes.push_back({"max stretch", Eigen::VectorXf::Ones(m.V.rows())});
  CHECK_THROWS_AS(gp::glb_bytes({bad}, "t"), gp::UsageError);
  bad = m;
  bad.attributes.push_back({"S", Eigen::VectorXf::Ones(3)});
  CHECK_THROWS_AS(gp::glb_bytes({bad}, "t"), gp::UsageError);
  bad = m;
  bad.colours = Eigen::MatrixXf::Ones(2, 3);
  CHECK_THROWS_AS(gp::glb_bytes({bad}, "t"), gp::UsageError);
}
