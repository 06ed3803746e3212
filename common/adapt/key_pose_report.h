#pragma once
// A key pose's figures as the stages' reports write them: simulate-adapt's
// key_poses and verification lists, and export-rest's sewn-fit check.
#include <string>
#include <vector>

#include "adapt/key_pose.h"
#include "spec/json_file.h"

namespace gp::adapt {

// `mesh`: the drape's file name. Without `failures`, the adaptation run's
// layout: key, pose, mesh, the stretch figures, penetration, the rest area's
// growth and last change, steps, settling, speeds, crossings and the held
// cloth. With `failures` (a verification's check of the pose; empty: passed),
// the verification's: verdict and failures after the mesh, the torn area
// fraction and crossings after the stretch figures, and neither the rest area
// nor the speeds. Each layout's key order is that of its readers' reports.
OrderedJson key_pose_json(const KeyPoseResult& k, const std::string& mesh,
                          const std::vector<std::string>* failures = nullptr, double area_fraction_torn = 0.0);

}  // namespace gp::adapt
