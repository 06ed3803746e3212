#include "adapt/fit_inputs.h"

#include <filesystem>

#include "core/error.h"
#include "io/mesh_io.h"
#include "registration/edge_ratios.h"

namespace gp::adapt {

namespace fs = std::filesystem;

FitInputs read_fit_inputs(const std::string& poses_path, const std::string& motion_path,
                          const std::string& garment_path, bool other_body) {
  FitInputs in;
  in.poses = load_pose_set(poses_path);
  in.motion = read_motion_spec(motion_path, in.poses);
  const PoseSet& poses = in.poses;
  // A hand-written manifest bypasses register-check; a pose with vertices
  // thrown away by a registration error would be fitted into the rest shape.
  {
    std::vector<int> used;
    for (const MotionKey& key : in.motion.keys) used.push_back(key.pose_index);
    check_pose_edge_ratios(poses, used, kDefaultMaxEdgeRatio, poses_path);
  }
  in.garment = read_garment_file(garment_path);
  const GarmentFile& garment = in.garment;
  const fs::path mesh_path = fs::path(garment_path).parent_path() / garment.mesh_file;
  MeshReadResult read = read_mesh(mesh_path);
  in.warnings = read.warnings;
  in.mesh = std::move(read.mesh);
  if (in.mesh.V.rows() != garment.vertex_count || in.mesh.F.rows() != garment.face_count) {
    throw InputError("garment mesh does not match the garment file's counts", mesh_path.string());
  }
  if (garment.body.vertex_count != 0 && garment.body.vertex_count != static_cast<long long>(poses.V[0].rows())) {
    throw GeometryError("the garment was designed on a body with " + std::to_string(garment.body.vertex_count) +
                            " vertices, the pose set has " + std::to_string(poses.V[0].rows()),
                        garment_path);
  }
  in.design = match_design_pose(garment, poses);
  const DesignPoseMatch& design = in.design;
  if (!design.same && !other_body)
    throw GeometryError("pose '" + garment.body.design_pose + "' of the pose set is another body than the "
                        "garment was designed on (its vertex checksum " + design.actual.substr(0, 16) +
                        ", the garment file's " + design.expected.substr(0, 16) +
                        "); pass --other-body to fit it deliberately",
                        poses_path);
  if (!design.same) {
    // The garment is put on the new body before it moves: carried with the
    // body where the design body can still be found, and cleared of it.
    Eigen::MatrixXd V_from;
    try {
      const DesignBody from = load_design_body(garment, garment_path, "");
      if (vertex_checksum(from.V) == design.expected) V_from = from.V;
    } catch (const InputError&) {
    }
    in.carried = carry_to_body(in.mesh.V, in.mesh.F, garment, V_from, poses.V[static_cast<size_t>(design.pose)],
                               poses.F);
    in.warnings.push_back("pose '" + garment.body.design_pose +
                          "' is another body than the garment was designed on; the garment was " +
                          (in.carried->carried ? "carried to it and " : "") + "cleared of it (" +
                          (in.carried->clearance.clear() ? "clear" : "still crossing it") +
                          ") as --other-body asks");
  }
  return in;
}

}  // namespace gp::adapt
