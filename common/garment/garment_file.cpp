#include "garment/garment_file.h"

#include "core/error.h"

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

}  // namespace

OrderedJson to_json(const Material& m) {
  OrderedJson j;
  j["k_stretch"] = m.k_stretch;
  j["k_shear"] = m.k_shear;
  j["k_bend"] = m.k_bend;
  j["damping_stretch"] = m.damping_stretch;
  j["damping_shear"] = m.damping_shear;
  j["damping_bend"] = m.damping_bend;
  j["density"] = m.density;
  j["compression_ratio"] = m.compression_ratio;
  return j;
}

Material read_material(const SpecObject& obj) {
  Material m;
  m.k_stretch = obj.number("k_stretch", m.k_stretch, Range::non_negative());
  m.k_shear = obj.number("k_shear", m.k_shear, Range::non_negative());
  m.k_bend = obj.number("k_bend", m.k_bend, Range::non_negative());
  m.damping_stretch = obj.number("damping_stretch", m.damping_stretch, Range::non_negative());
  m.damping_shear = obj.number("damping_shear", m.damping_shear, Range::non_negative());
  m.damping_bend = obj.number("damping_bend", m.damping_bend, Range::non_negative());
  m.density = obj.number("density", m.density, Range::positive());
  m.compression_ratio = obj.number("compression_ratio", m.compression_ratio, Range::between(1e-3, 1.0));
  obj.finish();
  return m;
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
  j["material"] = to_json(g.material);
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
  g.material = read_material(root.object("material"));
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
