#include <catch2/catch.hpp>

#include <string>

#include "core/error.h"
#include "interp/motion_spec.h"
#include "interp_fixtures.h"

namespace {

gp::PoseSet three_poses() {
  const gp::Mesh m = gp::testing::make_icosphere(0);
  return interp_test::make_pose_set(m.F, {m.V, 2.0 * m.V, 3.0 * m.V}, {"apose", "tpose", "armsup"});
}

// The SpecError message and location of parsing `text`.
std::string spec_error(const std::string& text) {
  try {
    gp::parse_motion_spec(gp::Json::parse(text), "motion.json", three_poses());
  } catch (const gp::SpecError& e) {
    return e.message();
  }
  return "no error";
}

}  // namespace

TEST_CASE("a motion spec lists keys with steps and expands into frames", "[interp][motion]") {
  const gp::MotionSpec spec = gp::parse_motion_spec(
      gp::Json::parse(R"({"schema": "motion/1", "steps": 4,
                          "sequence": ["apose", {"pose": "armsup", "steps": 2}, "tpose"]})"),
      "motion.json", three_poses());
  REQUIRE(spec.keys.size() == 3);
  CHECK(spec.keys[1].pose_index == 2);
  CHECK(spec.keys[1].steps == 2);
  CHECK(spec.keys[2].steps == 4);
  CHECK(spec.anchor.fraction == 0.2);
  const auto frames = gp::motion_frames(spec);
  REQUIRE(frames.size() == 1 + 2 + 4);
  CHECK(frames[0].key == 0);
  CHECK(frames[1].t == 0.5);
  CHECK(frames[1].from == 0);
  CHECK(frames[1].to == 2);
  CHECK(frames[2].t == 1.0);
  CHECK(frames[2].key == 1);
  CHECK(frames[3].from == 2);
  CHECK(frames[3].to == 1);
  CHECK(frames[3].t == 0.25);
  CHECK(frames[6].key == 2);
  CHECK(frames[6].transition == 1);
  for (size_t i = 0; i < frames.size(); ++i) CHECK(frames[i].index == static_cast<int>(i));

  // The effective spec round-trips.
  const gp::MotionSpec again =
      gp::parse_motion_spec(gp::Json::parse(gp::to_json(spec).dump()), "again.json", three_poses());
  CHECK(gp::motion_frames(again).size() == frames.size());
  CHECK(again.keys[2].steps == 4);
}

TEST_CASE("the default is 60 steps per transition; a single key is one frame", "[interp][motion]") {
  const auto spec = gp::parse_motion_spec(
      gp::Json::parse(R"({"schema": "motion/1", "sequence": ["apose", "armsup"],
                          "anchor": {"vertex_ids": [0, 3]}})"),
      "m.json", three_poses());
  CHECK(gp::motion_frames(spec).size() == 61);
  CHECK(spec.anchor.vertex_ids == std::vector<int>{0, 3});
  const auto single =
      gp::parse_motion_spec(gp::Json::parse(R"({"schema": "motion/1", "sequence": ["tpose"]})"), "m.json",
                            three_poses());
  CHECK(gp::motion_frames(single).size() == 1);
}

TEST_CASE("bad motion specs name the offending field", "[interp][motion]") {
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose", "waving"]})"),
             Catch::Contains("unknown pose 'waving'") && Catch::Contains("motion.json: /sequence/1"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose", {"pose": "sitting"}]})"),
             Catch::Contains("unknown pose 'sitting'") && Catch::Contains("/sequence/1/pose"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "steps": 0, "sequence": ["apose", "tpose"]})"),
             Catch::Contains("/steps") && Catch::Contains("out of range"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose", {"pose": "tpose", "steps": 0}]})"),
             Catch::Contains("/sequence/1/steps"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose", {"pose": "tpose", "steps": 2.5}]})"),
             Catch::Contains("/sequence/1/steps"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": [{"pose": "apose", "steps": 3}, "tpose"]})"),
             Catch::Contains("/sequence/0/steps"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": []})"), Catch::Contains("/sequence"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose", 7]})"),
             Catch::Contains("/sequence/1"));
  CHECK_THAT(spec_error(R"({"schema": "motion/2", "sequence": ["apose"]})"), Catch::Contains("schema"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose"], "fps": 30})"),
             Catch::Contains("/fps"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose"], "anchor": {"vertex_ids": [99]}})"),
             Catch::Contains("/anchor/vertex_ids"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose"], "anchor": {"fraction": 0}})"),
             Catch::Contains("/anchor/fraction"));
  CHECK_THAT(spec_error(R"({"schema": "motion/1", "sequence": ["apose"],
                            "anchor": {"fraction": 0.5, "vertex_ids": [1]}})"),
             Catch::Contains("/anchor"));
}
