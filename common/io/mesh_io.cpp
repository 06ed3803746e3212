#include "io/mesh_io.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"

namespace gp {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

MeshReadResult read_mesh(const std::filesystem::path& path, const MeshReadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError("no such file", path.string());
  if (std::filesystem::is_directory(path, ec)) throw InputError("is a folder, not a mesh file", path.string());
  if (std::filesystem::file_size(path, ec) == 0 && !ec) throw InputError("empty file", path.string());
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return read_ply(path, options);
  if (ext == ".obj") return read_obj(path, options);
  return read_with_assimp(path, options);
}

void write_mesh(const std::filesystem::path& path, const Mesh& mesh, const MeshWriteOptions& options) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return write_ply(path, mesh, options);
  if (ext == ".obj") return write_obj(path, mesh);
  throw OutputError("unsupported output format '" + ext + "' (use .ply or .obj)", path.string());
}

}  // namespace gp
