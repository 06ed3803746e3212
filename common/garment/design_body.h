#pragma once
// The body a garment was designed on, found from its garment file: for the
// stages after make-garment that need it (extend-boundary keeps the extension
// off it, export-rest maps seams given on the body).
#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "garment/body_clearance.h"
#include "garment/garment_file.h"
#include "pose/pose_set.h"

namespace gp {

struct DesignBody {
  Eigen::MatrixXd V;  // #Vb by 3, metres
  Eigen::MatrixXi F;  // #Fb by 3
};

// Loads the design-pose body named by the garment file: `source` (a pose-set
// manifest or a mesh) if not empty, else the garment's body.source as given or
// relative to the garment file's folder. InputError if it cannot be found,
// GeometryError if its counts differ from the garment file's.
DesignBody load_design_body(const GarmentFile& garment, const std::filesystem::path& garment_path,
                            const std::string& source);

// The pose set's pose named as the garment's design pose, compared with the
// body the garment was designed on (body.design_pose_sha256, a
// gp::vertex_checksum): a pose set of another body on the same template has
// the same counts and topology, and a garment fitted to it starts inside or
// far off the body.
struct DesignPoseMatch {
  int pose = -1;         // index in the pose set; -1 when the set has no pose of that name
  bool checked = false;  // false: no pose of that name, or a garment file without the checksum
  bool same = true;      // the checksums agree (true when not checked)
  std::string expected;  // the garment file's checksum
  std::string actual;    // the pose set's pose's checksum
};
DesignPoseMatch match_design_pose(const GarmentFile& garment, const PoseSet& poses);

struct CarryToBodyResult {
  bool carried = false;          // moved with the body (the design body was given), else only cleared
  double largest_carry = 0.0;    // m: largest move with the body
  BodyClearanceResult clearance; // of the new body, after the carry
};

// A garment designed on one body, put on another body on the same template
// (same triangles, vertex i the same body point) in its design pose, as a
// maternity garment designed on the slim body is fitted to the pregnant one.
// V (#V by 3, moved in place), F: the garment. V_to, F_body: the new body.
// V_from: the body it was designed on (same shape as V_to), or empty. With
// V_from, each vertex first moves with its closest body point (x += p_to -
// p_from, the same face and barycentric coordinates on both bodies). Bound
// loop vertices then take their binding-rule position on the new body, and
// the garment is cleared of the new body at its comfort offset (clear_body,
// bound vertices held).
CarryToBodyResult carry_to_body(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const GarmentFile& garment,
                                const Eigen::MatrixXd& V_from, const Eigen::MatrixXd& V_to,
                                const Eigen::MatrixXi& F_body);

}  // namespace gp
