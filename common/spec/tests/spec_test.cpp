#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "spec/json_file.h"
#include "spec/spec_object.h"
#include "testing/command.h"

namespace fs = std::filesystem;

namespace {

template <class Fn>
void require_spec_error(Fn f, const std::string& text) {
  try {
    f();
    FAIL("no error thrown; expected: " << text);
  } catch (const gp::SpecError& e) {
    CHECK_THAT(e.message(), Catch::Contains(text));
  }
}

}  // namespace

TEST_CASE("schema tags are checked by name and version", "[spec]") {
  const gp::Json ok = gp::Json::parse(R"({"schema": "garment-spec/1"})");
  CHECK(gp::check_schema(ok, "garment-spec", {1}, "g.json") == 1);
  require_spec_error([] { gp::check_schema(gp::Json::parse(R"({"schema": "garment-spec/2"})"), "garment-spec", {1}, "g.json"); },
                     "unsupported schema version \"garment-spec/2\" (this build reads garment-spec/1) (g.json: /schema)");
  require_spec_error([] { gp::check_schema(gp::Json::parse(R"({"schema": "motion/1"})"), "garment-spec", {1}, "g.json"); },
                     "expected \"garment-spec/<version>\"");
  require_spec_error([] { gp::check_schema(gp::Json::parse(R"({})"), "garment-spec", {1}, "g.json"); },
                     "missing field 'schema'");
  require_spec_error([] { gp::check_schema(gp::Json::parse(R"({"schema": 1})"), "x", {1}, "g.json"); },
                     "'schema' must be a string");
  require_spec_error([] { gp::check_schema(gp::Json::parse(R"({"schema": "x/1a"})"), "x", {1}, "g.json"); },
                     "unsupported schema version");
}

TEST_CASE("strict reading names the JSON path of bad fields", "[spec]") {
  const gp::Json j = gp::Json::parse(R"({
    "height": 1.8, "name": "anna", "steps": 60, "flag": true,
    "measurements": {"waist": -0.7, "hip": "wide"},
    "loops": [{"points": [1, 2, 3]}, {"points": [1, 2], "extra": 1}],
    "a/b": 3
  })");
  gp::SpecObject root(j, "spec.json");
  CHECK(root.number("height", 0, gp::Range::positive()) == 1.8);
  CHECK(root.number("absent", 2.5) == 2.5);
  CHECK(root.string("name", "") == "anna");
  CHECK(root.integer("steps", 1, gp::Range::positive()) == 60);
  CHECK(root.boolean("flag", false));
  require_spec_error([&] { root.integer("height", 0); }, "expected an integer, found number (spec.json: /height)");
  require_spec_error([&] { root.required_number("missing"); }, "missing required field 'missing' (spec.json: /missing)");
  require_spec_error([&] { root.choice("name", "", {"bob", "carl"}); }, "unknown value 'anna' (one of: bob, carl)");

  gp::SpecObject m = root.object("measurements");
  require_spec_error([&] { m.number("waist", 0.8, gp::Range::positive()); },
                     "value -0.7 out of range: must be positive (spec.json: /measurements/waist)");
  require_spec_error([&] { m.number("hip", 1.0); }, "expected a number, found string (spec.json: /measurements/hip)");

  gp::SpecArray loops = root.array("loops");
  REQUIRE(loops.size() == 2);
  gp::SpecObject first = loops.object(0);
  CHECK(first.numbers("points", 3).size() == 3);
  first.finish();
  gp::SpecObject second = loops.object(1);
  require_spec_error([&] { second.numbers("points", 3); }, "expected 3 numbers, found 2 (spec.json: /loops/1/points)");
  require_spec_error([&] { second.finish(); }, "unknown field 'extra' (spec.json: /loops/1/extra)");
  // Keys are escaped as JSON pointer tokens.
  require_spec_error([&] { root.finish(); }, "unknown field 'a/b' (spec.json: /a~1b)");
  root.allow("a/b");
  root.finish();
}

TEST_CASE("malformed JSON files are input errors with line and column", "[spec]") {
  const fs::path dir = gp::testing::fresh_temp_dir("spec_files");
  {
    std::ofstream(dir / "bad.json") << "{\n  \"a\": 1,\n  \"b\": ]\n}\n";
  }
  try {
    gp::read_json_file(dir / "bad.json");
    FAIL("no error");
  } catch (const gp::InputError& e) {
    CHECK_THAT(e.message(), Catch::Contains("malformed JSON") && Catch::Contains("bad.json:3:"));
  }
  { std::ofstream(dir / "empty.json") << "  \n"; }
  CHECK_THROWS_AS(gp::read_json_file(dir / "empty.json"), gp::InputError);
  CHECK_THROWS_AS(gp::read_json_file(dir / "absent.json"), gp::InputError);

  gp::OrderedJson out;
  out["schema"] = "x/1";
  out["z"] = 0.1 + 0.2;  // needs 17 digits to round-trip
  out["a"] = 1;
  gp::write_json_file(dir / "out.json", out);
  const gp::Json back = gp::read_json_file(dir / "out.json");
  CHECK(back["z"].get<double>() == 0.1 + 0.2);
  std::ifstream in(dir / "out.json");
  std::string first_line, second_line;
  std::getline(in, first_line);
  std::getline(in, second_line);
  CHECK_THAT(second_line, Catch::Contains("schema"));  // insertion order kept
  fs::remove_all(dir);
}
