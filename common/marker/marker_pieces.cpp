#include "marker/marker_pieces.h"

#include <cmath>

#include "core/error.h"
#include "spec/spec_object.h"

namespace gp {

double signed_area(const std::vector<Eigen::Vector2d>& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d& u = p[i];
    const Eigen::Vector2d& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return 0.5 * a;
}

MarkerPieces read_marker_pieces(const std::filesystem::path& path) {
  const std::string file = path.string();
  const Json j = read_json_file(path);
  check_schema(j, "marker-pieces", {1}, file);
  SpecObject o(j, file);
  o.allow("schema");
  o.allow("source");
  MarkerPieces m;
  m.units = o.string("units", "m");
  m.fabric_width = o.number("fabric_width", 0.0, Range::non_negative());
  m.fabric = o.string("fabric", "");
  const SpecArray pieces = o.array("pieces");
  if (pieces.empty()) throw SpecError("no pieces", file + ":/pieces");
  for (size_t i = 0; i < pieces.size(); ++i) {
    const SpecObject p = pieces.object(i);
    MarkerPiece piece;
    piece.name = p.required_string("name");
    piece.quantity = static_cast<int>(p.integer("quantity", 1, Range::between(1, 10000)));
    piece.mirrored_pairs = p.boolean("mirrored_pairs", false);
    if (p.has("orientations")) {
      piece.orientations.clear();
      for (double d : p.numbers("orientations")) {
        const long k = std::lround(d);
        if (std::abs(d - static_cast<double>(k)) > 1e-9 || k % 90 != 0)
          throw SpecError("orientations must be multiples of 90 degrees", p.where("orientations"));
        piece.orientations.push_back(static_cast<int>(((k % 360) + 360) % 360));
      }
      if (piece.orientations.empty()) throw SpecError("no orientation allowed", p.where("orientations"));
    }
    const SpecArray outline = p.array("outline");
    for (size_t k = 0; k < outline.size(); ++k) {
      const Json& q = outline.at(k);
      if (!q.is_array() || q.size() != 2 || !q[0].is_number() || !q[1].is_number())
        throw SpecError("a point must be [x, y]", outline.where(k));
      piece.outline.emplace_back(q[0].get<double>(), q[1].get<double>());
      if (!piece.outline.back().allFinite()) throw SpecError("a point is not finite", outline.where(k));
    }
    // A closing point equal to the first is dropped (the ESICUP files repeat it).
    if (piece.outline.size() > 3 && (piece.outline.front() - piece.outline.back()).norm() == 0.0) piece.outline.pop_back();
    if (piece.outline.size() < 3) throw SpecError("an outline needs at least 3 points", p.where("outline"));
    if (std::abs(signed_area(piece.outline)) <= 0.0) throw GeometryError("outline of no area", p.where("outline"));
    p.finish();
    m.pieces.push_back(piece);
  }
  o.finish();
  return m;
}

OrderedJson marker_pieces_json(const MarkerPieces& m) {
  OrderedJson j;
  j["schema"] = schema_tag("marker-pieces", 1);
  j["units"] = m.units;
  if (m.fabric_width > 0.0) j["fabric_width"] = m.fabric_width;
  if (!m.fabric.empty()) j["fabric"] = m.fabric;
  OrderedJson pieces = OrderedJson::array();
  for (const MarkerPiece& p : m.pieces) {
    OrderedJson outline = OrderedJson::array();
    for (const auto& q : p.outline) outline.push_back({q.x(), q.y()});
    pieces.push_back({{"name", p.name},
                      {"quantity", p.quantity},
                      {"mirrored_pairs", p.mirrored_pairs},
                      {"orientations", p.orientations},
                      {"outline", outline}});
  }
  j["pieces"] = pieces;
  return j;
}

}  // namespace gp
