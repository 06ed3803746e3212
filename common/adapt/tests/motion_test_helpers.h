#pragma once
// Motion runs of the library on a hard-case scene (hard_case_scene.h), and the
// comparison of two runs' fits, shared by the adapt module's tests.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapt/garment_motion.h"
#include "garment/garment_file.h"
#include "hard_case_scene.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"

namespace gp::hard_cases {

using adapt::MotionRunOptions;
using adapt::MotionRunResult;

// Everything a motion run needs, read back from a scene's files.
struct Loaded {
  gp::PoseSet poses;
  gp::GarmentFile garment;
  gp::Mesh mesh;
};

inline Loaded load(const Scene& scene) {
  Loaded l;
  l.poses = gp::load_pose_set(scene.poses);
  l.garment = gp::read_garment_file(scene.garment);
  l.mesh = gp::read_mesh(scene.garment.parent_path() / l.garment.mesh_file).mesh;
  return l;
}

inline gp::MotionSpec motion_of(const gp::PoseSet& poses, const std::vector<std::string>& sequence, int steps) {
  gp::Json j;
  j["schema"] = "motion/1";
  j["steps"] = steps;
  j["sequence"] = sequence;
  return gp::parse_motion_spec(j, "motion.json", poses);
}

// simulate-adapt's defaults with a cap on the work at each key pose: the
// settling steps, and as many Newton iterations of the static solve.
inline MotionRunOptions run_options(int settle_max_steps) {
  MotionRunOptions o;
  o.settle.max_steps = settle_max_steps;
  o.settle.statics.max_iterations = std::max(settle_max_steps, 1);
  return o;
}

inline MotionRunResult run(const Loaded& l, const gp::MotionSpec& motion, const Eigen::MatrixXd& V_start,
                           const MotionRunOptions& options) {
  gp::InterpolationOptions io;
  io.anchor = motion.anchor;
  gp::PoseInterpolator interpolator(l.poses, io);
  return run_garment_motion(interpolator, motion, V_start, l.mesh.F, l.garment, options);
}

// The same fit at every key pose: drapes within `max_distance` at any vertex
// and `mean_distance` on average, rest-area growth within `growth` (1 %),
// 99th-percentile stretch within 0.01, and b no deeper than 2 mm inside the
// body.
inline void check_same_fit(const MotionRunResult& a, const MotionRunResult& b, double max_distance,
                           double mean_distance = 0.01, double growth = 0.01) {
  REQUIRE(a.keys.size() == b.keys.size());
  for (size_t k = 0; k < a.keys.size(); ++k) {
    const Eigen::VectorXd d = (a.keys[k].V_draped - b.keys[k].V_draped).rowwise().norm();
    INFO("key " << a.keys[k].pose << ": max vertex distance " << d.maxCoeff() << " m, mean " << d.mean()
                << " m; growth " << a.keys[k].rest_area_growth << " vs " << b.keys[k].rest_area_growth
                << "; p99 stretch " << a.keys[k].p99_stretch << " vs " << b.keys[k].p99_stretch << "; max stretch "
                << a.keys[k].max_stretch << " vs " << b.keys[k].max_stretch << "; deepest "
                << a.keys[k].deepest_penetration << " vs " << b.keys[k].deepest_penetration << "; steps "
                << a.keys[k].steps << " vs " << b.keys[k].steps << ", settling " << a.keys[k].settle_steps << " vs "
                << b.keys[k].settle_steps << "; rejected " << a.solver.rejected << " vs " << b.solver.rejected);
    CHECK(b.keys[k].V_draped.allFinite());
    CHECK(d.maxCoeff() < max_distance);
    CHECK(d.mean() < mean_distance);
    CHECK(std::abs(a.keys[k].rest_area_growth - b.keys[k].rest_area_growth) < growth);
    CHECK(std::abs(a.keys[k].p99_stretch - b.keys[k].p99_stretch) < 0.01);
    CHECK(b.keys[k].deepest_penetration < 0.002);
  }
}

}  // namespace gp::hard_cases
