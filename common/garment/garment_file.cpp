#include "garment/garment_file.h"

#include <optional>

#include "core/error.h"
#include "fabric/fabric.h"
#include "fabric/fabric_units.h"

namespace gp {
namespace {

OrderedJson surface_points_json(const std::vector<SurfacePoint>& points) {
  if (points.empty()) return nullptr;
  OrderedJson faces = OrderedJson::array(), bary = OrderedJson::array();
  for (const auto& p : points) {
    faces.push_back(p.face);
    bary.push_back({p.bary[0], p.bary[1], p.bary[2]});
  }
  OrderedJson j;
  j["face_ids"] = faces;
  j["barycentric"] = bary;
  return j;
}

std::vector<SurfacePoint> read_surface_points(const SpecObject& parent, const std::string& key,
                                              long long n_faces) {
  const Json* raw = parent.raw(key);
  if (!raw) throw SpecError("missing required field '" + key + "'", parent.where(key));
  if (raw->is_null()) return {};
  const SpecObject obj(*raw, parent.file(), parent.pointer() + "/" + key);
  const Json* faces = obj.raw("face_ids");
  const Json* bary = obj.raw("barycentric");
  if (!faces || !faces->is_array()) throw SpecError("expected an array of face ids", obj.where("face_ids"));
  if (!bary || !bary->is_array()) throw SpecError("expected an array of [a, b, c]", obj.where("barycentric"));
  if (faces->size() != bary->size())
    throw SpecError("face_ids and barycentric differ in length", obj.where("barycentric"));
  obj.finish();
  std::vector<SurfacePoint> points(faces->size());
  for (size_t i = 0; i < faces->size(); ++i) {
    const Json& f = (*faces)[i];
    if (!f.is_number_integer() || f.get<long long>() < 0 || f.get<long long>() >= n_faces)
      throw SpecError("expected a body face id in [0, " + std::to_string(n_faces) + ")",
                      obj.where("face_ids") + "/" + std::to_string(i));
    const Json& b = (*bary)[i];
    if (!b.is_array() || b.size() != 3 || !b[0].is_number() || !b[1].is_number() || !b[2].is_number())
      throw SpecError("expected three numbers", obj.where("barycentric") + "/" + std::to_string(i));
    points[i].face = f.get<int>();
    points[i].bary = {b[0].get<double>(), b[1].get<double>(), b[2].get<double>()};
  }
  return points;
}


Material material_of(const fabric::Fabric& f) {
  Material m;
  m.fabric = f.name;
  m.k_stretch = f.k_warp;
  m.k_stretch_weft = f.k_weft;
  m.k_shear = f.k_shear;
  m.k_bend = f.k_bend;
  m.damping_stretch = f.damping_stretch;
  m.damping_shear = f.damping_shear;
  m.damping_bend = f.damping_bend;
  m.density = f.areal_density;
  m.compression_ratio = f.compression_ratio;
  m.thickness = f.thickness;
  m.knit = f.knit;
  m.stretch_limit_warp = f.limit_warp;
  m.stretch_limit_weft = f.limit_weft;
  return m;
}

}  // namespace

bool Material::turned_grain() const {
  for (double a : grain_angles)
    if (a != 0.0) return true;
  return false;
}

double contact_thickness(const Material& m) { return m.thickness > 0.0 ? m.thickness : kDefaultContactThickness; }

OrderedJson to_json(const Material& m) {
  OrderedJson j;
  j["fabric"] = m.fabric;
  j["k_stretch"] = m.k_stretch;
  j["k_stretch_weft"] = m.k_stretch_weft;
  j["k_shear"] = m.k_shear;
  j["k_bend"] = m.k_bend;
  j["damping_stretch"] = m.damping_stretch;
  j["damping_shear"] = m.damping_shear;
  j["damping_bend"] = m.damping_bend;
  j["density"] = m.density;
  j["compression_ratio"] = m.compression_ratio;
  j["thickness"] = m.thickness;
  j["knit"] = m.knit;
  j["stretch_limit_warp"] = m.stretch_limit_warp;
  j["stretch_limit_weft"] = m.stretch_limit_weft;
  return j;
}

Material read_material(const SpecObject& obj) {
  Material m;
  m.fabric = obj.string("fabric", m.fabric);
  m.k_stretch = obj.number("k_stretch", m.k_stretch, Range::non_negative());
  // An isotropic material by default: the weft as stiff as the warp.
  m.k_stretch_weft = obj.number("k_stretch_weft", m.k_stretch, Range::non_negative());
  m.k_shear = obj.number("k_shear", m.k_shear, Range::non_negative());
  m.k_bend = obj.number("k_bend", m.k_bend, Range::non_negative());
  m.damping_stretch = obj.number("damping_stretch", m.damping_stretch, Range::non_negative());
  m.damping_shear = obj.number("damping_shear", m.damping_shear, Range::non_negative());
  m.damping_bend = obj.number("damping_bend", m.damping_bend, Range::non_negative());
  m.density = obj.number("density", m.density, Range::positive());
  m.compression_ratio = obj.number("compression_ratio", m.compression_ratio, Range::between(1e-3, 1.0));
  m.thickness = obj.number("thickness", m.thickness, Range::non_negative());
  m.knit = obj.boolean("knit", m.knit);
  m.stretch_limit_warp = obj.number("stretch_limit_warp", m.stretch_limit_warp, Range::between(0.0, 3.0));
  m.stretch_limit_weft = obj.number("stretch_limit_weft", m.stretch_limit_weft, Range::between(0.0, 3.0));
  obj.finish();
  if ((m.stretch_limit_warp == 0.0) != (m.stretch_limit_weft == 0.0) ||
      (m.has_own_limits() && (m.stretch_limit_warp < 1.0 || m.stretch_limit_weft < 1.0))) {
    throw SpecError("stretch limits must both be stretch ratios of at least 1, or both 0 (the fit's delta)",
                    obj.where("stretch_limit_warp"));
  }
  if (m.k_stretch_weft != m.k_stretch && !(m.k_stretch > 0.0)) {
    throw SpecError("a weft stiffness needs a positive warp stiffness", obj.where("k_stretch"));
  }
  return m;
}

Material read_fabric(const Json& value, const std::string& file, const std::string& pointer) {
  const std::string where = file + ": " + (pointer.empty() ? "/" : pointer);
  if (value.is_string()) {
    const std::string name = value.get<std::string>();
    const fabric::Fabric* f = fabric::find_fabric(name);
    if (!f) throw SpecError("unknown fabric '" + name + "' (known: " + fabric::fabric_names() + ")", where);
    return material_of(*f);
  }
  if (!value.is_object()) {
    throw SpecError("expected a fabric name or an object with its values and units, got " + json_type_name(value),
                    where);
  }
  const SpecObject obj(value, file, pointer);
  fabric::Fabric f;
  f.name = obj.required_string("name");
  if (fabric::find_fabric(f.name)) {
    throw SpecError("a fabric given in full needs a name of its own, '" + f.name + "' is the library's",
                    obj.where("name"));
  }
  f.description = obj.string("description", "");
  f.source = obj.string("source", "the garment spec");
  f.knit = obj.boolean("knit", false);
  auto quantity = [&](const char* key, fabric::Dimension d, std::optional<double> fallback) {
    const Json* raw = obj.raw(key);
    if (!raw) {
      if (fallback) return *fallback;
      throw SpecError(std::string("missing required field '") + key + "'", obj.where(key));
    }
    if (!raw->is_string()) {
      throw SpecError("expected \"<number> <unit>\" (e.g. \"" + std::string("1 ") + fabric::unit_names(d)[0] +
                          "\"), got " + json_type_name(*raw),
                      obj.where(key));
    }
    try {
      return fabric::parse_quantity(raw->get<std::string>(), d);
    } catch (const SpecError& e) {
      throw SpecError(e.what(), obj.where(key));
    }
  };
  using fabric::Dimension;
  f.areal_density = quantity("areal_density", Dimension::areal_density, {});
  f.thickness = quantity("thickness", Dimension::length, 0.0);
  f.k_warp = quantity("k_warp", Dimension::tension, {});
  f.k_weft = quantity("k_weft", Dimension::tension, {});
  f.k_shear = quantity("k_shear", Dimension::tension, {});
  f.k_bend = quantity("k_bend", Dimension::bending, {});
  f.damping_stretch = quantity("damping_stretch", Dimension::damping_tension, f.damping_stretch);
  f.damping_shear = quantity("damping_shear", Dimension::damping_tension, f.damping_shear);
  f.damping_bend = quantity("damping_bend", Dimension::damping_bending, f.damping_bend);
  f.limit_warp = obj.required_number("limit_warp", Range::between(1.0, 3.0));
  f.limit_weft = obj.required_number("limit_weft", Range::between(1.0, 3.0));
  f.compression_ratio = obj.number("compression_ratio", f.compression_ratio, Range::between(1e-3, 1.0));
  obj.finish();
  fabric::check_fabric(f, obj.where());
  return material_of(f);
}

int GarmentFile::find_loop(const std::string& loop_name) const {
  for (size_t i = 0; i < loops.size(); ++i)
    if (loops[i].name == loop_name) return static_cast<int>(i);
  return -1;
}

OrderedJson to_json(const GarmentFile& g) {
  OrderedJson j;
  j["schema"] = schema_tag("garment", 1);
  j["name"] = g.name;
  j["units"] = "m";
  j["mesh"] = {{"file", g.mesh_file},
               {"sha256", g.mesh_sha256},
               {"vertex_count", g.vertex_count},
               {"face_count", g.face_count}};
  j["body"] = {{"source", g.body.source},
               {"source_sha256", g.body.source_sha256},
               {"design_pose", g.body.design_pose},
               {"vertex_count", g.body.vertex_count},
               {"face_count", g.body.face_count},
               {"topology_sha256", g.body.topology_sha256}};
  if (!g.body.design_pose_sha256.empty()) j["body"]["design_pose_sha256"] = g.body.design_pose_sha256;
  j["spec"] = {{"file", g.spec_file}, {"sha256", g.spec_sha256}};
  j["target_edge_length"] = g.target_edge_length;
  j["offset"] = g.offset;
  OrderedJson loops = OrderedJson::array();
  for (const auto& loop : g.loops) {
    OrderedJson l;
    l["name"] = loop.name;
    l["pinned"] = loop.pinned;
    l["vertex_ids"] = loop.vertex_ids;
    l["binding"] = surface_points_json(loop.binding);
    l["curve"] = surface_points_json(loop.curve);
    loops.push_back(l);
  }
  j["loops"] = loops;
  j["paint"] = g.paint;
  j["ease"] = g.ease;
  j["material"] = to_json(g.material);
  // Written only where a face is turned, so that a garment laid on the
  // straight grain (every garment before grain regions) has the same file.
  if (g.material.turned_grain()) {
    OrderedJson grain = OrderedJson::array();
    for (double a : g.material.grain_angles) grain.push_back(a / kRadiansPerDegree);
    j["grain"] = grain;
  }
  OrderedJson ext = OrderedJson::array();
  for (const auto& e : g.extensions)
    ext.push_back({{"loop", e.loop}, {"distance", e.distance}, {"scale", e.scale}, {"girth", e.girth}});
  j["extensions"] = ext;
  return j;
}

GarmentFile read_garment_file(const std::filesystem::path& path) {
  const Json j = read_json_file(path);
  const std::string file = path.string();
  check_schema(j, "garment", {1}, file);
  const SpecObject root(j, file);
  root.allow("schema");
  GarmentFile g;
  g.name = root.required_string("name");
  if (root.required_string("units") != "m") throw SpecError("units must be \"m\"", root.where("units"));
  const SpecObject mesh = root.object("mesh");
  g.mesh_file = mesh.required_string("file");
  g.mesh_sha256 = mesh.required_string("sha256");
  g.vertex_count = mesh.required_integer("vertex_count", Range::non_negative());
  g.face_count = mesh.required_integer("face_count", Range::non_negative());
  mesh.finish();
  const SpecObject body = root.object("body");
  g.body.source = body.required_string("source");
  g.body.source_sha256 = body.required_string("source_sha256");
  g.body.design_pose = body.required_string("design_pose");
  g.body.vertex_count = body.required_integer("vertex_count", Range::non_negative());
  g.body.face_count = body.required_integer("face_count", Range::non_negative());
  g.body.topology_sha256 = body.required_string("topology_sha256");
  g.body.design_pose_sha256 = body.string("design_pose_sha256", "");
  body.finish();
  const SpecObject spec = root.object("spec");
  g.spec_file = spec.required_string("file");
  g.spec_sha256 = spec.required_string("sha256");
  spec.finish();
  g.target_edge_length = root.required_number("target_edge_length", Range::positive());
  g.offset = root.required_number("offset", Range::non_negative());
  const SpecArray loops = root.array("loops");
  for (size_t i = 0; i < loops.size(); ++i) {
    const SpecObject l = loops.object(i);
    GarmentLoop loop;
    loop.name = l.required_string("name");
    loop.pinned = l.boolean("pinned", false);
    const Json* ids = l.raw("vertex_ids");
    if (!ids || !ids->is_array() || ids->size() < 3)
      throw SpecError("expected an array of at least three garment vertex ids", l.where("vertex_ids"));
    for (size_t k = 0; k < ids->size(); ++k) {
      const Json& v = (*ids)[k];
      if (!v.is_number_integer() || v.get<long long>() < 0 || v.get<long long>() >= g.vertex_count)
        throw SpecError("expected a garment vertex id in [0, " + std::to_string(g.vertex_count) + ")",
                        l.where("vertex_ids") + "/" + std::to_string(k));
      loop.vertex_ids.push_back(v.get<int>());
    }
    loop.binding = read_surface_points(l, "binding", g.body.face_count);
    if (!loop.binding.empty() && loop.binding.size() != loop.vertex_ids.size())
      throw SpecError("binding needs one entry per vertex id", l.where("binding"));
    loop.curve = read_surface_points(l, "curve", g.body.face_count);
    if (loop.pinned && loop.binding.empty())
      throw SpecError("a pinned loop needs a binding to the body", l.where("pinned"));
    l.finish();
    g.loops.push_back(loop);
  }
  const Json* paint = root.raw("paint");
  if (!paint || !paint->is_array() || static_cast<long long>(paint->size()) != g.face_count)
    throw SpecError("expected one paint factor per garment face (" + std::to_string(g.face_count) + ")",
                    root.where("paint"));
  for (size_t f = 0; f < paint->size(); ++f) {
    if (!(*paint)[f].is_number() || !((*paint)[f].get<double>() > 0))
      throw SpecError("expected a positive number", root.where("paint") + "/" + std::to_string(f));
    g.paint.push_back((*paint)[f].get<double>());
  }
  g.ease = root.number("ease", 0.0, Range::between(-0.5, 0.0));
  g.material = read_material(root.object("material"));
  if (const Json* grain = root.raw("grain")) {
    if (!grain->is_array() || static_cast<long long>(grain->size()) != g.face_count)
      throw SpecError("expected one grain angle per garment face (" + std::to_string(g.face_count) + ")",
                      root.where("grain"));
    for (size_t f = 0; f < grain->size(); ++f) {
      const Json& a = (*grain)[f];
      if (!a.is_number() || !(a.get<double>() >= -90.0 && a.get<double>() <= 90.0))
        throw SpecError("expected an angle in degrees within [-90, 90]", root.where("grain") + "/" + std::to_string(f));
      g.material.grain_angles.push_back(a.get<double>() * kRadiansPerDegree);
    }
  }
  const SpecArray ext = root.array("extensions");
  for (size_t i = 0; i < ext.size(); ++i) {
    const SpecObject e = ext.object(i);
    g.extensions.push_back({e.required_string("loop"), e.required_number("distance"),
                            e.required_number("scale", Range::positive()),
                            e.required_number("girth", Range::non_negative())});
    e.finish();
  }
  root.finish();
  return g;
}

void write_garment_file(const std::filesystem::path& path, const GarmentFile& garment) {
  write_json_file(path, to_json(garment));
}

Eigen::Vector3d evaluate_binding(const Eigen::MatrixXd& V, const Eigen::MatrixXd& N,
                                 const Eigen::MatrixXi& F, const SurfacePoint& p, double offset) {
  return evaluate(V, F, p) + offset * evaluate_normal(N, F, p);
}

}  // namespace gp
