#pragma once
// The motion spec (schema "motion/1"): which poses the body moves through and
// how many frames each transition takes. interp-poses writes the frames;
// simulate-adapt reads the same spec and moves the body in memory.
//
//   {
//     "schema": "motion/1",
//     "steps": 60,                        // frames per transition (default 60, >= 1)
//     "sequence": [ "apose",              // key poses in order: names, or objects
//                   { "pose": "armsup", "steps": 30 },   // with this transition's own steps
//                   "apose" ],
//     "anchor": { "fraction": 0.2 }       // optional: translation anchor, either
//                                         // {"fraction": f} (f of the vertices nearest the
//                                         // reference pose's centroid, default 0.2) or
//                                         // {"vertex_ids": [ ... ]}
//   }
//
// A transition with n steps contributes the frames t = 1/n, 2/n, ..., 1 after
// its first key; frame 0 is the first key, so a sequence has
// 1 + sum of steps frames and every key appears exactly once per visit.
#include <filesystem>
#include <string>
#include <vector>

#include "interp/pose_interpolator.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"

namespace gp {

struct MotionKey {
  std::string pose;     // pose name
  int pose_index = -1;  // index into the pose set
  int steps = 0;        // frames of the transition that ends at this key (0 for the first key)
};

struct MotionSpec {
  int default_steps = 60;
  std::vector<MotionKey> keys;
  AnchorOptions anchor;
};

struct MotionFrame {
  int index = 0;       // frame number from 0
  int from = 0;        // pose index at t = 0 of the transition
  int to = 0;          // pose index at t = 1
  double t = 0.0;      // in [0, 1]
  int transition = 0;  // 0-based transition (keys[transition] -> keys[transition + 1])
  int key = -1;        // index into keys if this frame is a key pose, else -1
};

// Strict reading; SpecError names the file and JSON pointer of the bad field
// (wrong schema, unknown pose name, steps < 1, unknown key, ...).
MotionSpec read_motion_spec(const std::filesystem::path& path, const PoseSet& poses);
MotionSpec parse_motion_spec(const Json& j, const std::string& file, const PoseSet& poses);

// Every frame of the motion in order.
std::vector<MotionFrame> motion_frames(const MotionSpec& spec);

// The effective spec (defaults filled in), for reports.
OrderedJson to_json(const MotionSpec& spec);

}  // namespace gp
