// The collider keeps the body faces the garment can reach in any key pose,
// not in the first frame alone: a hand that hangs far from the skirt at the
// start and comes down onto it later was culled and passed through the
// skirt (the demo-dress, BENCHMARKS.md).
#include <catch2/catch.hpp>

#include <algorithm>
#include <iterator>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapt/garment_motion.h"
#include "collision/body_collider.h"
#include "hard_case_scene.h"
#include "motion_test_helpers.h"
#include "testing/files.h"

using namespace gp::adapt;
namespace hc = gp::hard_cases;

TEST_CASE("the body faces kept are those within reach of the garment in the first frame or any key pose",
          "[adapt][collision]") {
  // The generated top on the small body, from the A-pose, where the hands
  // hang 0.25-0.3 m from the garment, to the hands on the thighs, beside its
  // hem. Expectation: the run keeps exactly the union of the faces within
  // reach (simulate-adapt's 0.15 m) in each key pose, measured here afresh;
  // the hands' faces make it larger than the first frame's set.
  std::string log;
  const hc::Scene scene = hc::build_scene(gp::testing::fresh_temp_dir("reach_hands"), "", "apose,handsonthighs", 350, log);
  REQUIRE_FALSE(scene.dir.empty());
  const hc::Loaded l = hc::load(scene);
  const gp::MotionSpec motion = hc::motion_of(l.poses, {"apose", "handsonthighs"}, 12);
  MotionRunOptions o = hc::run_options(0);
  o.adaptation.enabled = false;
  const MotionRunResult r = hc::run(l, motion, l.mesh.V, o);
  const gp::collision::ContactSurface& surface = r.contact_surface;
  std::vector<int> kept, first;
  for (const gp::MotionKey& key : motion.keys) {
    const std::vector<int> near = gp::collision::reachable_body_faces(
        surface.positions(l.poses.V[static_cast<size_t>(key.pose_index)]), surface.F, l.mesh.V, o.contact.reach);
    if (first.empty()) first = near;
    std::vector<int> merged;
    std::set_union(kept.begin(), kept.end(), near.begin(), near.end(), std::back_inserter(merged));
    kept = merged;
  }
  INFO("first frame " << first.size() << ", union " << kept.size() << ", the run's " << r.culled_body_faces);
  CHECK(kept.size() > first.size() + 20);
  CHECK(r.culled_body_faces == kept.size());
}
