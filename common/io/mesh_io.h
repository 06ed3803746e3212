#pragma once
// Reading and writing meshes.
//
// OBJ and PLY (ASCII and binary, either byte order) are read by the project's
// own parsers, which keep the file's vertex order exactly and never merge or
// duplicate vertices: registered poses rely on vertex i being the same body
// point in every file. Every other format is read through assimp, which may
// merge or reorder vertices; the result then carries a warning saying so.
//
// Writers produce binary little-endian PLY (with optional per-vertex and
// per-face scalar fields) or OBJ (geometry only), always through a temporary
// file renamed into place.
#include <filesystem>
#include <string>
#include <vector>

#include "io/mesh.h"

namespace gp {

struct MeshReadOptions {
  // Split faces with more than three corners into triangles (fan from the first
  // corner) and warn. When false such faces are a GeometryError.
  bool triangulate = false;
};

struct MeshReadResult {
  Mesh mesh;
  std::string format;                 // "ply-ascii", "ply-binary-le", "obj", "assimp:<ext>", ...
  bool vertex_order_preserved = true;  // false for formats read through assimp
  std::vector<std::string> warnings;  // things the caller should tell the user
};

// Reads a mesh; the format is chosen by the file extension (case-insensitive).
// Throws InputError (missing, unreadable, malformed or truncated file, face
// index out of range) or GeometryError (polygons without `triangulate`,
// faces with fewer than three corners). Non-finite coordinates are read as they
// are: checking them is the caller's decision (see mesh/validate.h).
MeshReadResult read_mesh(const std::filesystem::path& path, const MeshReadOptions& options = {});

struct MeshWriteOptions {
  // Vertex positions as 64-bit doubles (exact round trip) or 32-bit floats.
  bool double_precision = true;
};

// Writes `mesh` as binary PLY (".ply") or OBJ (".obj"), chosen by extension.
// OBJ has no place for scalar fields; they are written only to PLY.
// Throws OutputError on failure, leaving any existing file untouched.
void write_mesh(const std::filesystem::path& path, const Mesh& mesh,
                const MeshWriteOptions& options = {});

// Format-specific entry points (read_mesh/write_mesh dispatch to these).
MeshReadResult read_ply(const std::filesystem::path& path, const MeshReadOptions& options);
MeshReadResult read_obj(const std::filesystem::path& path, const MeshReadOptions& options);
MeshReadResult read_with_assimp(const std::filesystem::path& path, const MeshReadOptions& options);
void write_ply(const std::filesystem::path& path, const Mesh& mesh, const MeshWriteOptions& options);
void write_obj(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace gp
