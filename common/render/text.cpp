#include "render/text.h"

#include <algorithm>
#include <cstdint>
#include <vector>

#include <ft2build.h>
#include FT_FREETYPE_H

#include "core/error.h"

namespace gp::render {
namespace {

// Code points of a UTF-8 string; malformed bytes are skipped.
std::vector<char32_t> decode_utf8(const std::string& s) {
  std::vector<char32_t> out;
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 0 : (c >> 5) == 0x6 ? 1 : (c >> 4) == 0xE ? 2 : (c >> 3) == 0x1E ? 3 : -1;
    if (n < 0 || i + static_cast<size_t>(n) >= s.size()) {
      ++i;
      continue;
    }
    char32_t cp = n == 0 ? c : c & (0x3F >> n);
    bool ok = true;
    for (int k = 1; k <= n; ++k) {
      const auto d = static_cast<unsigned char>(s[i + static_cast<size_t>(k)]);
      if ((d >> 6) != 0x2) ok = false;
      cp = (cp << 6) | (d & 0x3F);
    }
    i += static_cast<size_t>(n) + 1;
    if (ok) out.push_back(cp);
  }
  return out;
}

}  // namespace

std::filesystem::path default_font_path() {
  const std::filesystem::path path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  if (!std::filesystem::exists(path))
    throw InputError("font not found; install Debian's fonts-dejavu-core (make deps)", path.string());
  return path;
}

struct Font::Impl {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
};

Font::Font(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
  if (FT_Init_FreeType(&impl_->library) != 0) throw InputError("FreeType cannot start", path.string());
  if (FT_New_Face(impl_->library, path.c_str(), 0, &impl_->face) != 0) {
    FT_Done_FreeType(impl_->library);
    throw InputError("cannot read the font", path.string());
  }
}

Font::~Font() {
  FT_Done_Face(impl_->face);
  FT_Done_FreeType(impl_->library);
}

void Font::draw(Image& image, int x, int baseline, const std::string& text, int pixel_size, Rgb colour) const {
  FT_Face face = impl_->face;
  FT_Set_Pixel_Sizes(face, 0, static_cast<FT_UInt>(pixel_size));
  const float rgb[3] = {colour.r * 255.0f, colour.g * 255.0f, colour.b * 255.0f};
  int pen = x;
  for (char32_t cp : decode_utf8(text)) {
    if (FT_Load_Char(face, cp, FT_LOAD_RENDER) != 0) continue;
    const FT_GlyphSlot g = face->glyph;
    const FT_Bitmap& bm = g->bitmap;
    for (unsigned row = 0; row < bm.rows; ++row) {
      const int y = baseline - g->bitmap_top + static_cast<int>(row);
      if (y < 0 || y >= image.height) continue;
      for (unsigned col = 0; col < bm.width; ++col) {
        const int px = pen + g->bitmap_left + static_cast<int>(col);
        if (px < 0 || px >= image.width) continue;
        const float a = bm.buffer[row * static_cast<unsigned>(std::abs(bm.pitch)) + col] / 255.0f;
        if (a <= 0.0f) continue;
        std::uint8_t* p = image.at(px, y);
        for (int c = 0; c < 3; ++c) p[c] = to_byte((p[c] + a * (rgb[c] - p[c])) / 255.0f);
      }
    }
    pen += static_cast<int>(g->advance.x >> 6);
  }
}

int Font::width(const std::string& text, int pixel_size) const {
  FT_Face face = impl_->face;
  FT_Set_Pixel_Sizes(face, 0, static_cast<FT_UInt>(pixel_size));
  int w = 0;
  for (char32_t cp : decode_utf8(text))
    if (FT_Load_Char(face, cp, FT_LOAD_DEFAULT) == 0) w += static_cast<int>(face->glyph->advance.x >> 6);
  return w;
}

}  // namespace gp::render
