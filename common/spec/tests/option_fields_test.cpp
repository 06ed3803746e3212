#include <catch2/catch.hpp>

#include "core/error.h"
#include "spec/option_fields.h"

namespace {

enum class Shape { round, square, flat };

struct Toy {
  double length = 0.5;  // m
  int count = 3;
  long big = 7;
  bool on = true;
  bool velocity = true;  // "velocity" or "projection"
  Shape shape = Shape::square;
};

struct ToyFields {
  template <class Fields>
  void operator()(Toy& t, Fields& f) const {
    f.number("length_m", t.length, gp::Range::positive());
    f.integer("count", t.count, gp::Range::between(1, 10));
    f.integer("big", t.big, gp::Range::non_negative());
    f.flag("on", t.on);
    f.names("contact", t.velocity, "velocity", "projection");
    f.choice("shape", t.shape,
             gp::ChoiceNames<Shape>{{Shape::round, "round"}, {Shape::square, "square"}, {Shape::flat, "flat"}});
  }
};

std::string spec_error(const gp::Json& j, bool required) {
  try {
    Toy t;
    const gp::SpecObject o(j, "toy.json");
    gp::read_options(o, required, t, ToyFields{});
  } catch (const gp::SpecError& e) {
    return e.message();
  }
  return "";
}

}  // namespace

TEST_CASE("options are written in their list's order and read back to the same values", "[spec]") {
  Toy t;
  t.length = 1e-7;
  t.count = 10;
  t.big = 1L << 40;
  t.on = false;
  t.velocity = false;
  t.shape = Shape::flat;
  const gp::OrderedJson j = gp::write_options(t, ToyFields{});
  CHECK(j.dump() ==
        R"({"length_m":1e-07,"count":10,"big":1099511627776,"on":false,"contact":"projection","shape":"flat"})");

  Toy back;
  const gp::Json parsed = gp::Json::parse(j.dump());
  const gp::SpecObject o(parsed, "toy.json");
  gp::read_options(o, true, back, ToyFields{});
  o.finish();  // every key written is a key read
  CHECK(back.length == t.length);
  CHECK(back.count == 10);
  CHECK(back.big == t.big);
  CHECK(!back.on);
  CHECK(!back.velocity);
  CHECK(back.shape == Shape::flat);
}

TEST_CASE("options are read strictly: missing, mistyped, out-of-range and unknown values are named", "[spec]") {
  const gp::Json full = gp::Json::parse(gp::write_options(Toy{}, ToyFields{}).dump());
  CHECK(spec_error(full, true).empty());

  gp::Json j = full;
  j.erase("count");
  CHECK_THAT(spec_error(j, true), Catch::Contains("missing field") && Catch::Contains("/count"));
  // Not required: a missing field keeps its value.
  {
    Toy t;
    t.count = 4;
    const gp::SpecObject o(j, "toy.json");
    gp::read_options(o, false, t, ToyFields{});
    CHECK(t.count == 4);
  }

  j = full;
  j["count"] = 11;
  CHECK_THAT(spec_error(j, false), Catch::Contains("toy.json") && Catch::Contains("/count"));
  j = full;
  j["count"] = 2.5;
  CHECK_THAT(spec_error(j, false), Catch::Contains("/count"));
  j = full;
  j["length_m"] = 0.0;
  CHECK_THAT(spec_error(j, false), Catch::Contains("/length_m"));
  j = full;
  j["length_m"] = "0.5";
  CHECK_THAT(spec_error(j, false), Catch::Contains("/length_m"));
  j = full;
  j["on"] = 1;
  CHECK_THAT(spec_error(j, false), Catch::Contains("/on"));
  j = full;
  j["contact"] = "friction";
  CHECK_THAT(spec_error(j, false), Catch::Contains("/contact") && Catch::Contains("projection"));
  j = full;
  j["shape"] = "oval";
  CHECK_THAT(spec_error(j, false), Catch::Contains("/shape") && Catch::Contains("round"));

  // A key the list does not name is left to the caller, whose finish()
  // rejects it where the object holds options only.
  j = full;
  j["colour"] = "red";
  Toy t;
  const gp::SpecObject o(j, "toy.json");
  gp::read_options(o, true, t, ToyFields{});
  CHECK_THROWS_AS(o.finish(), gp::SpecError);
}

