#pragma once
// The inputs of a fit as simulate-adapt reads and admits them: the pose set,
// the motion, the garment file and its mesh, checked against each other, and
// a garment designed on another body carried to the pose set's body.
#include <optional>
#include <string>
#include <vector>

#include "garment/design_body.h"
#include "garment/garment_file.h"
#include "interp/motion_spec.h"
#include "io/mesh.h"
#include "pose/pose_set.h"

namespace gp::adapt {

struct FitInputs {
  PoseSet poses;
  MotionSpec motion;
  GarmentFile garment;
  Mesh mesh;                                 // the garment as designed (metres), carried when `carried`
  DesignPoseMatch design;                    // the pose set's design pose against the garment file's
  std::optional<CarryToBodyResult> carried;  // set when the design pose is another body
  std::vector<std::string> warnings;         // the mesh reader's, then the carry's, in that order
};

// Reads the pose set (pose-set/1), the motion (motion/1) and the garment file
// (garment/1) with the mesh beside it, and checks that they belong together:
// the poses the motion visits have sane edge ratios (a hand-written manifest
// bypasses register-check), the mesh has the garment file's counts, the body
// its vertex count. A design pose that is another body than the garment was
// designed on is refused (GeometryError, exit 5) unless `other_body`; then the
// garment is carried to it with the body where the design body can still be
// found (its checksum agrees), and cleared of it (carry_to_body).
FitInputs read_fit_inputs(const std::string& poses_path, const std::string& motion_path,
                          const std::string& garment_path, bool other_body);

}  // namespace gp::adapt
