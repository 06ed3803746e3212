#include "pattern/cut_instructions.h"

#include <cmath>

#include "pattern/layout.h"
#include "pattern/piece_names.h"

namespace gp {

std::string CutInstruction::text() const {
  std::string s = "cut " + std::to_string(quantity) + " " + fabric + ", face up";
  if (on_fold) s += ", on fold";
  if (!mirror_of.empty()) s += ", pair of " + mirror_of;
  return s;
}

std::vector<CutInstruction> cut_instructions(const Pattern& pattern) {
  std::vector<CutInstruction> cut(pattern.pieces.size());
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const std::string& name = pattern.pieces[i].name;
    const std::string mirrored = mirror_name(name);
    if (mirrored == name) continue;
    for (const PatternPiece& q : pattern.pieces)
      if (q.name == mirrored) cut[i].mirror_of = mirrored;
  }
  return cut;
}

MarkerPieces marker_pieces(const Pattern& pattern, const Layout& layout, const std::vector<CutInstruction>& cut) {
  MarkerPieces m;
  m.units = "m";
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const LaidOutPiece& lp = layout.pieces[i];
    MarkerPiece p;
    p.name = pattern.pieces[i].name;
    p.quantity = cut[i].quantity;
    // Several cutting-line loops would be one piece cut apart: take the outermost (largest).
    const Polygon2* line = &lp.outline;
    double best = std::abs(signed_area(std::vector<Eigen::Vector2d>(lp.outline.begin(), lp.outline.end())));
    for (const Polygon2& poly : lp.allowance) {
      const double a = std::abs(signed_area(std::vector<Eigen::Vector2d>(poly.begin(), poly.end())));
      if (a > best) best = a, line = &poly;
    }
    for (const auto& q : *line) p.outline.emplace_back(q.y(), -q.x());  // grain +y -> +x
    m.pieces.push_back(p);
  }
  return m;
}

}  // namespace gp
