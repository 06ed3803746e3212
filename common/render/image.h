#pragma once
// An 8-bit RGB raster image, row-major from the top-left corner, and the few
// drawing operations the renders and legends need.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gp::render {

// A colour with components in [0, 1] (sRGB-encoded, as stored).
struct Rgb {
  float r = 0.0f, g = 0.0f, b = 0.0f;
};

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3 bytes, RGB, rows top to bottom

  Image() = default;
  // A width by height image filled with `fill`.
  Image(int width, int height, Rgb fill);
  std::uint8_t* at(int x, int y) { return &pixels[3 * (static_cast<std::size_t>(y) * width + x)]; }
  const std::uint8_t* at(int x, int y) const { return &pixels[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

// 8-bit value of a component in [0, 1] (clamped, rounded to nearest).
std::uint8_t to_byte(float c);

// Fills the rectangle [x, x+w) x [y, y+h), clipped to the image.
void fill_rect(Image& image, int x, int y, int w, int h, Rgb colour);

// Draws a ring of centre (cx, cy), radius `radius` and line width `width`
// [pixels] over the image, clipped: a pixel is coloured where its centre lies
// within width / 2 of the circle. Marks a place on a render.
void draw_ring(Image& image, double cx, double cy, double radius, double width, Rgb colour);

// Copies `src` into `dst` with its top-left corner at (x, y), clipped.
void paste(Image& dst, const Image& src, int x, int y);

// Averages blocks of factor by factor pixels (box filter): a (w/factor) by
// (h/factor) image. Used to resolve supersampled renders.
Image downsample(const Image& image, int factor);

}  // namespace gp::render
