#include "garment/design_body.h"

#include "core/error.h"
#include "io/mesh_io.h"
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

}  // namespace gp
