// Every format besides OBJ and PLY is read through assimp. assimp builds its
// own vertex arrays (joining identical vertices, splitting by material), so the
// file's vertex order is not kept; the result says so.
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/error.h"
#include "io/face_builder.h"
#include "io/mesh_io.h"

namespace gp {

MeshReadResult read_with_assimp(const std::filesystem::path& path, const MeshReadOptions& options) {
  const std::string file = path.string();
  Assimp::Importer importer;
  // Points and lines carry no surface: drop them instead of failing.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // Only positions matter here. Dropping normals, texture coordinates and
  // colours first lets JoinIdenticalVertices weld corners that differ only in
  // those (an STL file repeats every corner with its facet's normal).
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                  aiComponent_COLORS | aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS |
                                  aiComponent_ANIMATIONS | aiComponent_TEXTURES | aiComponent_LIGHTS |
                                  aiComponent_CAMERAS | aiComponent_MATERIALS);
  const unsigned flags = aiProcess_RemoveComponent | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(file, flags);
  if (!scene || !scene->mRootNode)
    throw InputError(std::string("cannot read mesh: ") + importer.GetErrorString(), file);

  MeshReadResult result;
  std::string ext = path.extension().string();
  result.format = "assimp:" + (ext.empty() ? std::string("?") : ext.substr(1));
  result.vertex_order_preserved = false;

  FaceBuilder faces(file, options.triangulate);
  std::vector<double> coords;
  long long face_index = 0;
  std::vector<long long> corners;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) continue;
    const long long base = static_cast<long long>(coords.size() / 3);
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      coords.push_back(mesh->mVertices[i].x);
      coords.push_back(mesh->mVertices[i].y);
      coords.push_back(mesh->mVertices[i].z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      corners.assign(face.mIndices, face.mIndices + face.mNumIndices);
      for (auto& c : corners) c += base;
      faces.add(corners, face_index++);
    }
  }
  const long long nv = static_cast<long long>(coords.size() / 3);
  if (nv == 0) throw InputError("file holds no triangle mesh", file);
  result.mesh.V.resize(nv, 3);
  for (long long i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) result.mesh.V(i, k) = coords[3 * i + k];
  result.mesh.F = faces.finish(nv, result.warnings);
  result.warnings.push_back(file + ": read through assimp; the " + result.format.substr(7) +
                            " format does not promise the vertex order (vertices may be merged or "
                            "reordered), so it cannot stand for a registered pose");
  if (scene->mNumMeshes > 1)
    result.warnings.push_back(file + ": merged " + std::to_string(scene->mNumMeshes) +
                              " meshes of the scene into one");
  return result;
}

}  // namespace gp
