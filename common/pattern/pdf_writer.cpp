#include "pattern/pdf_writer.h"

#include <cairo-pdf.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/text_format.h"

namespace gp {
namespace {

constexpr double kPointsPerMetre = 72.0 / 0.0254;

// A page's window on the sheet (metres, sheet frame: y up).
struct Window {
  double x0 = 0.0, y_top = 0.0, width = 0.0, height = 0.0;
};

// Whether the polygon reaches into the window: a vertex inside it, an edge
// across it, or the window inside the polygon.
bool polygon_meets_window(const Polygon2& poly, const Window& w) {
  const double x1 = w.x0 + w.width, y0 = w.y_top - w.height;
  auto inside = [&](const Eigen::Vector2d& p) { return p.x() >= w.x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= w.y_top; };
  for (const auto& p : poly)
    if (inside(p)) return true;
  // An edge crossing one of the window's four sides.
  auto crosses = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
    auto orient = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
      return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
    };
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    return ((o1 > 0) != (o2 > 0)) && ((o3 > 0) != (o4 > 0));
  };
  const Eigen::Vector2d corners[4] = {{w.x0, y0}, {x1, y0}, {x1, w.y_top}, {w.x0, w.y_top}};
  for (size_t i = 0; i < poly.size(); ++i)
    for (int k = 0; k < 4; ++k)
      if (crosses(poly[i], poly[(i + 1) % poly.size()], corners[k], corners[(k + 1) % 4])) return true;
  // The window inside the polygon (even-odd rule at a corner).
  bool in = false;
  const Eigen::Vector2d& q = corners[0];
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i].y() > q.y()) != (poly[j].y() > q.y()) &&
        q.x() < (poly[j].x() - poly[i].x()) * (q.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) + poly[i].x())
      in = !in;
  return in;
}

std::string row_name(int r) {
  std::string s;
  for (int k = r;; k = k / 26 - 1) {
    s.insert(s.begin(), static_cast<char>('A' + k % 26));
    if (k < 26) break;
  }
  return s;
}

struct Tiling {
  PdfSummary summary;
  double page_w = 0.0, page_h = 0.0;  // paper, metres, as printed (portrait or landscape)
  double step_x = 0.0, step_y = 0.0;
  std::vector<Window> windows;        // per tile
};

Tiling make_tiling(const Layout& layout, const PdfOptions& o, bool landscape) {
  Tiling t;
  t.page_w = landscape ? o.paper.height : o.paper.width;
  t.page_h = landscape ? o.paper.width : o.paper.height;
  const double pw = t.page_w - 2.0 * o.margin, ph = t.page_h - 2.0 * o.margin;
  if (!(pw > o.overlap && ph > o.overlap))
    throw UsageError("the paper " + o.paper.name + " leaves no room inside its margins", "--paper");
  t.step_x = pw - o.overlap;
  t.step_y = ph - o.overlap;
  PdfSummary& s = t.summary;
  s.columns = std::max(1, static_cast<int>(std::ceil((layout.width - o.overlap) / t.step_x - 1e-9)));
  s.rows = std::max(1, static_cast<int>(std::ceil((layout.height - o.overlap) / t.step_y - 1e-9)));
  for (int r = 0; r < s.rows; ++r)
    for (int c = 0; c < s.columns; ++c) {
      Window w{c * t.step_x, layout.height - r * t.step_y, pw, ph};
      PdfPage page{r, c, row_name(r) + std::to_string(c + 1), false};
      for (const LaidOutPiece& lp : layout.pieces) {
        if (polygon_meets_window(lp.outline, w)) page.printed = true;
        for (const Polygon2& poly : lp.allowance)
          if (polygon_meets_window(poly, w)) page.printed = true;
      }
      s.tiles.push_back(page);
      t.windows.push_back(w);
    }
  s.pages = 1;
  for (const PdfPage& p : s.tiles) s.pages += p.printed ? 1 : 0;
  return t;
}

Tiling best_tiling(const Layout& layout, const PdfOptions& o) {
  // The orientation that prints fewer pages (portrait on a tie).
  const Tiling portrait = make_tiling(layout, o, false);
  const Tiling landscape = make_tiling(layout, o, true);
  return landscape.summary.pages < portrait.summary.pages ? landscape : portrait;
}

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ostream*>(closure);
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return out->good() ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

