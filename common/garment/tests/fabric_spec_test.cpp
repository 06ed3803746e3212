// The garment spec's "fabric": a library name, a fabric in full with units,
// refusals naming the field, and the garment file carrying it.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "fabric/fabric.h"
#include "garment/garment_file.h"
#include "garment/garment_spec.h"
#include "io/mesh_io.h"
#include "garment/tests/cap_spec.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using gp::Json;
using gp::testing::cap_spec;
using gp::testing::spec_error;

namespace {

Json full_fabric() {
  return {{"name", "shop-twill"},     {"areal_density", "210 g/m^2"}, {"thickness", "0.4 mm"},
          {"k_warp", "40 N/cm"},      {"k_weft", "3000 N/m"},        {"k_shear", "50 N/m"},
          {"k_bend", "0.5 gf cm^2/cm"}, {"limit_warp", 1.05},        {"limit_weft", 1.08}};
}


}  // namespace

TEST_CASE("a spec names its fabric; the paper's material is the default", "[garment][fabric]") {
  const gp::GarmentSpec plain = gp::parse_garment_spec(cap_spec(), "s.json");
  CHECK(plain.material.fabric == "paper");
  CHECK(plain.material.k_stretch == 800.0);
  CHECK(plain.material.k_stretch_weft == 800.0);
  CHECK_FALSE(plain.material.has_own_limits());

  Json j = cap_spec();
  j["fabric"] = "denim-11oz";
  const gp::GarmentSpec denim = gp::parse_garment_spec(j, "s.json");
  const gp::fabric::Fabric& f = *gp::fabric::find_fabric("denim-11oz");
  CHECK(denim.material.fabric == "denim-11oz");
  CHECK(denim.material.k_stretch == f.k_warp);
  CHECK(denim.material.k_stretch_weft == f.k_weft);
  CHECK(denim.material.k_shear == f.k_shear);
  CHECK(denim.material.k_bend == f.k_bend);
  CHECK(denim.material.density == f.areal_density);
  CHECK(denim.material.stretch_limit_warp == f.limit_warp);
  CHECK(denim.material.stretch_limit_weft == f.limit_weft);
  // The effective spec names it too.
  CHECK(gp::to_json(denim)["material"]["fabric"] == "denim-11oz");
}

TEST_CASE("a fabric given in full is read with its units", "[garment][fabric]") {
  Json j = cap_spec();
  j["fabric"] = full_fabric();
  const gp::Material m = gp::parse_garment_spec(j, "s.json").material;
  CHECK(m.fabric == "shop-twill");
  CHECK(m.density == Approx(0.21));
  CHECK(m.thickness == Approx(4e-4));
  CHECK(m.k_stretch == Approx(4000.0));
  CHECK(m.k_stretch_weft == Approx(3000.0));
  CHECK(m.k_shear == Approx(50.0));
  CHECK(m.k_bend == Approx(0.5 * 9.80665e-5));
  CHECK(m.stretch_limit_warp == 1.05);
  CHECK(m.damping_stretch == 100.0);  // not given: the paper's
}

TEST_CASE("unknown fabrics, missing units and clashes are refused at their field", "[garment][fabric]") {
  Json j = cap_spec();
  j["fabric"] = "silk-charmeuse";
  std::string e = spec_error(j);
  CHECK(e.find("unknown fabric 'silk-charmeuse'") != std::string::npos);
  CHECK(e.find(gp::fabric::fabric_names()) != std::string::npos);
  CHECK(e.find("s.json: /fabric") != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);

  j["fabric"] = full_fabric();
  j["fabric"]["k_weft"] = 3000;  // no unit
  e = spec_error(j);
  CHECK(e.find("/fabric/k_weft") != std::string::npos);
  j["fabric"]["k_weft"] = "3000 kg";
  CHECK(spec_error(j).find("accepted: N/m, N/cm, gf/cm") != std::string::npos);
  j["fabric"] = full_fabric();
  j["fabric"].erase("limit_weft");
  CHECK(spec_error(j).find("/fabric/limit_weft") != std::string::npos);
  j["fabric"] = full_fabric();
  j["fabric"]["colour"] = "red";
  CHECK(spec_error(j).find("/fabric/colour") != std::string::npos);
  j["fabric"] = full_fabric();
  j["fabric"]["name"] = "cotton-poplin";
  CHECK(spec_error(j).find("name of its own") != std::string::npos);
  j["fabric"] = 3;
  CHECK(spec_error(j).find("/fabric") != std::string::npos);
  j["fabric"] = "cotton-poplin";
  j["material"] = {{"k_stretch", 100}};
  CHECK(spec_error(j).find("not both") != std::string::npos);
}

