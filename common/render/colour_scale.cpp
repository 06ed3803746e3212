#include "render/colour_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/error.h"

namespace gp::render {

ColourScale::ColourScale(std::string title, std::vector<ColourStop> stops, std::vector<ScaleTick> ticks,
                         bool log_axis)
    : title_(std::move(title)), stops_(std::move(stops)), ticks_(std::move(ticks)), log_axis_(log_axis) {
  if (stops_.size() < 2) throw UsageError("a colour scale needs at least two stops", title_);
  for (size_t i = 1; i < stops_.size(); ++i)
    if (!(stops_[i].value > stops_[i - 1].value)) throw UsageError("colour stops must increase", title_);
}

double ColourScale::axis(double value) const { return log_axis_ ? std::log2(value) : value; }

double ColourScale::min_value() const { return log_axis_ ? std::exp2(stops_.front().value) : stops_.front().value; }
double ColourScale::max_value() const { return log_axis_ ? std::exp2(stops_.back().value) : stops_.back().value; }

double ColourScale::position(double value) const {
  const double a = axis(value), lo = stops_.front().value, hi = stops_.back().value;
  if (!(a > lo)) return 0.0;
  if (a >= hi) return 1.0;
  return (a - lo) / (hi - lo);
}

double ColourScale::value_at(double position) const {
  const double a = stops_.front().value + position * (stops_.back().value - stops_.front().value);
  return log_axis_ ? std::exp2(a) : a;
}

Rgb ColourScale::colour(double value) const {
  const double a = axis(value);
  if (!(a > stops_.front().value)) return stops_.front().colour;
  if (a >= stops_.back().value) return stops_.back().colour;
  size_t i = 1;
  while (stops_[i].value < a) ++i;
  const ColourStop& p = stops_[i - 1];
  const ColourStop& q = stops_[i];
  const float t = static_cast<float>((a - p.value) / (q.value - p.value));
  return {p.colour.r + t * (q.colour.r - p.colour.r), p.colour.g + t * (q.colour.g - p.colour.g),
          p.colour.b + t * (q.colour.b - p.colour.b)};
}

ColourScale stretch_scale(double delta) {
  if (!(delta > 0.0 && delta < 0.3)) throw UsageError("the stretch scale needs 0 < delta < 0.3", "delta");
  const double limit = 1.0 + delta, top = 1.3;
  // Cool and pale up to the limit, then orange, red and dark red: what is
  // over the limit stands out whatever the limit is.
  std::vector<ColourStop> stops = {{1.0, {0.19f, 0.33f, 0.68f}},
                                   {1.0 + 0.5 * delta, {0.45f, 0.67f, 0.86f}},
                                   {limit, {0.93f, 0.93f, 0.80f}},
                                   {limit + 0.25 * (top - limit), {0.99f, 0.64f, 0.28f}},
                                   {limit + 0.5 * (top - limit), {0.86f, 0.22f, 0.14f}},
                                   {top, {0.42f, 0.0f, 0.10f}}};
  std::vector<ScaleTick> ticks;
  for (int i = 0; i <= 6; ++i) {
    const double v = 1.0 + 0.05 * i;
    if (std::abs(v - limit) < 0.02) continue;  // the limit's own tick stands there
    char label[16];
    std::snprintf(label, sizeof(label), "%.2f", v);
    ticks.push_back({v, label, false});
  }
  char label[32];
  std::snprintf(label, sizeof(label), "1+\xce\xb4 = %.2f", limit);  // UTF-8 delta
  ticks.push_back({limit, label, true});
  std::sort(ticks.begin(), ticks.end(), [](const ScaleTick& a, const ScaleTick& b) { return a.value < b.value; });
  return ColourScale("largest principal stretch", std::move(stops), std::move(ticks), false);
}

ColourScale growth_scale() {
  std::vector<ColourStop> stops = {{-1.0, {0.19f, 0.33f, 0.68f}},
                                   {-0.5, {0.58f, 0.74f, 0.89f}},
                                   {0.0, {0.95f, 0.95f, 0.93f}},
                                   {0.5, {0.97f, 0.61f, 0.43f}},
                                   {1.0, {0.70f, 0.06f, 0.12f}}};
  std::vector<ScaleTick> ticks = {
      {0.5, "0.5", false}, {0.75, "0.75", false}, {1.0, "1", true}, {1.5, "1.5", false}, {2.0, "2", false}};
  return ColourScale("rest area / design area, per face", std::move(stops), std::move(ticks), true);
}

Rgb body_colour() { return {0.70f, 0.70f, 0.70f}; }

}  // namespace gp::render
