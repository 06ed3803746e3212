#include "report/picture_sheet.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <thread>

#include "core/error.h"
#include "render/colour_bar.h"

namespace gp::report {
namespace {
const render::View kViews[] = {render::View::front, render::View::side, render::View::back};
const render::Rgb kInk{0.1f, 0.1f, 0.1f};
const render::Rgb kWhite{1.0f, 1.0f, 1.0f};
}  // namespace

std::vector<render::OrthoCamera> frame_views(const Eigen::AlignedBox3d& box, const SheetOptions& options) {
  if (box.isEmpty()) throw GeometryError("nothing to frame: the box is empty");
  // The box fills the views' height (or their widest allowed width): one
  // scale for the three views, the width no larger than the widest view needs.
  std::vector<render::OrthoCamera> cameras;
  std::vector<Eigen::Vector2d> halves;
  double scale = 1e300;
  for (render::View v : kViews) {
    cameras.push_back(render::view_axes(v, options.front));
    halves.push_back(render::projected_half_extents(box, cameras.back()) * (1.0 + options.margin));
    scale = std::min({scale, 0.5 * options.view_width / std::max(halves.back().x(), 1e-6),
                      0.5 * options.view_height / std::max(halves.back().y(), 1e-6)});
  }
  for (size_t v = 0; v < cameras.size(); ++v) {
    render::OrthoCamera& c = cameras[v];
    c.center = box.center();
    c.pixels_per_metre = scale;
    c.width = std::clamp(static_cast<int>(std::ceil(2.0 * halves[v].x() * scale - 1e-9)),
                         std::min(64, options.view_width), options.view_width);
    c.height = options.view_height;
  }
  return cameras;
}

std::vector<Views> render_views(const std::vector<SheetRow>& rows,
                                const std::vector<std::vector<render::OrthoCamera>>& cameras,
                                const SheetOptions& options) {
  if (cameras.size() != rows.size() || rows.empty()) throw UsageError("render_views needs one camera set per row");
  const size_t nc = cameras.front().size(), jobs = rows.size() * nc;
  for (const auto& c : cameras)
    if (c.size() != nc) throw UsageError("every row needs the same number of cameras");
  std::vector<Views> views(rows.size(), Views(nc));
  render::RenderOptions ro;
  ro.supersampling = options.supersampling;
  // Each view is rendered whole by one thread into its own image, so the
  // pixels do not depend on the thread count.
  std::atomic<size_t> next{0};
  std::vector<std::exception_ptr> errors(jobs);
  auto work = [&]() {
    for (size_t j = next++; j < jobs; j = next++) {
      try {
        views[j / nc][j % nc] = render::render(rows[j / nc].layers, cameras[j / nc][j % nc], ro);
      } catch (...) {
        errors[j] = std::current_exception();
      }
    }
  };
  const int threads = std::max(1, std::min(options.threads, static_cast<int>(jobs)));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return views;
}

render::Image compose_sheet(const std::string& title, const std::vector<std::pair<std::string, const Views*>>& rows,
                            const render::ColourScale& scale, const render::Font& font) {
  if (rows.empty() || !rows.front().second || rows.front().second->empty())
    throw UsageError("a picture sheet needs rendered views");
  const int text = 16, gap = 6;
  const int title_h = 2 * text + 8;
  const int row_label_h = rows.size() > 1 ? text + 10 : 0;
  const Views& first = *rows.front().second;
  const int n = static_cast<int>(first.size());
  const int vh = first.front().height;
  // Views side by side, each as wide as it is; every row alike.
  std::vector<int> xs;
  int width = 0;
  for (const render::Image& v : first) {
    xs.push_back(width);
    width += v.width + gap;
  }
  width -= gap;
  // Wide enough for the title and the row labels too.
  width = std::max(width, font.width(title, text + 2) + 8);
  for (const auto& row : rows) width = std::max(width, font.width(row.first, text) + 8);
  const render::Image legend = render::colour_bar(scale, font, std::min(width, 720), 14);
  const int height = title_h + static_cast<int>(rows.size()) * (row_label_h + vh + gap) + legend.height + gap;
  render::Image sheet(width, height, kWhite);
  font.draw(sheet, 4, text + 6, title, text + 2, kInk);
  int y = title_h;
  for (const auto& [label, views] : rows) {
    if (!views || static_cast<int>(views->size()) != n) throw UsageError("every row of a sheet needs the same views");
    for (int c = 0; c < n; ++c)
      if ((*views)[static_cast<size_t>(c)].width != first[static_cast<size_t>(c)].width ||
          (*views)[static_cast<size_t>(c)].height != vh)
        throw UsageError("every row of a sheet needs views of the same sizes");
    if (row_label_h > 0) font.draw(sheet, 4, y + text, label, text, kInk);
    y += row_label_h;
    for (int c = 0; c < n; ++c) {
      const int x = xs[static_cast<size_t>(c)];
      render::paste(sheet, (*views)[static_cast<size_t>(c)], x, y);
      font.draw(sheet, x + 6, y + text + 2, render::view_name(kViews[c % 3]), text - 2, kInk);
    }
    y += vh + gap;
  }
  render::paste(sheet, legend, (width - legend.width) / 2, y);
  return sheet;
}

render::Image picture_sheet(const std::string& title, const std::vector<SheetRow>& rows,
                            const std::vector<render::OrthoCamera>& cameras, const render::ColourScale& scale,
                            const render::Font& font, const SheetOptions& options) {
  const std::vector<Views> views =
      render_views(rows, std::vector<std::vector<render::OrthoCamera>>(rows.size(), cameras), options);
  std::vector<std::pair<std::string, const Views*>> labelled;
  for (size_t r = 0; r < rows.size(); ++r) labelled.emplace_back(rows[r].label, &views[r]);
  return compose_sheet(title, labelled, scale, font);
}

}  // namespace gp::report
