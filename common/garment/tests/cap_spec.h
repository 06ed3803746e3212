#pragma once
// The smallest garment spec the spec tests build (a cap of a sphere: one
// loop), and the message of the SpecError a spec is refused with.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "core/error.h"
#include "garment/garment_spec.h"
#include "spec/json_file.h"

namespace gp::testing {

inline Json cap_spec() {
  Json points = Json::array();
  for (int j = 0; j < 8; ++j) {
    const double phi = 2.0 * 3.14159265358979323846 * j / 8;
    points.push_back({0.2 * 0.6 * std::cos(phi), 0.2 * 0.8, 0.2 * 0.6 * std::sin(phi)});
  }
  Json j;
  j["schema"] = "garment-spec/1";
  j["name"] = "cap";
  j["loops"] = Json::array({{{"name", "rim"}, {"points", points}}});
  j["region"] = {0.0, 0.2, 0.0};
  j["resolution"] = {{"edge_length", 0.02}};
  return j;
}

inline std::string spec_error(const Json& j) {
  try {
    parse_garment_spec(j, "s.json");
  } catch (const SpecError& e) {
    return e.message();
  }
  FAIL("no SpecError");
  return "";
}

}  // namespace gp::testing
