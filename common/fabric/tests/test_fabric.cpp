// The fabric library: names, ranges, the paper preset, the conversion of the
// measured tables (README.md), and quantities with units.
#include <catch2/catch.hpp>

#include <set>
#include <string>

#include "core/error.h"
#include "fabric/fabric.h"
#include "fabric/fabric_units.h"

using namespace gp::fabric;

TEST_CASE("the library's fabrics are named once, valid, and paper comes first", "[fabric]") {
  const auto& lib = fabric_library();
  REQUIRE(lib.size() >= 8);
  CHECK(lib.front().name == "paper");
  std::set<std::string> names;
  for (const Fabric& f : lib) {
    INFO(f.name);
    CHECK(names.insert(f.name).second);
    CHECK_NOTHROW(check_fabric(f, f.name));
    CHECK(!f.description.empty());
    CHECK(!f.source.empty());
    // The warp is the stiffer direction of every measured fabric (README.md,
    // "Which axis is the warp").
    CHECK(f.k_warp >= f.k_weft);
    // The bias gives way: shear is far below the stretch stiffness.
    CHECK(f.k_shear < f.k_weft);
    if (f.name != "paper") {
      CHECK(f.has_own_limits());
      CHECK(f.limit_weft >= f.limit_warp);
    }
  }
  for (const char* required : {"cotton-poplin", "denim-11oz", "cotton-polyester-twill", "jersey-interlock", "rib-knit",
                               "swimwear-knit", "polyester-jet-set"}) {
    CHECK(find_fabric(required) != nullptr);
  }
  CHECK(find_fabric("silk") == nullptr);
  CHECK(fabric_names().find("paper, cotton-poplin, ") == 0);
}

TEST_CASE("paper is the project's former isotropic material, with the fit's own limit", "[fabric]") {
  const Fabric& p = *find_fabric("paper");
  CHECK(p.k_warp == 800.0);
  CHECK(p.k_weft == 800.0);
  CHECK(p.k_shear == 200.0);
  CHECK(p.k_bend == 1e-6);
  CHECK(p.areal_density == 0.15);
  CHECK(p.damping_stretch == 100.0);
  CHECK(p.damping_shear == 1.0);
  CHECK(p.damping_bend == 1e-5);
  CHECK(p.compression_ratio == 0.1);
  CHECK_FALSE(p.has_own_limits());
  CHECK_FALSE(p.knit);
}

TEST_CASE("the library's membrane values follow from the measured tables by README's rules", "[fabric]") {
  // Wang et al. 2011 tables (c11, c12, c22, c33 in N/m; row 0 at zero strain,
  // rows 1-5 at 16.7 % strain along 0, 22.5, 45, 67.5, 90 degrees from axis 0).
  struct Table {
    const char* name;
    double rows[6][4];
  };
  const Table tables[] = {
      {"denim-11oz",
       {{205.352005, 10.234077, 1013.88629, 53.387184},
        {232.027634, 40.646339, 1052.84289, 64.980499},
        {224.592209, 40.384563, 1054.43444, 67.184807},
        {225.951050, 62.095657, 1059.59741, 83.992020},
        {226.039566, 40.502792, 1058.27771, 75.118423},
        {225.767487, 40.917892, 1051.55712, 71.810631}}},
      {"jersey-interlock",
       {{16.593832, -14.695990, 34.477123, 36.860302},
        {46.364765, 53.694656, 261.013855, -29.691301},
        {49.285110, 87.596100, 206.373993, 22.768457},
        {123.989220, 105.181770, 365.966217, 44.217571},
        {139.686325, 73.592560, 413.553162, -174.43853},
        {127.443810, 85.848587, 405.872833, 32.238411}}},
  };
  for (const Table& t : tables) {
    INFO(t.name);
    const Fabric& f = *find_fabric(t.name);
    CHECK(f.k_warp == Approx(t.rows[0][2] + t.rows[5][2]).epsilon(1e-4));
    CHECK(f.k_weft == Approx(t.rows[0][0] + t.rows[1][0]).epsilon(1e-4));
    CHECK(f.k_shear == Approx((t.rows[0][3] + t.rows[3][3]) / 4.0).epsilon(1e-3));
  }
}

TEST_CASE("quantities with units convert to SI and wrong units are refused", "[fabric]") {
  CHECK(parse_quantity("0.2 kg/m^2", Dimension::areal_density) == Approx(0.2));
  CHECK(parse_quantity("150 g/m^2", Dimension::areal_density) == Approx(0.15));
  CHECK(parse_quantity("11 oz/yd^2", Dimension::areal_density) == Approx(0.37297).epsilon(1e-4));
  CHECK(parse_quantity("0.5 mm", Dimension::length) == Approx(5e-4));
  CHECK(parse_quantity("800 N/m", Dimension::tension) == Approx(800.0));
  CHECK(parse_quantity("8 N/cm", Dimension::tension) == Approx(800.0));
  CHECK(parse_quantity("10 gf/cm", Dimension::tension) == Approx(9.80665));
  CHECK(parse_quantity("20 uN m", Dimension::bending) == Approx(2e-5));
  // KES-F bending rigidity B = 0.1 gf cm^2/cm is 9.8 uN m.
  CHECK(parse_quantity("0.1 gf cm^2/cm", Dimension::bending) == Approx(9.80665e-6));
  CHECK(parse_quantity(" 100 N s/m ", Dimension::damping_tension) == Approx(100.0));
  CHECK_THROWS_AS(parse_quantity("800", Dimension::tension), gp::SpecError);
  CHECK_THROWS_AS(parse_quantity("800 kg/m^2", Dimension::tension), gp::SpecError);
  CHECK_THROWS_AS(parse_quantity("N/m", Dimension::tension), gp::SpecError);
  CHECK_THROWS_WITH(parse_quantity("1 inch", Dimension::length), Catch::Contains("accepted: m, mm, um"));
}

TEST_CASE("out-of-range fabrics are refused", "[fabric]") {
  Fabric f = *find_fabric("cotton-poplin");
  CHECK_NOTHROW(check_fabric(f, "x"));
  Fabric g = f;
  g.k_weft = 0.0;
  CHECK_THROWS_AS(check_fabric(g, "x"), gp::SpecError);
  g = f;
  g.limit_weft = 0.9;
  CHECK_THROWS_AS(check_fabric(g, "x"), gp::SpecError);
  g = f;
  g.limit_weft = 0.0;  // one limit without the other
  CHECK_THROWS_AS(check_fabric(g, "x"), gp::SpecError);
  g = f;
  g.areal_density = -1.0;
  CHECK_THROWS_AS(check_fabric(g, "x"), gp::SpecError);
}
