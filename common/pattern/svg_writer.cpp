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
         ".fold{stroke:#000;stroke-width:0.3;stroke-dasharray:1,1}\n"
         ".drill{fill:none;stroke:#000;stroke-width:0.4}\n"
         "text{font-family:sans-serif;fill:#000}\n"
         "</style>\n";
  const std::vector<CutInstruction> cut = cut_instructions(pattern);
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const PatternPiece& p = pattern.pieces[i];
    const LaidOutPiece& lp = layout.pieces[i];
    std::string id = p.name;
    std::replace(id.begin(), id.end(), ' ', '-');
    out << "<g id=\"" << escape_xml(id) << "\">\n";
    for (const auto& poly : lp.allowance) out << "<path class=\"cut\" d=\"" << path(poly) << "\"/>\n";
    out << "<path class=\"sew\" d=\"" << path(lp.outline) << "\"/>\n";
    for (const Notch& n : layout.notches)
      if (n.piece == static_cast<int>(i)) {
        // The pair's label (the same on both pieces of the seam) as a tooltip.
        const std::string l = line(n.at, n.tip, "notch");
        out << l.substr(0, l.size() - 2) << "><title>" << escape_xml(n.label) << "</title></line>\n";
      }
    // The label, centred in the piece, and the grain line through it with an
    // arrow head at both ends, interrupted where the label is.
    const PieceLabel label = piece_label(lp, options.title, p.name, cut[i]);
    const Eigen::Vector2d a = lp.grain_from, b = lp.grain_to;
    const double head = std::min(0.01, 0.25 * (b - a).norm());
    if (a.y() < label.box.lo.y()) out << line(a, Eigen::Vector2d(a.x(), label.box.lo.y() - 0.002), "grain") << "\n";
    if (b.y() > label.box.hi.y()) out << line(Eigen::Vector2d(b.x(), label.box.hi.y() + 0.002), b, "grain") << "\n";
    for (const auto& [tip, dir] : {std::pair{b, 1.0}, std::pair{a, -1.0}}) {
      out << line(tip, tip + Eigen::Vector2d(-0.4 * head, -dir * head), "grain") << "\n";
      out << line(tip, tip + Eigen::Vector2d(0.4 * head, -dir * head), "grain") << "\n";
    }
    out << "<text x=\"" << X(label.line1_at) << "\" y=\"" << Y(label.line1_at) << "\" font-size=\""
        << format_fixed(1000.0 * label.size1, 1) << "\" text-anchor=\"middle\">" << escape_xml(label.line1) << "</text>\n";
    out << "<text x=\"" << X(label.line2_at) << "\" y=\"" << Y(label.line2_at) << "\" font-size=\""
        << format_fixed(1000.0 * label.size2, 1) << "\" text-anchor=\"middle\">" << escape_xml(label.line2) << "</text>\n";
    // Darts: the fold line from the middle of the mouth to the tip, and the
    // drill hole a centimetre short of the tip.
    for (const DartMark& d : layout.darts)
      if (d.piece == static_cast<int>(i)) {
        out << line(0.5 * (d.mouth_left + d.mouth_right), d.tip, "fold") << "\n";
        out << "<circle class=\"drill\" cx=\"" << X(d.drill) << "\" cy=\"" << Y(d.drill) << "\" r=\"1.5\"/>\n";
      }
    for (const SeamLabel& s : layout.seam_labels)
      if (s.piece == static_cast<int>(i))
        out << "<text x=\"" << X(s.at) << "\" y=\"" << Y(s.at) << "\" font-size=\"3\" text-anchor=\"middle\">"
            << escape_xml(pattern.seams[static_cast<size_t>(s.seam)].name) << "</text>\n";
    out << "</g>\n";
  }
  out << "</svg>\n";
}

}  // namespace gp
