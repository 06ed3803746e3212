#pragma once
// Binary glTF 2.0 (.glb) files of triangle meshes, for viewers and tools:
// one named node and mesh per input mesh, positions, optional normals,
// vertex colours (COLOR_0) and application-specific float attributes named
// "_<NAME>" (glTF 2.0 spec, section 3.7.2.1: attribute semantics starting
// with an underscore). The file is built in memory in a fixed order, so the
// same meshes give the same bytes.
//
// assimp's glTF 2 exporter is not used: an aiMesh has no named per-vertex
// scalar channel, so "_MAX_STRETCH" cannot be expressed through it.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gp {

struct GltfAttribute {
  std::string name;        // written as "_" + name, e.g. "MAX_STRETCH" -> "_MAX_STRETCH"
  Eigen::VectorXf values;  // #V
};

struct GltfMesh {
  std::string name;                 // node and mesh name
  Eigen::MatrixXd V;                // #V by 3 [m]
  Eigen::MatrixXi F;                // #F by 3
  Eigen::MatrixXd N;                // #V by 3 unit normals, or empty (viewers then shade flat)
  Eigen::MatrixXf colours;          // #V by 3 sRGB-encoded in [0, 1] (written linear, as glTF wants), or empty
  std::vector<GltfAttribute> attributes;
  float base_colour[3] = {1.0f, 1.0f, 1.0f};  // material base colour, sRGB-encoded
  float roughness = 0.9f;
  bool double_sided = true;
};

// The .glb bytes. Throws UsageError for sizes that do not match, an index out
// of range, non-finite positions or a name that is not a valid attribute name
// ([A-Z0-9_]).
std::vector<std::uint8_t> glb_bytes(const std::vector<GltfMesh>& meshes, const std::string& generator);

// Writes glb_bytes() to `path` atomically. Throws OutputError.
void write_glb(const std::filesystem::path& path, const std::vector<GltfMesh>& meshes, const std::string& generator);

}  // namespace gp
