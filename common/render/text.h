#pragma once
// Text on images (labels of views and legends), rasterized by FreeType from a
// TrueType font with anti-aliasing; the same font file gives the same pixels.
#include <filesystem>
#include <memory>
#include <string>

#include "render/image.h"

namespace gp::render {

// DejaVu Sans from Debian's fonts-dejavu-core. Throws InputError naming the
// path if it is not installed.
std::filesystem::path default_font_path();

class Font {
 public:
  // Throws InputError if the file cannot be read as a font.
  explicit Font(const std::filesystem::path& path);
  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  // Draws UTF-8 `text` with its baseline at y, starting at x, `pixel_size`
  // pixels per em, blended over the image. Characters the font lacks are skipped.
  void draw(Image& image, int x, int baseline, const std::string& text, int pixel_size, Rgb colour) const;
  // Advance width of `text` in pixels.
  int width(const std::string& text, int pixel_size) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gp::render