TEST_CASE("the material round-trips through the garment file's JSON", "[garment][fabric]") {
  Json j = cap_spec();
  j["fabric"] = "jersey-interlock";
  const gp::Material m = gp::parse_garment_spec(j, "s.json").material;
  const Json written = Json::parse(gp::to_json(m).dump());
  const gp::Material back = gp::read_material(gp::SpecObject(written, "garment.json", "/material"));
  CHECK(back.fabric == "jersey-interlock");
  CHECK(back.k_stretch == m.k_stretch);
  CHECK(back.k_stretch_weft == m.k_stretch_weft);
  CHECK(back.stretch_limit_warp == m.stretch_limit_warp);
  CHECK(back.stretch_limit_weft == m.stretch_limit_weft);
  CHECK(back.knit);
  // A garment file of before the fabrics (no such keys) reads as the paper's isotropic material.
  const Json old = {{"k_stretch", 800.0}, {"k_shear", 200.0}};
  const gp::Material o = gp::read_material(gp::SpecObject(old, "garment.json", "/material"));
  CHECK(o.fabric == "paper");
  CHECK(o.k_stretch_weft == 800.0);
  CHECK_FALSE(o.has_own_limits());
}

TEST_CASE("make-garment refuses an unknown fabric in one line with exit 4, and names a known one", "[garment][fabric][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("garment_fabric_cli");
  gp::write_mesh(dir / "body.ply", gp::testing::make_icosphere(4, 0.2));
  Json good = cap_spec(), bad = cap_spec();
  good["fabric"] = "cotton-poplin";
  bad["fabric"] = "tweed";
  std::ofstream(dir / "good.json") << good.dump(2);
  std::ofstream(dir / "bad.json") << bad.dump(2);
  const std::string mg = gp::testing::tool_path("make-garment");
  const std::string d = dir.string();
  auto r = gp::testing::run_command(mg + " " + d + "/bad.json --avatar " + d + "/body.ply --out " + d + "/bad");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("make-garment: error[spec]: unknown fabric 'tweed' (known: paper, cotton-poplin") == 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir / "bad"));
  r = gp::testing::run_command(mg + " " + d + "/good.json --avatar " + d + "/body.ply --out " + d + "/good -q");
  REQUIRE(r.exit_code == 0);
  const gp::GarmentFile g = gp::read_garment_file(dir / "good" / "garment.json");
  CHECK(g.material.fabric == "cotton-poplin");
  CHECK(g.material.k_stretch == gp::fabric::find_fabric("cotton-poplin")->k_warp);
  fs::remove_all(dir);
}

TEST_CASE("negative ease: knits only, within what the knit's stretch allows", "[garment][fabric]") {
  Json j = cap_spec();
  j["fabric"] = "jersey-interlock";  // limits 1.15 warp, 1.30 weft: at least 1 / 1.15 - 1 = -0.130
  j["ease"] = -0.08;
  CHECK(gp::parse_garment_spec(j, "s.json").ease == -0.08);
  j["ease"] = -0.14;
  CHECK(spec_error(j).find("beyond what the knit's stretch allows") != std::string::npos);
  j["ease"] = 0.05;
  CHECK(spec_error(j).find("/ease") != std::string::npos);
  j["fabric"] = "cotton-poplin";
  j["ease"] = -0.02;
  CHECK(spec_error(j).find("needs a knit") != std::string::npos);
}

TEST_CASE("make-garment puts a knit's negative ease into the paint", "[garment][fabric][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("garment_ease_cli");
  gp::write_mesh(dir / "body.ply", gp::testing::make_icosphere(4, 0.2));
  Json j = cap_spec();
  j["fabric"] = "jersey-interlock";
  j["ease"] = -0.08;
  std::ofstream(dir / "knit.json") << j.dump(2);
  const std::string d = dir.string();
  const auto r = gp::testing::run_command(gp::testing::tool_path("make-garment") + " " + d + "/knit.json --avatar " + d +
                                          "/body.ply --out " + d + "/knit -q");
  REQUIRE(r.exit_code == 0);
  const gp::GarmentFile g = gp::read_garment_file(dir / "knit" / "garment.json");
  CHECK(g.ease == -0.08);
  REQUIRE(!g.paint.empty());
  for (double p : g.paint) CHECK(p == Approx(0.92 * 0.92).epsilon(1e-12));
  fs::remove_all(dir);
}
