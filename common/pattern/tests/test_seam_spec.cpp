#include <catch2/catch.hpp>

#include "core/error.h"
#include "garment/garment_file.h"
#include "pattern/mesh_cut.h"
#include "pattern/seam_spec.h"
#include "testing/test_meshes.h"

using namespace gp;

namespace {

std::vector<SeamPath> resolve(const Mesh& m, const Json& j) {
  return resolve_seams(m.V, m.F, parse_seam_spec(j, "seams.json"), nullptr, nullptr);
}

template <class E>
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.message();
  }
  return "no error";
}

}  // namespace

TEST_CASE("seam specs are read strictly", "[seam_spec]") {
  const Json good = Json::parse(R"({"schema": "seam-spec/1", "seams": [
      {"name": "side", "points": [0, [0.0, 1.0, 0.5]]}]})");
  const SeamSpec spec = parse_seam_spec(good, "seams.json");
  REQUIRE(spec.seams.size() == 1);
  CHECK(spec.seams[0].points[1].is_vertex == false);
  CHECK(spec.snap_tolerance == Approx(0.03));
  CHECK(to_json(spec)["seams"][0]["on"] == "rest");

  auto bad = [](const char* text) { return message_of<SpecError>([&] { parse_seam_spec(Json::parse(text), "s.json"); }); };
  CHECK(bad(R"({"schema": "seam-spec/2", "seams": []})").find("schema") != std::string::npos);
  CHECK(bad(R"({"schema": "seam-spec/1", "seams": [{"name": "a", "points": [1, 2]}], "extra": 1})").find("extra") != std::string::npos);
  CHECK(bad(R"({"schema": "seam-spec/1", "seams": [{"name": "a", "points": [1]}]})").find("'a'") != std::string::npos);
  CHECK(bad(R"({"schema": "seam-spec/1", "seams": [{"name": "a", "points": [1, 2], "on": "sky"}]})").find("/seams/0/on") != std::string::npos);
  CHECK(bad(R"({"schema": "seam-spec/1", "seams": [{"name": "a", "points": [1, 2]}, {"name": "a", "points": [3, 4]}]})").find("unique") != std::string::npos);
  CHECK(bad(R"({"schema": "seam-spec/1", "seams": [{"name": "a", "points": [1, "x"]}]})").find("/seams/0/points/1") != std::string::npos);
}

TEST_CASE("seams resolve to edge paths on the rest shape", "[seam_spec]") {
  const int nu = 16, nv = 6;
  const Mesh cyl = testing::make_open_cylinder(nu, nv, 0.1, 0.3);
  // Bottom ring vertex 0 to top ring vertex nv*nu, clicked by id and by a 3D point.
  const auto paths = resolve(cyl, Json::parse(R"({"schema": "seam-spec/1", "seams": [
      {"name": "side", "points": [0, [0.0, 0.3, 0.1]]}]})"));
  REQUIRE(paths.size() == 1);
  CHECK(paths[0].vertex_ids.front() == 0);
  CHECK(paths[0].vertex_ids.back() == nv * nu);
  CHECK(paths[0].vertex_ids.size() == static_cast<size_t>(nv + 1));
  // Cutting along it: the seam vertices are doubled, every cut edge has a partner.
  const CutMesh cut = cut_mesh(cyl.V, cyl.F, {{0, paths[0].vertex_ids, false}});
  CHECK(cut.V.rows() == cyl.V.rows() + nv + 1);
  CHECK(cut.edges.size() == static_cast<size_t>(nv));
  for (const auto& e : cut.edges) CHECK(e.length == Approx(0.3 / nv));
}

TEST_CASE("bad seams name the seam and have the right category", "[seam_spec][errors]") {
  const Mesh cyl = testing::make_open_cylinder(16, 6, 0.1, 0.3);
  auto spec_error = [&](const char* text) { return message_of<SpecError>([&] { resolve(cyl, Json::parse(text)); }); };
  auto geometry_error = [&](const char* text) { return message_of<GeometryError>([&] { resolve(cyl, Json::parse(text)); }); };
  // A vertex id that is not on the mesh.
  CHECK(spec_error(R"({"schema": "seam-spec/1", "seams": [{"name": "front", "points": [0, 5000]}]})")
            .find("seam 'front'") != std::string::npos);
  // A point far off the surface: the path would leave the mesh.
  const std::string far = spec_error(R"({"schema": "seam-spec/1", "seams": [{"name": "back", "points": [0, [2.0, 0.1, 0.0]]}]})");
  CHECK(far.find("seam 'back'") != std::string::npos);
  CHECK(far.find("leave the mesh") != std::string::npos);
  // A seam whose two ends are inside: reaches neither the boundary nor another seam.
  const std::string inside = geometry_error(R"({"schema": "seam-spec/1", "seams": [{"name": "pocket", "points": [33, 35]}]})");
  CHECK(inside.find("seam 'pocket'") != std::string::npos);
  CHECK(inside.find("does not reach") != std::string::npos);
  // Ending on another seam is fine; a dart (one end inside) is fine.
  CHECK_NOTHROW(resolve(cyl, Json::parse(R"({"schema": "seam-spec/1", "seams": [
      {"name": "side", "points": [0, 96]}, {"name": "branch", "points": [35, 48]}, {"name": "dart", "points": [8, 40]}]})")));
  // Only along the boundary: cuts nothing.
  CHECK(geometry_error(R"({"schema": "seam-spec/1", "seams": [{"name": "hem", "points": [0, 3]}]})")
            .find("seam 'hem'") != std::string::npos);
  // Two components: no path between them.
  Mesh two = cyl;
  const Mesh other = testing::make_grid(2, 2);
  two.V.conservativeResize(cyl.V.rows() + other.V.rows(), 3);
  two.V.bottomRows(other.V.rows()) = other.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  two.F.conservativeResize(cyl.F.rows() + other.F.rows(), 3);
  two.F.bottomRows(other.F.rows()) = other.F.array() + static_cast<int>(cyl.V.rows());
  const std::string split = message_of<GeometryError>([&] {
    resolve(two, Json::parse(R"({"schema": "seam-spec/1", "seams": [{"name": "bridge", "points": [0, 112]}]})"));
  });
  CHECK(split.find("seam 'bridge'") != std::string::npos);
  CHECK(split.find("leave the mesh") != std::string::npos);
  // Body points without a body.
  CHECK(spec_error(R"({"schema": "seam-spec/1", "seams": [{"name": "b", "on": "body", "points": [0, 1]}]})")
            .find("no body") != std::string::npos);
}

