#include "garment/design_body.h"

#include <algorithm>

#include "core/error.h"
#include "garment/surface_point.h"
#include "io/mesh_io.h"
#include "mesh/measures.h"
#include "pose/pose_set.h"

namespace gp {

DesignBody load_design_body(const GarmentFile& garment, const std::filesystem::path& garment_path,
                            const std::string& source) {
  namespace fs = std::filesystem;
  fs::path path = source.empty() ? fs::path(garment.body.source) : fs::path(source);
  if (source.empty() && !fs::exists(path) && path.is_relative())
    path = garment_path.parent_path() / garment.body.source;
  if (path.empty() || !fs::exists(path))
    throw InputError("the body of the garment cannot be found (give it with --body)",
                     path.empty() ? garment_path.string() : path.string());
  DesignBody body;
  if (path.extension() == ".json") {
    const PoseSet set = load_pose_set(path);
    const int index = set.index_of(garment.body.design_pose, garment_path.string() + ": /body/design_pose");
    body.V = set.V[static_cast<size_t>(index)];
    body.F = set.F;
  } else {
    const MeshReadResult read = read_mesh(path);
    body.V = read.mesh.V;
    body.F = read.mesh.F;
  }
  if ((garment.body.vertex_count > 0 && body.V.rows() != garment.body.vertex_count) ||
      (garment.body.face_count > 0 && body.F.rows() != garment.body.face_count))
    throw GeometryError("the body has " + std::to_string(body.V.rows()) + " vertices and " +
                            std::to_string(body.F.rows()) + " triangles, the garment file expects " +
                            std::to_string(garment.body.vertex_count) + " and " +
                            std::to_string(garment.body.face_count),
                        path.string());
  return body;
}

DesignPoseMatch match_design_pose(const GarmentFile& garment, const PoseSet& poses) {
  DesignPoseMatch m;
  for (size_t i = 0; i < poses.names.size(); ++i)
    if (poses.names[i] == garment.body.design_pose) m.pose = static_cast<int>(i);
  if (m.pose < 0 || garment.body.design_pose_sha256.empty()) return m;
  m.checked = true;
  m.expected = garment.body.design_pose_sha256;
  m.actual = vertex_checksum(poses.V[static_cast<size_t>(m.pose)]);
  m.same = m.expected == m.actual;
  return m;
}

CarryToBodyResult carry_to_body(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const GarmentFile& garment,
                                const Eigen::MatrixXd& V_from, const Eigen::MatrixXd& V_to,
                                const Eigen::MatrixXi& F_body) {
  CarryToBodyResult result;
  if (V_from.rows() > 0) {
    if (V_from.rows() != V_to.rows())
      throw GeometryError("the design body has " + std::to_string(V_from.rows()) + " vertices, the new body " +
                          std::to_string(V_to.rows()));
    const SurfaceLocator from(V_from, F_body);
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      const SurfacePoint at = from.closest(V.row(v).transpose()).at;
      const Eigen::Vector3d move = evaluate(V_to, F_body, at) - evaluate(V_from, F_body, at);
      V.row(v) += move.transpose();
      result.largest_carry = std::max(result.largest_carry, move.norm());
    }
    result.carried = true;
  }
  const Eigen::MatrixXd N_to = vertex_normals(V_to, F_body);
  std::vector<char> fixed(static_cast<size_t>(V.rows()), 0);
  for (const GarmentLoop& loop : garment.loops) {
    if (loop.binding.empty()) continue;
    for (size_t k = 0; k < loop.vertex_ids.size(); ++k) {
      const int v = loop.vertex_ids[k];
      V.row(v) = evaluate_binding(V_to, N_to, F_body, loop.binding[k], garment.offset).transpose();
      fixed[static_cast<size_t>(v)] = 1;
    }
  }
  BodyClearanceOptions clearance;
  clearance.offset = garment.offset;
  result.clearance = clear_body(V, F, V_to, F_body, fixed, clearance);
  return result;
}

}  // namespace gp
