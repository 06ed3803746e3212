#pragma once
// The legend of a colour scale: a horizontal bar with its title above and
// labelled ticks below; the marked tick (the limit) is drawn across the bar.
#include "render/colour_scale.h"
#include "render/image.h"
#include "render/text.h"

namespace gp::render {

// A `width` pixels wide legend on a white background; its height follows from
// the text size (`pixel_size`, pixels per em).
Image colour_bar(const ColourScale& scale, const Font& font, int width, int pixel_size = 14);

}  // namespace gp::render