namespace {

struct Box {
  double width = 0.2;  // m
  std::string label = "box";
  Toy inner;
};

struct BoxFields {
  template <class Fields>
  void operator()(Box& b, Fields& f) const {
    f.number("width_m", b.width, gp::Range::positive());
    f.text("label", b.label);
    f.group("inner", b.inner, ToyFields{});
  }
};

}  // namespace

TEST_CASE("a nested options struct is written as an object and read back strictly", "[spec]") {
  Box b;
  b.width = 3.0;
  b.inner.count = 9;
  b.inner.shape = Shape::round;
  b.label = "crate";
  const gp::OrderedJson j = gp::write_options(b, BoxFields{});
  CHECK(j.dump() ==
        R"({"width_m":3.0,"label":"crate","inner":{"length_m":0.5,"count":9,"big":7,"on":true,"contact":"velocity","shape":"round"}})");
  const gp::Json parsed = gp::Json::parse(j.dump());
  Box back;
  gp::read_options(gp::SpecObject(parsed, "box.json"), true, back, BoxFields{});
  CHECK(back.width == 3.0);
  CHECK(back.label == "crate");
  CHECK(back.inner.count == 9);
  CHECK(back.inner.shape == Shape::round);
  // A field missing inside the group is named by its pointer.
  gp::Json missing = parsed;
  missing["inner"].erase("count");
  try {
    Box c;
    gp::read_options(gp::SpecObject(missing, "box.json"), true, c, BoxFields{});
    FAIL("no error for a missing nested field");
  } catch (const gp::SpecError& e) {
    CHECK(std::string(e.message()).find("/inner/count") != std::string::npos);
  }
  // Not required: the group keeps its values where the object is absent.
  gp::Json none = parsed;
  none.erase("inner");
  Box d;
  gp::read_options(gp::SpecObject(none, "box.json"), false, d, BoxFields{});
  CHECK(d.inner.count == 3);
}

namespace {

// A choice written only away from its usual value, and a number that only that choice has.
struct Rare {
  Shape shape = Shape::round;
  double depth = 0.1;  // m, with Shape::flat only
};

struct RareFields {
  template <class Fields>
  void operator()(Rare& r, Fields& f) const {
    f.optional_choice("shape", r.shape,
                      gp::ChoiceNames<Shape>{{Shape::round, "round"}, {Shape::square, "square"}, {Shape::flat, "flat"}},
                      Shape::round);
    if (r.shape == Shape::flat) f.number("depth_m", r.depth, gp::Range::positive());
  }
};

}  // namespace

TEST_CASE("an optional choice is written only away from its absent value, which a missing key reads as",
          "[spec]") {
  Rare usual;
  CHECK(gp::write_options(usual, RareFields{}).dump() == "{}");
  Rare rare;
  rare.shape = Shape::flat;
  rare.depth = 0.25;
  const gp::OrderedJson j = gp::write_options(rare, RareFields{});
  CHECK(j.dump() == R"({"shape":"flat","depth_m":0.25})");

  const gp::Json parsed = gp::Json::parse(j.dump());
  Rare back;
  gp::read_options(gp::SpecObject(parsed, "rare.json"), true, back, RareFields{});
  CHECK(back.shape == Shape::flat);
  CHECK(back.depth == 0.25);

  // Required: a missing key is the absent value, not the one the struct had.
  const gp::Json empty = gp::Json::object();
  Rare was_flat = rare;
  gp::read_options(gp::SpecObject(empty, "rare.json"), true, was_flat, RareFields{});
  CHECK(was_flat.shape == Shape::round);
  // Not required (a spec): the value it had.
  Rare kept = rare;
  const gp::Json only_depth = gp::Json::parse(R"({"depth_m":0.5})");
  gp::read_options(gp::SpecObject(only_depth, "rare.json"), false, kept, RareFields{});
  CHECK(kept.shape == Shape::flat);
  CHECK(kept.depth == 0.5);
  // The choice's names are checked as a plain choice's.
  const gp::Json bad = gp::Json::parse(R"({"shape":"oval"})");
  CHECK_THROWS_AS(gp::read_options(gp::SpecObject(bad, "rare.json"), true, back, RareFields{}), gp::SpecError);
}
