#pragma once
// Fixed colour scales for the fit pictures, so that every render of every
// customer reads the same way: the largest principal stretch on 1.0 to 1.3
// (cool up to the adaptation's limit 1 + delta, warm above it), and the area
// growth of the rest shape against the design on 0.5 to 2 (log axis, white at
// 1). Values beyond a scale's ends take the end colour.
#include <string>
#include <vector>

#include "render/image.h"

namespace gp::render {

struct ColourStop {
  double value = 0.0;  // on the scale's axis (log2 of the value for a log scale)
  Rgb colour;
};

struct ScaleTick {
  double value = 0.0;  // the value itself (not its log)
  std::string label;
  bool marked = false;  // drawn heavier: the limit 1 + delta
};

class ColourScale {
 public:
  // `stops` in increasing order of value (at least two); `log_axis`: values
  // are placed by their base-2 logarithm. Throws UsageError otherwise.
  ColourScale(std::string title, std::vector<ColourStop> stops, std::vector<ScaleTick> ticks, bool log_axis);
  Rgb colour(double value) const;  // NaN gives the first stop's colour
  // Position of `value` on the bar, 0 at the low end, 1 at the high end (clamped).
  double position(double value) const;
  // The value at `position` in [0, 1] (the inverse of position()).
  double value_at(double position) const;
  double min_value() const;
  double max_value() const;
  bool log_axis() const { return log_axis_; }
  const std::string& title() const { return title_; }
  const std::vector<ScaleTick>& ticks() const { return ticks_; }

 private:
  double axis(double value) const;
  std::string title_;
  std::vector<ColourStop> stops_;
  std::vector<ScaleTick> ticks_;
  bool log_axis_;
};

// Largest principal stretch from 1.0 to 1.3 with the colour change at
// 1 + delta (delta in (0, 0.3)); ticks every 0.05 and the limit marked.
ColourScale stretch_scale(double delta);

// Rest-shape face area over the design's, 0.5 to 2, log axis, white at 1.
ColourScale growth_scale();

// The neutral grey of the body in every picture.
Rgb body_colour();

}  // namespace gp::render
