#include "pattern/dxf_writer.h"

#include <algorithm>

#include "pattern/svg_writer.h"

namespace gp {
namespace {

class DxfStream {
 public:
  explicit DxfStream(std::ostream& out) : out_(out) {}
  void pair(int code, const std::string& value) { out_ << code << "\n" << value << "\n"; }
  void number(int code, double mm) { pair(code, format_fixed(mm, 4)); }
  void point(const Eigen::Vector2d& p, int base = 10) {
    number(base, 1000.0 * p.x());
    number(base + 10, 1000.0 * p.y());
    number(base + 20, 0.0);
  }
  void polyline(const Polygon2& poly, const std::string& layer) {
    pair(0, "POLYLINE");
    pair(8, layer);
    pair(66, "1");
    point(Eigen::Vector2d::Zero());
    pair(70, "1");  // closed
    for (const auto& p : poly) {
      pair(0, "VERTEX");
      pair(8, layer);
      point(p);
    }
    pair(0, "SEQEND");
    pair(8, layer);
  }
  void line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const std::string& layer) {
    pair(0, "LINE");
    pair(8, layer);
    point(a, 10);
    point(b, 11);
  }
  void text(const Eigen::Vector2d& at, double height_mm, const std::string& s, const std::string& layer) {
    pair(0, "TEXT");
    pair(8, layer);
    point(at);
    number(40, height_mm);
    pair(1, s);
  }

 private:
  std::ostream& out_;
};

}  // namespace

void write_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const std::string& title) {
  DxfStream d(out);
  d.pair(0, "SECTION");
  d.pair(2, "HEADER");
  d.pair(9, "$ACADVER");
  d.pair(1, "AC1009");
  d.pair(9, "$EXTMIN");
  d.point(Eigen::Vector2d::Zero());
  d.pair(9, "$EXTMAX");
  d.point(Eigen::Vector2d(layout.width, layout.height));
  d.pair(0, "ENDSEC");
  d.pair(0, "SECTION");
  d.pair(2, "TABLES");
  d.pair(0, "TABLE");
  d.pair(2, "LAYER");
  const char* layers[] = {"SEW", "CUT", "NOTCH", "GRAIN", "LABEL"};
  d.pair(70, std::to_string(sizeof(layers) / sizeof(layers[0])));
  int color = 1;
  for (const char* name : layers) {
    d.pair(0, "LAYER");
    d.pair(2, name);
    d.pair(70, "0");
    d.pair(62, std::to_string(color++));
    d.pair(6, "CONTINUOUS");
  }
  d.pair(0, "ENDTAB");
  d.pair(0, "ENDSEC");
  d.pair(0, "SECTION");
  d.pair(2, "ENTITIES");
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const LaidOutPiece& lp = layout.pieces[i];
    d.polyline(lp.outline, "SEW");
    for (const auto& poly : lp.allowance) d.polyline(poly, "CUT");
    for (const Notch& n : layout.notches)
      if (n.piece == static_cast<int>(i)) d.line(n.at, n.tip, "NOTCH");
    d.line(lp.grain_from, lp.grain_to, "GRAIN");
    const PieceLabel label = piece_label(lp, title, pattern.pieces[i].name);
    // DXF R12 text starts at its insertion point: shifted left by half its estimated width.
    d.text(label.line1_at - Eigen::Vector2d(0.3 * label.size1 * static_cast<double>(label.line1.size()), 0.0),
           1000.0 * label.size1, label.line1, "LABEL");
    for (const DartMark& m : layout.darts)
      if (m.piece == static_cast<int>(i)) d.line(0.5 * (m.mouth_left + m.mouth_right), m.tip, "DART");
    for (const SeamLabel& s : layout.seam_labels)
      if (s.piece == static_cast<int>(i)) d.text(s.at, 3.0, pattern.seams[static_cast<size_t>(s.seam)].name, "LABEL");
  }
  d.pair(0, "ENDSEC");
  d.pair(0, "EOF");
}

}  // namespace gp
