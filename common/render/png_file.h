#pragma once
// PNG files through libpng: 8-bit RGB, no time stamp or other run-dependent
// chunk, fixed compression settings, so that the same image gives the same
// bytes.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/image.h"

namespace gp::render {

// The PNG encoding of `image`. Throws OutputError if libpng fails.
std::vector<std::uint8_t> encode_png(const Image& image);

// Writes `image` as a PNG file, atomically (core/atomic_file.h). Throws
// OutputError.
void write_png(const std::filesystem::path& path, const Image& image);

// Reads a PNG file as 8-bit RGB (palette, grey and 16-bit images are
// converted, alpha is composited on white). Throws InputError naming the file.
Image read_png(const std::filesystem::path& path);

}  // namespace gp::render
