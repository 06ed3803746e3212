// Key poses solved statically (MotionRunOptions::settle.equilibrium static_solve) on the generated body:
// every key pose converges to the force-residual tolerance, the cloth stays out of the body, and the
// fit is the damped settling's within stated bounds.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include "adapt/garment_motion.h"
#include "hard_case_scene.h"
#include "motion_test_helpers.h"

using namespace gp::adapt;
namespace hc = gp::hard_cases;

TEST_CASE("key poses solved statically converge, stay clear of the body and fit as the damped settling does",
          "[adapt][body][static]") {
  // A-pose -> T-pose in 10 frames on the generated shirt, with adaptation.
  const hc::Loaded l = hc::load(hc::default_scene());
  const gp::MotionSpec motion = hc::motion_of(l.poses, {"apose", "tpose"}, 10);
  MotionRunOptions statics = hc::run_options(600);
  statics.settle.equilibrium = Equilibrium::static_solve;
  MotionRunOptions dynamic = hc::run_options(600);
  dynamic.settle.equilibrium = Equilibrium::dynamic;
  const MotionRunResult s = hc::run(l, motion, l.mesh.V, statics);
  const MotionRunResult d = hc::run(l, motion, l.mesh.V, dynamic);
  REQUIRE(s.keys.size() == 2);
  for (size_t k = 0; k < s.keys.size(); ++k) {
    const KeyPoseResult& key = s.keys[k];
    INFO("key " << key.pose << ": " << key.newton_iterations << " Newton iterations, force residual "
                << key.force_residual << ", " << key.crossings.crossings() << " crossings (" << key.crossings.body_edge_crossings << " body edges, " << key.crossings.body_vertices_behind << " body vertices behind)"
                << "; residual "
                << key.force_residual << "; rest growth " << key.rest_area_growth << " against "
                << d.keys[k].rest_area_growth << "; max stretch " << key.max_stretch << " against "
                << d.keys[k].max_stretch);
    CHECK(key.solved_static);
    CHECK(key.settled);
    CHECK(key.force_residual < statics.settle.statics.tolerance);
    CHECK(key.newton_iterations == static_cast<int>(key.force_residuals.size()) - 1);
    CHECK(key.force_residuals.back() == key.force_residual);
    // No cloth vertex inside the body: the barrier's guarantee. Body edges between cloth vertices
    // are not (adapt/README.md, "The static solve": no edge-edge barrier yet).
    CHECK(key.deepest_penetration == 0.0);
    CHECK(d.keys[k].crossings.crossings() == 0);
    CHECK(!d.keys[k].solved_static);
    // The fit: the rest growth within 2 % of the damped settling's, the largest stretch within 0.02.
    CHECK(key.rest_area_growth == Approx(d.keys[k].rest_area_growth).epsilon(0.02));
    CHECK(key.max_stretch == Approx(d.keys[k].max_stretch).margin(0.02));
  }
  CHECK(s.newton_iterations == s.keys[0].newton_iterations + s.keys[1].newton_iterations);
  CHECK(s.line_search_trials >= s.newton_iterations);
  CHECK(s.static_seconds > 0.0);
}

TEST_CASE("without adaptation a static key pose is one solve to the tolerance", "[adapt][body][static]") {
  const hc::Loaded l = hc::load(hc::default_scene());
  const gp::MotionSpec motion = hc::motion_of(l.poses, {"apose"}, 1);
  MotionRunOptions o = hc::run_options(300);
  o.settle.equilibrium = Equilibrium::static_solve;
  o.adaptation.enabled = false;
  const MotionRunResult r = hc::run(l, motion, l.mesh.V, o);
  REQUIRE(r.keys.size() == 1);
  INFO(r.keys[0].newton_iterations << " iterations, residual " << r.keys[0].force_residual);
  CHECK(r.keys[0].settled);
  CHECK(r.keys[0].force_residual < o.settle.statics.tolerance);
  CHECK(r.keys[0].rest_area_growth == 1.0);
  CHECK(r.adaptations == 0);
  // A cap below what the solve needs leaves the pose unsettled, and says so.
  o.settle.statics.max_iterations = 2;
  const MotionRunResult capped = hc::run(l, motion, l.mesh.V, o);
  CHECK(!capped.keys[0].settled);
  CHECK(capped.keys[0].newton_iterations == 2);
  CHECK(capped.keys[0].force_residual > o.settle.statics.tolerance);
}
