#pragma once
// A picture sheet of the fit report: a title, one or more rows of the front,
// side and back views (each row a labelled scene, e.g. "adapted" and "as
// designed"), and the legend of the colour scale, all views at one scale.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "render/colour_scale.h"
#include "render/rasterizer.h"
#include "render/text.h"
#include "render/views.h"
#include "spec/option_fields.h"

namespace gp::report {

struct SheetOptions {
  int view_width = 720;          // widest view [pixels]; each view is as wide as the framed box needs
  int view_height = 600;         // height of every view [pixels]
  int supersampling = 3;         // samples per pixel along each axis
  Eigen::Vector3d front = Eigen::Vector3d::UnitZ();  // the body's front direction (+y is up)
  double margin = 0.06;          // space around the framed box, fraction of its size
  int threads = 1;               // views rendered in parallel (same pixels for any count)
};

// The options that decide the pictures, as a report records them
// (spec/option_fields.h). The front direction and the thread count are not
// among them: the tool records the one as its axis name, and the other does
// not change a pixel.
struct SheetOptionFields {
  template <class Fields>
  void operator()(SheetOptions& o, Fields& f) const {
    f.integer("view_width_px", o.view_width, Range::between(64, 4096));
    f.integer("view_height_px", o.view_height, Range::between(64, 4096));
    f.integer("supersampling", o.supersampling, Range::between(1, 8));
    f.number("margin", o.margin, Range::non_negative());
  }
};

// Cameras for the front, side and back views that show `box` whole, centred,
// at the one scale (pixels per metre) at which it fits every view: the box
// fills the view height unless a view would be wider than view_width; each
// view is as wide as the box needs in it.
std::vector<render::OrthoCamera> frame_views(const Eigen::AlignedBox3d& box, const SheetOptions& options);

struct SheetRow {
  std::string label;                        // e.g. "adapted"
  std::vector<render::MeshLayer> layers;    // what to draw (pointers must outlive the call)
};

// The views of a scene, one per camera.
using Views = std::vector<render::Image>;

// Renders row r in each of cameras[r], spread over options.threads threads:
// one Views per row.
std::vector<Views> render_views(const std::vector<SheetRow>& rows,
                                const std::vector<std::vector<render::OrthoCamera>>& cameras,
                                const SheetOptions& options);

// The sheet: title, rows of already rendered views (front, side, back) each
// under its label, and the legend of `scale`.
render::Image compose_sheet(const std::string& title, const std::vector<std::pair<std::string, const Views*>>& rows,
                            const render::ColourScale& scale, const render::Font& font);

// render_views() and compose_sheet() in one.
render::Image picture_sheet(const std::string& title, const std::vector<SheetRow>& rows,
                            const std::vector<render::OrthoCamera>& cameras, const render::ColourScale& scale,
                            const render::Font& font, const SheetOptions& options);

}  // namespace gp::report