// Drawing in page metres (x right, y down from the paper's top left corner).
class Painter {
 public:
  explicit Painter(cairo_t* cr) : cr_(cr) {}
  void begin_page() {
    cairo_identity_matrix(cr_);
    cairo_scale(cr_, kPointsPerMetre, kPointsPerMetre);
    cairo_select_font_face(cr_, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  }
  void width(double w) { cairo_set_line_width(cr_, w); }
  void grey(double g) { cairo_set_source_rgb(cr_, g, g, g); }
  void dash(double on, double off) {
    const double d[2] = {on, off};
    cairo_set_dash(cr_, d, 2, 0.0);
  }
  void solid() { cairo_set_dash(cr_, nullptr, 0, 0.0); }
  void line(double x0, double y0, double x1, double y1) {
    cairo_move_to(cr_, x0, y0);
    cairo_line_to(cr_, x1, y1);
    cairo_stroke(cr_);
  }
  void rect(double x, double y, double w, double h, bool fill) {
    cairo_rectangle(cr_, x, y, w, h);
    fill ? cairo_fill(cr_) : cairo_stroke(cr_);
  }
  void circle(double x, double y, double r) {
    cairo_new_sub_path(cr_);
    cairo_arc(cr_, x, y, r, 0.0, 2.0 * M_PI);
    cairo_stroke(cr_);
  }
  // Text with its baseline's centre (align 0.5), start (0) or end (1) at (x, y).
  void text(double x, double y, double size, const std::string& s, double align = 0.5) {
    cairo_set_font_size(cr_, size);
    cairo_text_extents_t e;
    cairo_text_extents(cr_, s.c_str(), &e);
    cairo_move_to(cr_, x - align * e.x_advance, y);
    cairo_show_text(cr_, s.c_str());
  }
  void clip(double x, double y, double w, double h) {
    cairo_save(cr_);
    cairo_rectangle(cr_, x, y, w, h);
    cairo_clip(cr_);
  }
  void unclip() { cairo_restore(cr_); }
  cairo_t* cr() { return cr_; }

 private:
  cairo_t* cr_;
};

// Draws the pattern with `to_page` mapping sheet metres to page metres
// (a similarity: scale s, y flipped).
template <class ToPage>
void draw_pattern(Painter& p, const Pattern& pattern, const Layout& layout, const std::vector<CutInstruction>& cut,
                  const std::string& title, const ToPage& to_page, double scale, bool details) {
  cairo_t* cr = p.cr();
  auto path = [&](const Polygon2& poly) {
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d q = to_page(poly[i]);
      i == 0 ? cairo_move_to(cr, q.x(), q.y()) : cairo_line_to(cr, q.x(), q.y());
    }
    cairo_close_path(cr);
  };
  auto seg = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d qa = to_page(a), qb = to_page(b);
    p.line(qa.x(), qa.y(), qb.x(), qb.y());
  };
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const LaidOutPiece& lp = layout.pieces[i];
    p.grey(0.0);
    p.solid();
    p.width(details ? 0.0005 : 0.0002);
    for (const Polygon2& poly : lp.allowance) {
      path(poly);
      cairo_stroke(cr);
    }
    if (lp.allowance.empty() || details) {
      if (!lp.allowance.empty()) p.dash(0.003, 0.0015), p.width(0.0003);
      path(lp.outline);
      cairo_stroke(cr);
      p.solid();
    }
    if (!details) continue;
    p.width(0.0005);
    for (const Notch& n : layout.notches)
      if (n.piece == static_cast<int>(i)) seg(n.at, n.tip);
    p.width(0.0004);
    const Eigen::Vector2d a = lp.grain_from, b = lp.grain_to;
    seg(a, b);
    const double head = std::min(0.01, 0.25 * (b - a).norm());
    for (const auto& [tip, dir] : {std::pair{b, 1.0}, std::pair{a, -1.0}}) {
      seg(tip, tip + Eigen::Vector2d(-0.4 * head, -dir * head));
      seg(tip, tip + Eigen::Vector2d(0.4 * head, -dir * head));
    }
    for (const DartMark& d : layout.darts)
      if (d.piece == static_cast<int>(i)) {
        p.dash(0.001, 0.001);
        seg(0.5 * (d.mouth_left + d.mouth_right), d.tip);
        p.solid();
        const Eigen::Vector2d q = to_page(d.drill);
        p.circle(q.x(), q.y(), 0.0015);
      }
    const PieceLabel label = piece_label(lp, title, pattern.pieces[i].name, cut[i]);
    // The label with a white backing so that the grain line does not run through it.
    const Eigen::Vector2d lo = to_page(Eigen::Vector2d(label.box.lo.x(), label.box.hi.y()));
    const Eigen::Vector2d hi = to_page(Eigen::Vector2d(label.box.hi.x(), label.box.lo.y()));
    p.grey(1.0);
    p.rect(lo.x(), lo.y(), hi.x() - lo.x(), hi.y() - lo.y(), true);
    p.grey(0.0);
    const Eigen::Vector2d l1 = to_page(label.line1_at), l2 = to_page(label.line2_at);
    p.text(l1.x(), l1.y(), scale * label.size1, label.line1);
    p.text(l2.x(), l2.y(), scale * label.size2, label.line2);
    for (const SeamLabel& s : layout.seam_labels)
      if (s.piece == static_cast<int>(i)) {
        const Eigen::Vector2d q = to_page(s.at);
        p.text(q.x(), q.y(), scale * 0.003, pattern.seams[static_cast<size_t>(s.seam)].name);
      }
  }
}