TEST_CASE("seams clicked on the body map to the garment through its binding", "[seam_spec]") {
  const int nu = 24, nv = 10;
  const Mesh body_mesh = testing::make_open_cylinder(nu, nv, 0.10, 0.5);
  const Mesh rest = testing::make_open_cylinder(nu, nv, 0.11, 0.5);  // 1 cm off the body
  DesignBody body{body_mesh.V, body_mesh.F};
  GarmentFile garment;
  garment.offset = 0.01;
  garment.vertex_count = rest.V.rows();
  garment.face_count = rest.F.rows();
  GarmentLoop hem;
  hem.name = "hem";
  // The rest shape's hem vertex i is bound to body vertex (i + 3) % nu, so
  // that the binding, not the closest point, decides where a click lands.
  for (int i = 0; i < nu; ++i) {
    hem.vertex_ids.push_back(i);
    const int b = (i + 3) % nu;
    for (int f = 0; f < body_mesh.F.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (body_mesh.F(f, k) == b && hem.binding.size() == static_cast<size_t>(i)) {
          SurfacePoint sp;
          sp.face = f;
          sp.bary = Eigen::Vector3d::Zero();
          sp.bary[k] = 1.0;
          hem.binding.push_back(sp);
        }
  }
  garment.loops = {hem};
  const SeamSpec spec = parse_seam_spec(Json::parse(R"({"schema": "seam-spec/1", "seams": [
      {"name": "side", "on": "body", "points": [3, 243]}]})"), "seams.json");
  const auto paths = resolve_seams(rest.V, rest.F, spec, &garment, &body);
  REQUIRE(paths.size() == 1);
  CHECK(paths[0].vertex_ids.front() == 0);     // through the binding of the hem
  CHECK(paths[0].vertex_ids.back() == 243);    // by the offset along the body normal
  // A body vertex id beyond the body is a spec error naming the seam.
  const SeamSpec bad = parse_seam_spec(Json::parse(R"({"schema": "seam-spec/1", "seams": [
      {"name": "far", "on": "body", "points": [3, 99999]}]})"), "seams.json");
  CHECK_THROWS_WITH(resolve_seams(rest.V, rest.F, bad, &garment, &body), Catch::Contains("seam 'far'"));

  // After adaptation the rest shape may have grown away from the body (here
  // to a 16 cm radius, 5 cm beyond the snap tolerance's reach): body clicks
  // then land through the garment as designed, which shares its connectivity.
  const Mesh grown = testing::make_open_cylinder(nu, nv, 0.16, 0.5);
  CHECK_THROWS_WITH(resolve_seams(grown.V, grown.F, spec, &garment, &body),
                    Catch::Contains("from the rest shape"));
  const auto through_design = resolve_seams(grown.V, grown.F, spec, &garment, &body, &rest.V);
  REQUIRE(through_design.size() == 1);
  CHECK(through_design[0].vertex_ids.front() == 0);
  CHECK(through_design[0].vertex_ids.back() == 243);
}

TEST_CASE("seams clicked on the garment as designed hold on the adapted rest shape", "[seam_spec]") {
  const int nu = 16, nv = 6;
  const Mesh design = testing::make_open_cylinder(nu, nv, 0.1, 0.3);
  // The adapted rest shape grew 4 cm in radius and moved 2 cm down: the
  // clicked points are centimetres beyond the snap tolerance from it.
  Mesh grown = testing::make_open_cylinder(nu, nv, 0.14, 0.3);
  grown.V.col(1).array() -= 0.02;
  const Json j = Json::parse(R"({"schema": "seam-spec/1", "snap_tolerance": 0.01, "seams": [
      {"name": "side", "on": "design", "points": [[0.0, 0.0, 0.1], [0.0, 0.3, 0.1]]}]})");
  const SeamSpec spec = parse_seam_spec(j, "seams.json");
  CHECK(to_json(spec)["seams"][0]["on"] == "design");
  const auto paths = resolve_seams(grown.V, grown.F, spec, nullptr, nullptr, &design.V);
  REQUIRE(paths.size() == 1);
  CHECK(paths[0].vertex_ids.front() == 0);
  CHECK(paths[0].vertex_ids.back() == nv * nu);
  CHECK(paths[0].vertex_ids.size() == static_cast<size_t>(nv + 1));
  // The same points taken as rest-shape points miss the grown shape.
  Json on_rest = j;
  on_rest["seams"][0]["on"] = "rest";
  CHECK_THROWS_WITH(resolve_seams(grown.V, grown.F, parse_seam_spec(on_rest, "seams.json"), nullptr, nullptr),
                    Catch::Contains("from the rest shape"));
  // Without the design mesh the seam cannot be placed: a spec error naming it.
  CHECK_THROWS_AS(resolve_seams(grown.V, grown.F, spec, nullptr, nullptr), SpecError);
  CHECK_THROWS_WITH(resolve_seams(grown.V, grown.F, spec, nullptr, nullptr), Catch::Contains("seam 'side'"));
}
