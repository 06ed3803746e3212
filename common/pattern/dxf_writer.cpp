#include "pattern/dxf_writer.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <limits>

#include "core/error.h"
#include "core/math.h"
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
  void point_entity(const Eigen::Vector2d& p, const std::string& layer) {
    pair(0, "POINT");
    pair(8, layer);
    point(p);
  }
  void notch_point(const Eigen::Vector2d& p, double degrees, const std::string& layer) {
    point_entity(p, layer);
    pair(50, format_fixed(degrees, 4));
  }

 private:
  std::ostream& out_;
};

// Where the notch at `n` meets the cutting line: the ray from the sewing
// line outwards hits the nearest cutting-line segment; where it hits none
// within 5 cm (at a dart's mouth, whose allowance is bridged), the point of
// the cutting line nearest to the notch.
Eigen::Vector2d notch_on_cut_line(const Notch& n, const std::vector<Polygon2>& cut) {
  double best = 0.05;
  Eigen::Vector2d at = n.at;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Polygon2& poly : cut)
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d a = poly[i], e = poly[(i + 1) % poly.size()] - a;
      const double t = std::clamp((n.at - a).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
      const Eigen::Vector2d q = a + t * e;
      if ((q - n.at).norm() < nearest) nearest = (q - n.at).norm(), at = q;
    }
  for (const Polygon2& poly : cut)
    for (size_t i = 0; i < poly.size(); ++i) {
      const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()];
      const Eigen::Vector2d e = b - a;
      const double den = n.outward.x() * (-e.y()) - n.outward.y() * (-e.x());
      if (std::abs(den) < 1e-12) continue;
      const Eigen::Vector2d r = a - n.at;
      const double t = (r.x() * (-e.y()) - r.y() * (-e.x())) / den;  // along the ray
      const double u = (n.outward.x() * r.y() - n.outward.y() * r.x()) / den;  // along the segment
      if (t >= 0.0 && t < best && u >= 0.0 && u <= 1.0) best = t, at = n.at + t * n.outward;
    }
  return at;
}

// Block names: the piece's name with spaces as underscores, in ASCII.
std::string block_name(const std::string& piece) {
  std::string s = ascii_text(piece);
  for (char& c : s)
    if (c == ' ') c = '_';
  return s;
}

void write_header_and_layers(DxfStream& d, const Layout& layout, const std::vector<std::string>& layers) {
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
  d.pair(70, std::to_string(layers.size()));
  int color = 1;
  for (const std::string& name : layers) {
    d.pair(0, "LAYER");
    d.pair(2, name);
    d.pair(70, "0");
    d.pair(62, std::to_string(color++));
    d.pair(6, "CONTINUOUS");
  }
  d.pair(0, "ENDTAB");
  d.pair(0, "ENDSEC");
}

