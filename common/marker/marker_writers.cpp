#include "marker/marker_writers.h"

#include <cairo-pdf.h>
#include <cairo.h>

#include <algorithm>
#include <memory>

#include "core/error.h"
#include "core/text_format.h"

namespace gp {
namespace {

constexpr double kMargin = 10.0;  // mm around the fabric

std::string copy_label(const MarkerPieces& pieces, const Placement& p) {
  const MarkerPiece& piece = pieces.pieces[static_cast<size_t>(p.piece)];
  std::string s = piece.name;
  if (piece.quantity > 1) s += " " + std::to_string(p.copy + 1) + "/" + std::to_string(piece.quantity);
  if (p.mirrored) s += " (mirrored)";
  return s;
}

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ostream*>(closure);
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return out->good() ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

double marker_mm_per_unit(const MarkerPieces& pieces) { return pieces.units == "m" ? 1000.0 : 10.0; }

void write_marker_svg(std::ostream& out, const MarkerPieces& pieces, const MarkerResult& m, const std::string& title) {
  const double k = marker_mm_per_unit(pieces);
  const double L = k * m.length, W = k * m.width;
  const double pw = L + 2.0 * kMargin, ph = W + 2.0 * kMargin + 12.0;
  // Fabric frame (x along the length, y across, up) to SVG (y down): the
  // selvedge y = width at the top.
  auto X = [&](double x) { return format_fixed(kMargin + k * x); };
  auto Y = [&](double y) { return format_fixed(kMargin + W - k * y); };
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << format_fixed(pw) << "mm\" height=\""
      << format_fixed(ph) << "mm\" viewBox=\"0 0 " << format_fixed(pw) << " " << format_fixed(ph) << "\">\n";
  out << "<title>" << escape_xml(title) << ": marker</title>\n";
  out << "<style>.fabric{fill:#fbfaf6;stroke:#000;stroke-width:0.6}.piece{fill:#dfe8f1;stroke:#000;stroke-width:0.4}"
         "text{font-family:sans-serif;fill:#000}</style>\n";
  out << "<rect class=\"fabric\" x=\"" << X(0) << "\" y=\"" << Y(m.width) << "\" width=\"" << format_fixed(L)
      << "\" height=\"" << format_fixed(W) << "\"/>\n";
  for (const Placement& p : m.placements) {
    std::string d;
    for (size_t i = 0; i < p.outline.size(); ++i) d += (i ? " L" : "M") + X(p.outline[i].x()) + "," + Y(p.outline[i].y());
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& q : p.outline) c += q / static_cast<double>(p.outline.size());
    out << "<g><path class=\"piece\" d=\"" << d << " Z\"/><text x=\"" << X(c.x()) << "\" y=\"" << Y(c.y())
        << "\" font-size=\"" << format_fixed(std::max(2.0, std::min(12.0, 0.02 * W)), 1) << "\" text-anchor=\"middle\">"
        << escape_xml(copy_label(pieces, p)) << "</text></g>\n";
  }
  const std::string units = pieces.units == "m" ? "m" : " " + pieces.units;
  out << "<text x=\"" << format_fixed(kMargin) << "\" y=\"" << format_fixed(ph - 4.0) << "\" font-size=\"6\">"
      << escape_xml(title + ": marker " + format_fixed(m.length, 3) + units + " long on " + format_fixed(m.width, 3) + units +
                    " wide, utilisation " + format_fixed(100.0 * m.utilisation, 1) + " %, " +
                    std::to_string(m.placements.size()) + " pieces; grain along the length")
      << "</text>\n";
  out << "</svg>\n";
}

void write_marker_pdf(std::ostream& out, const MarkerPieces& pieces, const MarkerResult& m, const std::string& title) {
  const double mm = 72.0 / 25.4;
  const double k = marker_mm_per_unit(pieces);
  const double L = k * m.length, W = k * m.width;
  double pw = L + 2.0 * kMargin, ph = W + 2.0 * kMargin + 12.0;
  const double largest = 14400.0 / mm;  // PDF's largest page side, 200 in
  const double scale = std::min(1.0, largest / std::max(pw, ph));
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_pdf_surface_create_for_stream(write_to_stream, &out, mm * scale * pw, mm * scale * ph), cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) throw OutputError("cairo cannot make a PDF surface", "marker.pdf");
  cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATE_DATE, "2000-01-01T00:00:00Z");
  cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_TITLE, (title + ": marker").c_str());
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> holder(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = holder.get();
  cairo_scale(cr, mm * scale, mm * scale);
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  auto X = [&](double x) { return kMargin + k * x; };
  auto Y = [&](double y) { return kMargin + W - k * y; };
  cairo_set_source_rgb(cr, 0.985, 0.98, 0.965);
  cairo_rectangle(cr, X(0), Y(m.width), L, W);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 0.6);
  cairo_stroke(cr);
  cairo_set_line_width(cr, 0.4);
  for (const Placement& p : m.placements) {
    for (size_t i = 0; i < p.outline.size(); ++i)
      i ? cairo_line_to(cr, X(p.outline[i].x()), Y(p.outline[i].y())) : cairo_move_to(cr, X(p.outline[i].x()), Y(p.outline[i].y()));
    cairo_close_path(cr);
    cairo_set_source_rgb(cr, 0.875, 0.91, 0.945);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_stroke(cr);
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& q : p.outline) c += q / static_cast<double>(p.outline.size());
    const std::string label = copy_label(pieces, p);
    cairo_set_font_size(cr, std::max(2.0, std::min(12.0, 0.02 * W)));
    cairo_text_extents_t e;
    cairo_text_extents(cr, label.c_str(), &e);
    cairo_move_to(cr, X(c.x()) - 0.5 * e.x_advance, Y(c.y()));
    cairo_show_text(cr, label.c_str());
  }
  const std::string units = pieces.units == "m" ? "m" : " " + pieces.units;
  std::string caption = title + ": marker " + format_fixed(m.length, 3) + units + " long on " + format_fixed(m.width, 3) +
                        units + " wide, utilisation " + format_fixed(100.0 * m.utilisation, 1) + " %, " +
                        std::to_string(m.placements.size()) + " pieces; grain along the length";
  if (scale < 1.0) caption += "; drawn at " + format_fixed(scale, 3) + " of full size";
  cairo_set_font_size(cr, 6.0);
  cairo_move_to(cr, kMargin, ph - 4.0);
  cairo_show_text(cr, caption.c_str());
  cairo_show_page(cr);
  holder.reset();
  cairo_surface_finish(surface.get());
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) throw OutputError("cairo failed to write the PDF", "marker.pdf");
}

