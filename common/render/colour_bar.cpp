#include "render/colour_bar.h"

#include <algorithm>
#include <cmath>

namespace gp::render {

Image colour_bar(const ColourScale& scale, const Font& font, int width, int pixel_size) {
  const Rgb ink{0.1f, 0.1f, 0.1f};
  const int pad = pixel_size;
  const int bar_h = pixel_size + 4;
  const int title_h = pixel_size * 3 / 2;
  const int height = title_h + bar_h + pixel_size * 2 + 4;
  Image image(width, height, Rgb{1.0f, 1.0f, 1.0f});
  font.draw(image, pad, pixel_size, scale.title(), pixel_size, ink);
  // Labels may stand out past the bar's ends by half their width.
  int margin = pad;
  for (const ScaleTick& t : scale.ticks()) margin = std::max(margin, font.width(t.label, pixel_size) / 2 + 2);
  const int x0 = margin, x1 = width - margin, y0 = title_h;
  for (int x = x0; x < x1; ++x) {
    fill_rect(image, x, y0, 1, bar_h, scale.colour(scale.value_at((x + 0.5 - x0) / (x1 - x0))));
  }
  for (const ScaleTick& t : scale.ticks()) {
    const int x = x0 + static_cast<int>(std::lround(scale.position(t.value) * (x1 - x0)));
    if (t.marked) {
      fill_rect(image, x - 1, y0 - 3, 3, bar_h + 9, ink);
    } else {
      fill_rect(image, x, y0 + bar_h, 1, 5, ink);
    }
    const int w = font.width(t.label, pixel_size);
    font.draw(image, x - w / 2, y0 + bar_h + 6 + pixel_size, t.label, pixel_size, ink);
  }
  return image;
}

}  // namespace gp::render