void write_industry_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const DxfOptions& options,
                        const std::vector<CutInstruction>& cut) {
  DxfStream d(out);
  const bool astm = options.profile == DxfProfile::astm;
  write_header_and_layers(d, layout, {"0", "1", "2", "3", "4", "6", "7", "8", "13", "14"});
  const std::string size = ascii_text(options.size.empty() ? options.style : options.size);
  // Each piece's block in its own frame: the lower left corner of its
  // cutting line's box is the block's origin and the INSERT's point.
  std::vector<Eigen::Vector2d> origin(pattern.pieces.size());
  d.pair(0, "SECTION");
  d.pair(2, "BLOCKS");
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const LaidOutPiece& lp = layout.pieces[i];
    const std::vector<Polygon2> cut_lines = lp.allowance.empty() ? std::vector<Polygon2>{lp.outline} : lp.allowance;
    Eigen::Vector2d lo = lp.outline.front();
    for (const Polygon2& poly : cut_lines)
      for (const auto& q : poly) lo = lo.cwiseMin(q);
    origin[i] = lo;
    auto at = [&](const Eigen::Vector2d& p) -> Eigen::Vector2d { return p - lo; };
    auto shifted = [&](const Polygon2& poly) {
      Polygon2 q;
      for (const auto& p : poly) q.push_back(at(p));
      return q;
    };
    const std::string name = block_name(pattern.pieces[i].name);
    d.pair(0, "BLOCK");
    d.pair(8, "0");
    d.pair(2, name);
    d.pair(70, "0");
    d.point(Eigen::Vector2d::Zero());
    d.pair(3, name);
    for (const Polygon2& poly : cut_lines) {
      d.polyline(shifted(poly), "1");
      // Turn and curve points at the cutting line's vertices.
      const size_t m = poly.size();
      for (size_t k = 0; k < m; ++k) {
        const Eigen::Vector2d a = poly[(k + m - 1) % m], p = poly[k], b = poly[(k + 1) % m];
        const Eigen::Vector2d u = p - a, v = b - p;
        const double turn = std::abs(gp::math::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v))) * 180.0 / M_PI;
        d.point_entity(at(p), turn > kTurnPointDegrees ? "2" : "3");
      }
    }
    for (const Notch& n : layout.notches) {
      if (n.piece != static_cast<int>(i)) continue;
      const Eigen::Vector2d on_cut = notch_on_cut_line(n, cut_lines);
      const Eigen::Vector2d inward = -n.outward;
      if (astm) {
        d.notch_point(at(on_cut), gp::math::atan2(inward.y(), inward.x()) * 180.0 / M_PI, "4");
      } else {
        const double depth = std::max(0.002, (n.tip - n.at).norm());
        d.line(at(on_cut), at(on_cut + depth * inward), "4");
      }
    }
    d.line(at(lp.grain_from), at(lp.grain_to), "7");
    for (const DartMark& m : layout.darts)
      if (m.piece == static_cast<int>(i)) {
        d.line(at(m.mouth_left), at(m.tip), "8");
        d.line(at(m.mouth_right), at(m.tip), "8");
        d.point_entity(at(m.drill), "13");
      }
    d.polyline(shifted(lp.outline), "14");
    // Piece text, one line per TEXT, stacked downwards from the label's place.
    const CutInstruction& c = cut[i];
    const std::vector<std::string> lines = {
        "Piece Name: " + ascii_text(pattern.pieces[i].name),
        "Quantity: " + std::to_string(c.quantity),
        "Size: " + size,
        "Category: " + ascii_text(c.fabric),
        "Fabric: " + ascii_text(c.fabric),
        "Annotation: " + ascii_text(c.text())};
    const double height = std::clamp(lp.label_room / 8.0, 0.001, 0.004);  // metres
    size_t longest = 0;
    for (const std::string& s : lines) longest = std::max(longest, s.size());
    // TEXT starts at its insertion point: the block of lines centred on the
    // label's place (widths estimated at 0.6 of the height per character).
    Eigen::Vector2d line_at = lp.label_at + Eigen::Vector2d(-0.3 * height * static_cast<double>(longest), 4.0 * height);
    for (const std::string& s : lines) {
      d.text(at(line_at), 1000.0 * height, s, "1");
      line_at.y() -= 1.6 * height;
    }
    d.pair(0, "ENDBLK");
    d.pair(8, "0");
  }
  d.pair(0, "ENDSEC");
  d.pair(0, "SECTION");
  d.pair(2, "ENTITIES");
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    d.pair(0, "INSERT");
    d.pair(8, "1");
    d.pair(2, block_name(pattern.pieces[i].name));
    d.point(origin[i]);
  }
  // Style text, once, above the sheet's lower left corner.
  const std::vector<std::string> style = {"Style Name: " + ascii_text(options.style),
                                          "Creation Date: " + (options.date.empty() ? std::string("unknown") : ascii_text(options.date)),
                                          "Author: " + ascii_text(options.author),
                                          "Sample Size: " + size,
                                          "Units: METRIC"};
  Eigen::Vector2d style_at(0.0, -0.006);
  for (const std::string& s : style) {
    d.text(style_at, 4.0, s, "1");
    style_at.y() -= 0.0065;
  }
  d.pair(0, "ENDSEC");
  d.pair(0, "EOF");
}

}  // namespace

DxfProfile dxf_profile_from_name(const std::string& name) {
  if (name == "astm") return DxfProfile::astm;
  if (name == "aama") return DxfProfile::aama;
  if (name == "plain") return DxfProfile::plain;
  throw UsageError("unknown DXF profile '" + name + "' (astm, aama or plain)", "--dxf-profile");
}

std::string dxf_profile_name(DxfProfile profile) {
  switch (profile) {
    case DxfProfile::astm: return "astm";
    case DxfProfile::aama: return "aama";
    case DxfProfile::plain: return "plain";
  }
  return "astm";
}

std::string default_creation_date(const std::string& input) {
  std::time_t t = 0;
  bool known = false;
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long v = std::strtoll(epoch, &end, 10);
    if (end != epoch && *end == '\0') t = static_cast<std::time_t>(v), known = true;
  }
  struct stat st {};
  if (!known && ::stat(input.c_str(), &st) == 0) t = st.st_mtime, known = true;
  if (!known) return "";
  std::tm tm {};
  gmtime_r(&t, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

std::string ascii_text(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c <= 0x7e) {
      out += static_cast<char>(c);
    } else {
      out += '?';
      if (c >= 0xc0)  // skip the continuation bytes of a UTF-8 sequence
        while (i + 1 < s.size() && (static_cast<unsigned char>(s[i + 1]) & 0xc0) == 0x80) ++i;
    }
  }
  return out;
}

void write_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const DxfOptions& options,
               const std::vector<CutInstruction>& cut) {
  if (options.profile == DxfProfile::plain) {
    write_dxf(out, pattern, layout, options.style);
    return;
  }
  write_industry_dxf(out, pattern, layout, options, cut);
}

void write_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const std::string& title) {
  const std::vector<CutInstruction> cut = cut_instructions(pattern);
  DxfStream d(out);
  write_header_and_layers(d, layout, {"SEW", "CUT", "NOTCH", "GRAIN", "LABEL"});
  d.pair(0, "SECTION");
  d.pair(2, "ENTITIES");
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const LaidOutPiece& lp = layout.pieces[i];
    d.polyline(lp.outline, "SEW");
    for (const auto& poly : lp.allowance) d.polyline(poly, "CUT");
    for (const Notch& n : layout.notches)
      if (n.piece == static_cast<int>(i)) d.line(n.at, n.tip, "NOTCH");
    d.line(lp.grain_from, lp.grain_to, "GRAIN");
    const PieceLabel label = piece_label(lp, title, pattern.pieces[i].name, cut[i]);
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
