// The spec's grain regions (a bias cut), their refusals in one line naming
// the field, the garment file carrying the angle per face only where one is
// turned, and the fabric's thickness as the contact's.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "fabric/fabric.h"
#include "garment/extend_boundary.h"
#include "garment/garment_file.h"
#include "garment/garment_spec.h"
#include "io/mesh_io.h"
#include "spec/json_file.h"
#include "garment/tests/cap_spec.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using gp::Json;
using gp::testing::cap_spec;
using gp::testing::spec_error;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_CASE("a grain region turns the warp by its angle in degrees", "[garment][fabric][grain]") {
  Json j = cap_spec();
  j["grain"] = Json::array({{{"name", "skirt"}, {"angle", 45}, {"disc", {{"center", {0.0, 0.2, 0.0}}, {"radius", 0.05}}}},
                            {{"angle", -30}, {"vertices", {1, 2, 3}}}});
  const gp::GarmentSpec s = gp::parse_garment_spec(j, "s.json");
  REQUIRE(s.grain.size() == 2);
  CHECK(s.grain[0].name == "skirt");
  CHECK(s.grain[0].angle == Approx(kPi / 4).epsilon(1e-15));
  CHECK(s.grain[0].on.is_disc);
  CHECK(s.grain[0].on.radius == 0.05);
  CHECK(s.grain[1].name == "grain1");
  CHECK(s.grain[1].angle == Approx(-kPi / 6).epsilon(1e-15));
  CHECK(s.grain[1].on.vertex_ids == std::vector<long long>{1, 2, 3});
  // The effective spec gives the angles back in degrees.
  const gp::OrderedJson back = gp::to_json(s);
  CHECK(back["grain"][0]["angle"].get<double>() == Approx(45.0));
  // No grain: no key, as before.
  CHECK_FALSE(gp::to_json(gp::parse_garment_spec(cap_spec(), "s.json")).contains("grain"));
}

TEST_CASE("bad grain regions are refused at their field", "[garment][fabric][grain]") {
  Json j = cap_spec();
  j["grain"] = Json::array({{{"angle", 120}, {"vertices", {1}}}});
  std::string e = spec_error(j);
  CHECK(e.find("s.json: /grain/0/angle") != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);
  j["grain"][0]["angle"] = "45 deg";
  CHECK(spec_error(j).find("/grain/0/angle") != std::string::npos);
  j["grain"][0].erase("angle");
  CHECK(spec_error(j).find("/grain/0/angle") != std::string::npos);
  j["grain"] = Json::array({{{"angle", 45}}});
  CHECK(spec_error(j).find("exactly one of 'disc' and 'vertices'") != std::string::npos);
  j["grain"] = Json::array({{{"angle", 45}, {"vertices", {1}}, {"factor", 2}}});
  CHECK(spec_error(j).find("/grain/0/factor") != std::string::npos);
  j["grain"] = {{"angle", 45}};
  CHECK(spec_error(j).find("/grain") != std::string::npos);
  // The extension's grain, the same unit and range.
  Json x = {{"schema", "extend-spec/1"}, {"loop", "rim"}, {"target", {{"distance", 0.1}}}, {"grain", 91}};
  try {
    gp::parse_extend_spec(x, "x.json");
    FAIL("no SpecError");
  } catch (const gp::SpecError& err) {
    CHECK(std::string(err.message()).find("x.json: /grain") != std::string::npos);
  }
  x["grain"] = -45;
  CHECK(gp::parse_extend_spec(x, "x.json").grain_angle == Approx(-kPi / 4));
}

TEST_CASE("make-garment writes the grain per face where a region turns it, and refuses a bad angle with exit 4",
          "[garment][fabric][grain][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("garment_grain_cli");
  const gp::Mesh sphere = gp::testing::make_icosphere(4, 0.2);
  gp::write_mesh(dir / "body.ply", sphere);
  // The body vertices of the cap's lower half (y below 0.18): that part of the cap on the bias.
  Json ids = Json::array();
  for (int v = 0; v < sphere.V.rows(); ++v)
    if (sphere.V(v, 1) > 0.14 && sphere.V(v, 1) < 0.18) ids.push_back(v);
  Json j = cap_spec();
  j["grain"] = Json::array({{{"name", "band"}, {"angle", 45}, {"vertices", ids}}});
  Json bad = j;
  bad["grain"][0]["angle"] = 135;
  std::ofstream(dir / "good.json") << j.dump(2);
  std::ofstream(dir / "bad.json") << bad.dump(2);
  std::ofstream(dir / "plain.json") << cap_spec().dump(2);
  const std::string mg = gp::testing::tool_path("make-garment"), d = dir.string();
  auto r = gp::testing::run_command(mg + " " + d + "/bad.json --avatar " + d + "/body.ply --out " + d + "/bad");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("make-garment: error[spec]: ") == 0);
  CHECK(r.err.find("/grain/0/angle") != std::string::npos);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "bad"));

  r = gp::testing::run_command(mg + " " + d + "/good.json --avatar " + d + "/body.ply --out " + d + "/good -q");
  REQUIRE(r.exit_code == 0);
  const gp::GarmentFile g = gp::read_garment_file(dir / "good" / "garment.json");
  REQUIRE(static_cast<long long>(g.material.grain_angles.size()) == g.face_count);
  const long turned = std::count_if(g.material.grain_angles.begin(), g.material.grain_angles.end(),
                                    [](double a) { return a != 0.0; });
  for (double a : g.material.grain_angles) CHECK((a == 0.0 || a == Approx(kPi / 4).epsilon(1e-12)));
  CHECK(turned > 0);
  CHECK(turned < g.face_count);  // the cap's top stays on the straight grain

  r = gp::testing::run_command(mg + " " + d + "/plain.json --avatar " + d + "/body.ply --out " + d + "/plain -q");
  REQUIRE(r.exit_code == 0);
  // No region: no "grain" key, the garment file as before the regions.
  CHECK_FALSE(gp::read_json_file(dir / "plain" / "garment.json").contains("grain"));
  CHECK(gp::read_garment_file(dir / "plain" / "garment.json").material.grain_angles.empty());
  fs::remove_all(dir);
}

TEST_CASE("the contact keeps the fabric's thickness, 1 mm where it gives none", "[garment][fabric]") {
  gp::Material paper;
  CHECK(gp::contact_thickness(paper) == 1e-3);
  Json j = cap_spec();
  j["fabric"] = "denim-11oz";
  const gp::Material denim = gp::parse_garment_spec(j, "s.json").material;
  CHECK(denim.thickness == gp::fabric::find_fabric("denim-11oz")->thickness);
  CHECK(gp::contact_thickness(denim) == denim.thickness);
  CHECK(gp::contact_thickness(denim) == Approx(0.75e-3));
}