// The cover: title, instructions, the test square(s), the page map.
void draw_cover(Painter& p, const Pattern& pattern, const Layout& layout, const std::vector<CutInstruction>& cut,
                const PdfOptions& o, const Tiling& t, double cover_w, double cover_h) {
  const PdfSummary& s = t.summary;
  p.begin_page();
  const double m = std::max(o.margin, 0.01);
  p.grey(0.0);
  p.text(m, m + 0.008, 0.006, o.title + ": pattern, " + o.paper.name + ", " + std::to_string(s.pages - 1) + " pages", 0.0);
  p.text(m, m + 0.014, 0.003, "Print at 100 % (actual size, no fit to page) and check the square.", 0.0);
  p.text(m, m + 0.018, 0.003, "Trim each page along its dashed left and top lines and lay it over", 0.0);
  p.text(m, m + 0.022, 0.003, "its neighbours so that the circled crosses meet.", 0.0);
  const double sq_y = m + 0.028;
  // The test square is a filled grey 60 % square of exactly its side (no
  // outline, whose width would add to it), so that a scan can measure it.
  p.grey(0.6);
  p.rect(m, sq_y, o.test_square, o.test_square, true);
  p.grey(0.0);
  p.text(m + 0.5 * o.test_square, sq_y + 0.5 * o.test_square, 0.005, format_fixed(100.0 * o.test_square, 0) + " cm");
  double map_y = sq_y + o.test_square + 0.012;
  if (o.paper.inches) {
    const double in4 = 4.0 * 0.0254;
    const double x = m + o.test_square + 0.01;
    p.grey(0.6);
    p.rect(x, sq_y, in4, in4, true);
    p.grey(0.0);
    p.text(x + 0.5 * in4, sq_y + 0.5 * in4, 0.005, "4 in");
    map_y = sq_y + std::max(o.test_square, in4) + 0.012;
  }
  // Page map: the sheet scaled into the rest of the cover.
  {
    // The map shows the whole grid of pages, which reaches past the sheet.
    const double grid_w = std::max(layout.width, s.columns * t.step_x + o.overlap);
    const double grid_h = std::max(layout.height, s.rows * t.step_y + o.overlap);
    const double avail_w = cover_w - 2.0 * m, avail_h = cover_h - map_y - m - 0.012;
    const double k = std::min(avail_w / grid_w, avail_h / grid_h);
    p.text(m, map_y, 0.003, "Page map: rows A, B, ... from the top, columns 1, 2, ... from the left;", 0.0);
    p.text(m, map_y + 0.004, 0.003, "grey pages are blank and not printed.", 0.0);
    const double ox = m, oy = map_y + 0.008;
    auto to_map = [&](const Eigen::Vector2d& q) { return Eigen::Vector2d(ox + k * q.x(), oy + k * (layout.height - q.y())); };
    for (size_t i = 0; i < s.tiles.size(); ++i) {
      const Window& w = t.windows[i];
      const Eigen::Vector2d a = to_map(Eigen::Vector2d(w.x0, w.y_top));
      p.width(0.0003);
      if (!s.tiles[i].printed) {
        p.grey(0.85);
        p.rect(a.x(), a.y(), k * w.width, k * w.height, true);
      }
      p.grey(0.4);
      p.rect(a.x(), a.y(), k * w.width, k * w.height, false);
      p.text(a.x() + 0.5 * k * w.width, a.y() + 0.5 * k * w.height + 0.002, std::min(0.006, 0.25 * k * w.height),
             s.tiles[i].label + (s.tiles[i].printed ? "" : " (blank)"));
    }
    draw_pattern(p, pattern, layout, cut, o.title, to_map, k, false);
  }
}

