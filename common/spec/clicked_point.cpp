#include "spec/clicked_point.h"

#include "core/error.h"
#include "spec/spec_object.h"

namespace gp {

ClickedPoint read_clicked_point(const Json& j, const std::string& where, const std::string& noun) {
  ClickedPoint p;
  p.where = where;
  if (j.is_number_integer()) {
    p.vertex_id = j.get<long long>();
    if (p.vertex_id < 0) throw SpecError("a " + noun + " id cannot be negative", where);
    return p;
  }
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number()) {
    p.is_vertex = false;
    p.point = {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
    if (!p.point.allFinite()) throw SpecError("point is not finite", where);
    return p;
  }
  throw SpecError("expected a " + noun + " id or a point [x, y, z], found " + json_type_name(j), where);
}

OrderedJson to_json(const ClickedPoint& p) {
  if (p.is_vertex) return p.vertex_id;
  return OrderedJson::array({p.point[0], p.point[1], p.point[2]});
}

}  // namespace gp