OrderedJson marker_report(const MarkerPieces& pieces, const MarkerResult& m, const NestOptions& o) {
  OrderedJson j;
  j["schema"] = schema_tag("make-marker-report", 1);
  j["units"] = pieces.units;
  if (!pieces.fabric.empty()) j["fabric"] = pieces.fabric;
  j["options"] = {{"fabric_width", o.width},
                  {"resolution", m.resolution},
                  {"seed", o.seed},
                  {"budget_s", o.budget_s},
                  {"work_per_second", kWorkPerSecond}};
  j["fabric_width"] = m.width;
  j["length"] = m.length;
  j["utilisation"] = m.utilisation;
  j["piece_area"] = m.piece_area;
  j["pieces"] = m.placements.size();
  j["largest_first_length"] = m.first_length;
  j["orders_tried"] = m.evaluations;
  j["work"] = m.work;
  int overlaps = 0;
  double tol = 1e-9 * std::max(1.0, m.width);
  for (size_t a = 0; a < m.placements.size(); ++a)
    for (size_t b = a + 1; b < m.placements.size(); ++b)
      overlaps += polygons_overlap(m.placements[a].outline, m.placements[b].outline, tol) ? 1 : 0;
  bool inside = true;
  for (const Placement& p : m.placements)
    for (const auto& q : p.outline) inside = inside && q.y() >= -tol && q.y() <= m.width + tol && q.x() >= -tol;
  j["overlapping_pairs"] = overlaps;
  j["inside_width"] = inside;
  OrderedJson placements = OrderedJson::array();
  for (const Placement& p : m.placements) {
    OrderedJson outline = OrderedJson::array();
    for (const auto& q : p.outline) outline.push_back({q.x(), q.y()});
    placements.push_back({{"piece", pieces.pieces[static_cast<size_t>(p.piece)].name},
                          {"copy", p.copy},
                          {"mirrored", p.mirrored},
                          {"rotation_deg", p.rotation},
                          {"offset", {p.offset.x(), p.offset.y()}},
                          {"outline", outline}});
  }
  j["placements"] = placements;
  return j;
}

}  // namespace gp