// Tile i, on paper pw by ph: its part of the sheet, the overlap bands,
// alignment marks, trim lines and the labels of it and its neighbours.
void draw_tile(Painter& p, const Pattern& pattern, const Layout& layout, const std::vector<CutInstruction>& cut,
               const PdfOptions& o, const Tiling& t, size_t i, double pw, double ph) {
  const PdfSummary& s = t.summary;
  const PdfPage& tile = s.tiles[i];
  p.begin_page();
  const Window& w = t.windows[i];
  auto to_page = [&](const Eigen::Vector2d& q) { return Eigen::Vector2d(o.margin + q.x() - w.x0, o.margin + w.y_top - q.y()); };
  const double iw = pw - 2.0 * o.margin, ih = ph - 2.0 * o.margin;  // printable part of this page
  p.clip(o.margin, o.margin, iw, ih);
  // Overlap bands, tinted, along the right and bottom (printed again on the
  // next page), under the pattern.
  p.grey(0.93);
  if (tile.column + 1 < s.columns) p.rect(o.margin + iw - o.overlap, o.margin, o.overlap, ih, true);
  if (tile.row + 1 < s.rows) p.rect(o.margin, o.margin + ih - o.overlap, iw, o.overlap, true);
  draw_pattern(p, pattern, layout, cut, o.title, to_page, 1.0, true);
  // Alignment marks: in sheet coordinates at the middle of every band
  // (shared with the neighbour), a circle with a cross.
  p.grey(0.0);
  p.width(0.0003);
  auto mark = [&](const Eigen::Vector2d& sheet) {
    const Eigen::Vector2d q = to_page(sheet);
    p.circle(q.x(), q.y(), 0.0035);
    p.line(q.x() - 0.005, q.y(), q.x() + 0.005, q.y());
    p.line(q.x(), q.y() - 0.005, q.x(), q.y() + 0.005);
  };
  const double mid_y = w.y_top - 0.5 * w.height, mid_x = w.x0 + 0.5 * w.width;
  if (tile.column > 0) mark({w.x0 + 0.5 * o.overlap, mid_y});
  if (tile.column + 1 < s.columns) mark({w.x0 + w.width - 0.5 * o.overlap, mid_y});
  if (tile.row > 0) mark({mid_x, w.y_top - 0.5 * o.overlap});
  if (tile.row + 1 < s.rows) mark({mid_x, w.y_top - w.height + 0.5 * o.overlap});
  p.unclip();
  // Trim lines along the left and top edges of the printed area (where a
  // neighbour is), dashed, across the whole paper.
  p.grey(0.0);
  p.width(0.0002);
  p.dash(0.002, 0.001);
  if (tile.column > 0) p.line(o.margin, 0.0, o.margin, ph);
  if (tile.row > 0) p.line(0.0, o.margin, pw, o.margin);
  p.solid();
  // Labels: this page's in the top right corner, the neighbours' at the edges.
  const std::string here = tile.label;
  p.text(pw - o.margin, o.margin - 0.002, 0.006, here + "  (" + o.title + ")", 1.0);
  const double ts = 0.0035;
  auto neighbour = [&](int dr, int dc) -> std::string {
    const int r = tile.row + dr, c = tile.column + dc;
    if (r < 0 || c < 0 || r >= s.rows || c >= s.columns) return "";
    const PdfPage& n = s.tiles[static_cast<size_t>(r * s.columns + c)];
    return n.label + (n.printed ? "" : " (blank)");
  };
  // (a quarter along each edge, clear of the alignment marks at the middle)
  if (const std::string l = neighbour(0, -1); !l.empty()) p.text(o.margin + 0.002, o.margin + 0.25 * ih, ts, "< " + l, 0.0);
  if (const std::string l = neighbour(0, 1); !l.empty()) p.text(pw - o.margin - 0.002, o.margin + 0.25 * ih, ts, l + " >", 1.0);
  if (const std::string l = neighbour(-1, 0); !l.empty()) p.text(o.margin + 0.25 * iw, o.margin + 0.005, ts, "^ " + l);
  if (const std::string l = neighbour(1, 0); !l.empty()) p.text(o.margin + 0.25 * iw, ph - o.margin - 0.002, ts, "v " + l);
}

}  // namespace

