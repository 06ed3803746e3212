#pragma once
// A PNG picture of an SVG file, drawn by rsvg-convert (Debian's librsvg2-bin)
// at a given width, on white.
#include <filesystem>

namespace gp::report {

// Runs `rsvg-convert` (found on PATH) and writes `png`. Throws InputError if
// the program is missing, OutputError if it fails.
void svg_to_png(const std::filesystem::path& svg, const std::filesystem::path& png, int width_px);

}  // namespace gp::report
