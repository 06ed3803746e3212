#include "pattern/svg_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gp {

void write_svg(std::ostream& out, const Pattern& pattern, const Layout& layout, const SvgOptions& options) {
  const double W = 1000.0 * layout.width, H = 1000.0 * layout.height;
  // Sheet metres (y up) to SVG millimetres (y down).
  auto X = [&](const Eigen::Vector2d& p) { return format_fixed(1000.0 * p.x()); };
  auto Y = [&](const Eigen::Vector2d& p) { return format_fixed(H - 1000.0 * p.y()); };
  auto path = [&](const Polygon2& poly) {
    std::string d;
    for (size_t i = 0; i < poly.size(); ++i) d += (i == 0 ? "M" : " L") + X(poly[i]) + "," + Y(poly[i]);
    return d + " Z";
  };
  auto line = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const std::string& cls) {
    return "<line class=\"" + cls + "\" x1=\"" + X(a) + "\" y1=\"" + Y(a) + "\" x2=\"" + X(b) + "\" y2=\"" + Y(b) + "\"/>";
  };
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << format_fixed(W) << "mm\" height=\""
      << format_fixed(H) << "mm\" viewBox=\"0 0 " << format_fixed(W) << " " << format_fixed(H) << "\">\n";
  out << "<title>" << escape_xml(options.title) << ": sewing pattern, 1:1, millimetres</title>\n";
  out << "<style>\n"
         ".cut{fill:none;stroke:#000;stroke-width:0.5}\n"
         ".sew{fill:#f4f1ea;stroke:#000;stroke-width:0.3;stroke-dasharray:3,1.5}\n"
         ".notch{stroke:#000;stroke-width:0.5}\n"
         ".grain{stroke:#000;stroke-width:0.4}\n"
         "text{font-family:sans-serif;fill:#000}\n"
         "</style>\n";
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const PatternPiece& p = pattern.pieces[i];
    const LaidOutPiece& lp = layout.pieces[i];
    out << "<g id=\"" << escape_xml(p.name) << "\">\n";
    for (const auto& poly : lp.allowance) out << "<path class=\"cut\" d=\"" << path(poly) << "\"/>\n";
    out << "<path class=\"sew\" d=\"" << path(lp.outline) << "\"/>\n";
    for (const Notch& n : layout.notches)
      if (n.piece == static_cast<int>(i))
        out << line(n.at, n.tip, "notch") << "\n";
    // Grain line with an arrow head at both ends.
    const Eigen::Vector2d a = lp.grain_from, b = lp.grain_to;
    const double head = std::min(0.01, 0.25 * (b - a).norm());
    out << line(a, b, "grain") << "\n";
    for (const auto& [tip, dir] : {std::pair{b, 1.0}, std::pair{a, -1.0}}) {
      out << line(tip, tip + Eigen::Vector2d(-0.4 * head, -dir * head), "grain") << "\n";
      out << line(tip, tip + Eigen::Vector2d(0.4 * head, -dir * head), "grain") << "\n";
    }
    const double size = std::clamp(1000.0 * lp.label_room / 4.0, 2.0, 10.0);
    const Eigen::Vector2d t = lp.label_at + Eigen::Vector2d(0.002, 0.0);
    out << "<text x=\"" << X(t) << "\" y=\"" << Y(t) << "\" font-size=\"" << format_fixed(size, 1) << "\">"
        << escape_xml(options.title + " " + p.name) << "</text>\n";
    const Eigen::Vector2d t2 = t - Eigen::Vector2d(0.0, 0.0012 * size);
    out << "<text x=\"" << X(t2) << "\" y=\"" << Y(t2) << "\" font-size=\"" << format_fixed(0.6 * size, 1)
        << "\">cut 1, right side up, grain " << (lp.grain_from_body_vertical ? "vertical" : "along the piece")
        << "</text>\n";
    for (const SeamLabel& s : layout.seam_labels)
      if (s.piece == static_cast<int>(i))
        out << "<text x=\"" << X(s.at) << "\" y=\"" << Y(s.at) << "\" font-size=\"3\" text-anchor=\"middle\">"
            << escape_xml(pattern.seams[static_cast<size_t>(s.seam)].name) << "</text>\n";
    out << "</g>\n";
  }
  out << "</svg>\n";
}

}  // namespace gp