PaperSize paper_a4() { return {"a4", 0.210, 0.297, false, false}; }
PaperSize paper_letter() { return {"letter", 0.2159, 0.2794, true, false}; }
PaperSize paper_a0() { return {"a0", 0.841, 1.189, false, false}; }
PaperSize paper_roll914() { return {"roll914", 0.914, 2.5, false, true}; }

std::vector<PaperSize> pdf_papers() { return {paper_a4(), paper_letter(), paper_a0(), paper_roll914()}; }

PdfSummary tile_pages(const Layout& layout, const PdfOptions& options) { return best_tiling(layout, options).summary; }

PdfSummary write_pdf(std::ostream& out, const Pattern& pattern, const Layout& layout,
                     const std::vector<CutInstruction>& cut, const PdfOptions& o, const std::string& date) {
  const Tiling t = best_tiling(layout, o);
  const PdfSummary& s = t.summary;
  // A roll's pages end where the content does (plus the margin).
  auto page_size = [&](size_t tile) {
    double w = t.page_w, h = t.page_h;
    if (o.paper.roll && tile < t.windows.size()) {
      const Window& win = t.windows[tile];
      if (t.page_w > t.page_h) w = std::min(w, layout.width - win.x0 + 2.0 * o.margin);
      else h = std::min(h, win.y_top + 2.0 * o.margin);
    }
    return std::pair{w, h};
  };
  // The cover is as large as the first page's paper, at least A4 for the map.
  double cover_w = std::max(t.page_w, 0.210), cover_h = std::max(std::min(t.page_h, 1.189), 0.297);
  // Both test squares side by side need 23 cm across: a portrait Letter
  // cover is turned to landscape for them.
  const double squares_w = 2.0 * std::max(o.margin, 0.01) + o.test_square + (o.paper.inches ? 0.01 + 4.0 * 0.0254 : 0.0);
  if (squares_w > cover_w && cover_h > cover_w) std::swap(cover_w, cover_h);
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_pdf_surface_create_for_stream(write_to_stream, &out, kPointsPerMetre * cover_w, kPointsPerMetre * cover_h),
      cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw OutputError("cairo cannot make a PDF surface", o.paper.name);
  cairo_pdf_surface_restrict_to_version(surface.get(), CAIRO_PDF_VERSION_1_5);
  const std::string pdf_date = date.size() == 10 ? date + "T00:00:00Z" : "2000-01-01T00:00:00Z";
  cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATE_DATE, pdf_date.c_str());
  cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_TITLE, (o.title + ": sewing pattern, " + o.paper.name).c_str());
  cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATOR, "export-rest");
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), cairo_destroy);
  Painter p(cr.get());

  draw_cover(p, pattern, layout, cut, o, t, cover_w, cover_h);
  cairo_show_page(cr.get());

  // The tiles.
  for (size_t i = 0; i < s.tiles.size(); ++i) {
    if (!s.tiles[i].printed) continue;
    const auto [pw, ph] = page_size(i);
    cairo_pdf_surface_set_size(surface.get(), kPointsPerMetre * pw, kPointsPerMetre * ph);
    draw_tile(p, pattern, layout, cut, o, t, i, pw, ph);
    cairo_show_page(cr.get());
  }
  cr.reset();
  cairo_surface_finish(surface.get());
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw OutputError(std::string("cairo failed to write the PDF: ") + cairo_status_to_string(cairo_surface_status(surface.get())),
                      o.paper.name);
  return s;
}

}  // namespace gp
