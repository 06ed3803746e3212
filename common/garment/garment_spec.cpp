#include "garment/garment_spec.h"

#include <algorithm>
#include <set>

#include "core/error.h"
#include "spec/clicked_point.h"

namespace gp {
namespace {

SpecPoint read_point(const Json& j, const std::string& where) {
  return read_clicked_point(j, where, "body vertex");
}

OrderedJson point_json(const SpecPoint& p) { return to_json(p); }

// The body region of a paint or grain entry: a geodesic disc ("disc") or a
// set of body vertices ("vertices"), exactly one of them.
void read_body_region(const SpecObject& p, PaintRegion& r) {
  const bool disc = p.has("disc"), vertices = p.has("vertices");
  if (disc == vertices) throw SpecError("give exactly one of 'disc' and 'vertices'", p.where());
  if (disc) {
    const SpecObject d = p.object("disc");
    const Json* center = d.raw("center");
    if (!center) throw SpecError("missing required field 'center'", d.where("center"));
    r.center = read_point(*center, d.where("center"));
    r.radius = d.required_number("radius", Range::positive());
    d.finish();
  } else {
    r.is_disc = false;
    const Json* ids = p.raw("vertices");
    if (!ids->is_array() || ids->empty())
      throw SpecError("expected a non-empty array of body vertex ids", p.where("vertices"));
    for (size_t k = 0; k < ids->size(); ++k) {
      if (!(*ids)[k].is_number_integer() || (*ids)[k].get<long long>() < 0)
        throw SpecError("expected a body vertex id", p.where("vertices") + "/" + std::to_string(k));
      r.vertex_ids.push_back((*ids)[k].get<long long>());
    }
  }
}

}  // namespace

GarmentSpec parse_garment_spec(const Json& j, const std::string& file) {
  check_schema(j, "garment-spec", {1}, file);
  const SpecObject root(j, file);
  root.allow("schema");
  GarmentSpec s;
  s.file = file;
  s.name = root.string("name", "garment");
  s.design_pose = root.string("design_pose", "");

  const SpecArray loops = root.array("loops");
  if (loops.empty()) throw SpecError("a garment needs at least one boundary loop", root.where("loops"));
  std::set<std::string> names;
  for (size_t i = 0; i < loops.size(); ++i) {
    const SpecObject l = loops.object(i);
    SpecLoop loop;
    loop.where = l.where();
    loop.name = l.required_string("name");
    if (loop.name.empty() || !names.insert(loop.name).second)
      throw SpecError("loop names must be unique and not empty", l.where("name"));
    loop.pinned = l.boolean("pinned", false);
    const Json* points = l.raw("points");
    if (!points) throw SpecError("missing required field 'points'", l.where("points"));
    if (!points->is_array()) throw SpecError("expected an array of points", l.where("points"));
    for (size_t k = 0; k < points->size(); ++k)
      loop.points.push_back(read_point((*points)[k], l.where("points") + "/" + std::to_string(k)));
    l.finish();
    s.loops.push_back(loop);
  }

  const Json* region = root.raw("region");
  if (!region) throw SpecError("missing required field 'region'", root.where("region"));
  s.region = read_point(*region, root.where("region"));

  const SpecObject resolution = root.object("resolution");
  const bool by_length = resolution.has("edge_length"), by_count = resolution.has("vertex_count");
  if (by_length == by_count)
    throw SpecError("give exactly one of 'edge_length' and 'vertex_count'", resolution.where());
  if (by_length) s.edge_length = resolution.required_number("edge_length", Range::between(1e-4, 1.0));
  else s.vertex_count = resolution.required_integer("vertex_count", Range::between(50, 1e7));
  resolution.finish();

  s.offset = root.number("offset", 0.0, Range::between(0.0, 0.5));
  s.offset_fillet = root.number("offset_fillet", s.offset_fillet, Range::between(0.0, 0.5));
  s.fabric_width = root.number("fabric_width", 0.0, Range::between(0.0, 10.0));
  if (const auto paint = root.optional_array("paint")) {
    for (size_t i = 0; i < paint->size(); ++i) {
      const SpecObject p = paint->object(i);
      PaintRegion r;
      r.where = p.where();
      r.name = p.string("name", "paint" + std::to_string(i));
      r.factor = p.required_number("factor", Range::between(0.01, 100.0));
      read_body_region(p, r);
      p.finish();
      s.paint.push_back(r);
    }
  }
  if (const auto grain = root.optional_array("grain")) {
    for (size_t i = 0; i < grain->size(); ++i) {
      const SpecObject g = grain->object(i);
      GrainRegion r;
      r.where = g.where();
      r.name = g.string("name", "grain" + std::to_string(i));
      // Degrees from the body's vertical: a turn beyond a quarter is the
      // same grain laid the other way up (warp and weft are both axes).
      r.angle = g.required_number("angle", Range::between(-90.0, 90.0)) * kRadiansPerDegree;
      r.on.name = r.name;
      r.on.where = r.where;
      read_body_region(g, r.on);
      g.finish();
      s.grain.push_back(r);
    }
  }
  if (root.has("fabric") && root.has("material")) {
    throw SpecError("give either 'fabric' (a fabric by name, or in full with units) or 'material' (raw cloth "
                    "parameters), not both",
                    root.where("material"));
  }
  if (const Json* fabric = root.raw("fabric")) s.material = read_fabric(*fabric, root.file(), root.pointer() + "/fabric");
  s.ease = root.number("ease", 0.0, Range::between(-0.5, 0.0));
  if (s.ease < 0.0) {
    if (!s.material.knit) {
      throw SpecError("negative ease needs a knit; the fabric '" + s.material.fabric + "' is not one",
                      root.where("ease"));
    }
    const double least = std::min(s.material.stretch_limit_warp, s.material.stretch_limit_weft);
    if (!(least > 1.0) || 1.0 + s.ease < 1.0 / least) {
      throw SpecError("ease " + std::to_string(s.ease) + " is beyond what the knit's stretch allows (at least " +
                          std::to_string(least > 1.0 ? 1.0 / least - 1.0 : 0.0) + ")",
                      root.where("ease"));
    }
  }
  if (const auto material = root.optional_object("material")) {
    s.material = read_material(*material);
    // Raw parameters are no fabric of the library: named so unless they say.
    if (!material->has("fabric")) s.material.fabric = "custom";
  }
  if (const auto smoothing = root.optional_object("smoothing")) {
    s.smoothing.smoothing_iterations = static_cast<int>(
        smoothing->integer("iterations", s.smoothing.smoothing_iterations, Range::between(0, 200)));
    s.smoothing.band_rings =
        static_cast<int>(smoothing->integer("band_rings", s.smoothing.band_rings, Range::between(1, 50)));
    smoothing->finish();
  }
  if (const auto remesh = root.optional_object("remesh")) {
    s.remesh.iterations =
        static_cast<int>(remesh->integer("iterations", s.remesh.iterations, Range::between(1, 50)));
    s.remesh.relaxation_steps = static_cast<int>(
        remesh->integer("relaxation_steps", s.remesh.relaxation_steps, Range::between(1, 20)));
    remesh->finish();
  }
  s.snap_tolerance = root.number("snap_tolerance", s.snap_tolerance, Range::positive());
  root.finish();
  return s;
}

GarmentSpec read_garment_spec(const std::filesystem::path& path) {
  return parse_garment_spec(read_json_file(path), path.string());
}

OrderedJson to_json(const GarmentSpec& s) {
  OrderedJson j;
  j["schema"] = schema_tag("garment-spec", 1);
  j["name"] = s.name;
  j["design_pose"] = s.design_pose;
  OrderedJson loops = OrderedJson::array();
  for (const auto& l : s.loops) {
    OrderedJson points = OrderedJson::array();
    for (const auto& p : l.points) points.push_back(point_json(p));
    loops.push_back({{"name", l.name}, {"pinned", l.pinned}, {"points", points}});
  }
  j["loops"] = loops;
  j["region"] = point_json(s.region);
  if (s.edge_length > 0) j["resolution"] = {{"edge_length", s.edge_length}};
  else j["resolution"] = {{"vertex_count", s.vertex_count}};
  j["offset"] = s.offset;
  j["offset_fillet"] = s.offset_fillet;
  if (s.fabric_width > 0.0) j["fabric_width"] = s.fabric_width;
  OrderedJson paint = OrderedJson::array();
  for (const auto& r : s.paint) {
    OrderedJson p;
    p["name"] = r.name;
    p["factor"] = r.factor;
    if (r.is_disc) p["disc"] = {{"center", point_json(r.center)}, {"radius", r.radius}};
    else p["vertices"] = r.vertex_ids;
    paint.push_back(p);
  }
  j["paint"] = paint;
  if (!s.grain.empty()) {
    OrderedJson grain = OrderedJson::array();
    for (const auto& g : s.grain) {
      OrderedJson r;
      r["name"] = g.name;
      r["angle"] = g.angle / kRadiansPerDegree;
      if (g.on.is_disc) r["disc"] = {{"center", point_json(g.on.center)}, {"radius", g.on.radius}};
      else r["vertices"] = g.on.vertex_ids;
      grain.push_back(r);
    }
    j["grain"] = grain;
  }
  j["ease"] = s.ease;
  j["material"] = to_json(s.material);
  j["smoothing"] = {{"iterations", s.smoothing.smoothing_iterations}, {"band_rings", s.smoothing.band_rings}};
  j["remesh"] = {{"iterations", s.remesh.iterations}, {"relaxation_steps", s.remesh.relaxation_steps}};
  j["snap_tolerance"] = s.snap_tolerance;
  return j;
}

}  // namespace gp
