#include "render/image.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace gp::render {

Image::Image(int w, int h, Rgb fill) : width(w), height(h) {
  if (w < 0 || h < 0) throw UsageError("image size must be non-negative");
  const std::uint8_t c[3] = {to_byte(fill.r), to_byte(fill.g), to_byte(fill.b)};
  if (c[0] == c[1] && c[1] == c[2]) {
    pixels.assign(3 * static_cast<size_t>(w) * static_cast<size_t>(h), c[0]);
    return;
  }
  pixels.resize(3 * static_cast<size_t>(w) * static_cast<size_t>(h));
  for (size_t i = 0; i < pixels.size(); i += 3) std::copy(c, c + 3, &pixels[i]);
}

std::uint8_t to_byte(float c) {
  if (!(c > 0.0f)) return 0;  // also NaN
  if (c >= 1.0f) return 255;
  return static_cast<std::uint8_t>(c * 255.0f + 0.5f);  // round half up
}

void fill_rect(Image& image, int x, int y, int w, int h, Rgb colour) {
  const std::uint8_t c[3] = {to_byte(colour.r), to_byte(colour.g), to_byte(colour.b)};
  const int x0 = std::max(0, x), x1 = std::min(image.width, x + w);
  const int y0 = std::max(0, y), y1 = std::min(image.height, y + h);
  for (int yy = y0; yy < y1; ++yy)
    for (int xx = x0; xx < x1; ++xx) std::copy(c, c + 3, image.at(xx, yy));
}

void draw_ring(Image& image, double cx, double cy, double radius, double width, Rgb colour) {
  const std::uint8_t c[3] = {to_byte(colour.r), to_byte(colour.g), to_byte(colour.b)};
  const double outer = radius + 0.5 * width, inner = std::max(0.0, radius - 0.5 * width);
  const int x0 = std::max(0, static_cast<int>(std::floor(cx - outer)));
  const int x1 = std::min(image.width - 1, static_cast<int>(std::ceil(cx + outer)));
  const int y0 = std::max(0, static_cast<int>(std::floor(cy - outer)));
  const int y1 = std::min(image.height - 1, static_cast<int>(std::ceil(cy + outer)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double r = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      if (r >= inner && r <= outer) std::copy(c, c + 3, image.at(x, y));
    }
}

void paste(Image& dst, const Image& src, int x, int y) {
  const int x0 = std::max(0, x), x1 = std::min(dst.width, x + src.width);
  const int y0 = std::max(0, y), y1 = std::min(dst.height, y + src.height);
  if (x0 >= x1) return;
  for (int yy = y0; yy < y1; ++yy) std::copy(src.at(x0 - x, yy - y), src.at(x0 - x, yy - y) + 3 * (x1 - x0), dst.at(x0, yy));
}

Image downsample(const Image& image, int factor) {
  if (factor < 1) throw UsageError("downsampling factor must be at least 1");
  if (factor == 1) return image;
  Image out(image.width / factor, image.height / factor, Rgb{});
  const int n = factor * factor;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      int sum[3] = {0, 0, 0};
      for (int dy = 0; dy < factor; ++dy) {
        const std::uint8_t* p = image.at(x * factor, y * factor + dy);
        for (int dx = 0; dx < factor; ++dx, p += 3) {
          sum[0] += p[0];
          sum[1] += p[1];
          sum[2] += p[2];
        }
      }
      std::uint8_t* q = out.at(x, y);
      for (int c = 0; c < 3; ++c) q[c] = static_cast<std::uint8_t>((sum[c] + n / 2) / n);
    }
  return out;
}

}  // namespace gp::render
