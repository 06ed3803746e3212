#pragma once
// One fuzz input for the mesh readers: the first byte picks the format (.ply,
// .obj or .stl) and polygon splitting, the rest is the file. The input must
// either read, with every face index in range, or throw a gp::Error; anything
// else (a crash, another exception, an out-of-range index) is a bug. Shared by
// the libFuzzer target and the unit test that replays testdata/fuzz/read_mesh.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/error.h"
#include "io/mesh_io.h"

namespace gp::fuzz {

// Returns false when the reader returned a mesh with a face index out of range.
inline bool read_mesh_once(const uint8_t* data, size_t size) {
  if (size == 0) return true;
  static const char* const extensions[] = {".ply", ".obj", ".stl"};
  const char* ext = extensions[data[0] % 3];
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("gp_fuzz_mesh_" + std::to_string(::getpid()) + ext);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  MeshReadOptions options;
  options.triangulate = (data[0] & 4) != 0;
  bool ok = true;
  try {
    const Mesh mesh = read_mesh(path, options).mesh;
    for (Eigen::Index i = 0; i < mesh.F.size(); ++i)
      if (mesh.F.data()[i] < 0 || mesh.F.data()[i] >= mesh.V.rows()) ok = false;
  } catch (const Error&) {
  }
  std::error_code ignored;
  std::filesystem::remove(path, ignored);
  return ok;
}

}  // namespace gp::fuzz
