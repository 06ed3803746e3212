#include "report/sewn_sheet.h"

#include <cstdio>

#include "core/error.h"
#include "io/mesh_io.h"
#include "render/png_file.h"

namespace gp::report {
namespace fs = std::filesystem;

render::ColourScale drape_distance_scale() {
  std::vector<render::ColourStop> stops = {{0.0, {0.95f, 0.95f, 0.93f}},
                                           {5.0, {0.62f, 0.80f, 0.62f}},
                                           {15.0, {0.97f, 0.61f, 0.20f}},
                                           {30.0, {0.70f, 0.06f, 0.12f}}};
  std::vector<render::ScaleTick> ticks = {{0.0, "0", false},   {5.0, "5", true},    {10.0, "10", false},
                                          {15.0, "15", true},  {20.0, "20", false}, {30.0, "30", false}};
  return render::ColourScale("distance of the sewn drape from its reference [mm], per face", std::move(stops),
                             std::move(ticks), false);
}

Eigen::VectorXd face_mean_of_vertices(const Eigen::VectorXd& vertex_values, const Eigen::MatrixXi& F) {
  Eigen::VectorXd out(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    out(f) = (vertex_values(F(f, 0)) + vertex_values(F(f, 1)) + vertex_values(F(f, 2))) / 3.0;
  return out;
}

namespace {

Eigen::MatrixXf colours_of(const Eigen::VectorXd& values, const render::ColourScale& scale) {
  Eigen::MatrixXf c(values.size(), 3);
  for (Eigen::Index f = 0; f < values.size(); ++f) {
    const render::Rgb rgb = scale.colour(values(f));
    c.row(f) << rgb.r, rgb.g, rgb.b;
  }
  return c;
}

Mesh read_garment_drape(const fs::path& path, const Eigen::MatrixXi& F) {
  if (!fs::is_regular_file(path)) throw InputError("the sewn-fit check's drape is missing", path.string());
  Mesh m = read_mesh(path).mesh;
  if (m.F != F) throw GeometryError("the drape does not have the garment's triangles", path.string());
  return m;
}

std::string mm(const Json& v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f", 1e3 * v.get<double>());
  return buf;
}

}  // namespace

std::vector<std::string> write_sewn_sheets(const FitRun& run, const PoseSet& poses, const Eigen::MatrixXi& F,
                                           const render::Font& font, const SheetOptions& sheet,
                                           const fs::path& folder) {
  std::vector<std::string> files(run.keys.size());
  const Json* keys = lookup(run.pattern, "/sewn_fit/key_poses");
  if (!keys || !keys->is_array()) return files;
  const render::ColourScale scale = drape_distance_scale();
  const render::Rgb body_grey = render::body_colour();
  const fs::path pattern_dir = run.pattern.path.parent_path();
  const bool rest_reference = [&] {
    const Json* r = lookup(run.pattern, "/sewn_fit/drape/reference");
    return r && r->is_string() && r->get<std::string>() != "the fit's verified drapes";
  }();
  for (size_t i = 0; i < run.keys.size(); ++i) {
    const Json* entry = nullptr;
    for (const Json& k : *keys)
      if (k.contains("key") && k["key"].is_number_integer() && k["key"].get<int>() == run.keys[i].key) entry = &k;
    if (!entry || !entry->contains("distance_to_verified") || !(*entry)["distance_to_verified"].is_object()) continue;
    // Settled at the pose alone from the reference (export-rest, by default)
    // where measured: the pattern's figure; else the drape after the motion.
    const bool settled = entry->contains("settled_from_reference") &&
                         (*entry)["settled_from_reference"].is_object() &&
                         (*entry)["settled_from_reference"].contains("mesh");
    const Json& motion = (*entry)["distance_to_verified"];
    const std::string in = motion.value("verified_mesh_in", std::string("fit"));
    const fs::path reference_path =
        (in == "pattern" ? pattern_dir : run.dir / "fit") / motion["verified_mesh"].get<std::string>();
    const Json& d = settled ? (*entry)["settled_from_reference"]["sewn"] : motion;
    const fs::path sewn_path =
        pattern_dir / (settled ? (*entry)["settled_from_reference"]["mesh"] : (*entry)["mesh"]).get<std::string>();
    const Mesh reference = read_garment_drape(reference_path, F);
    const Mesh sewn = read_garment_drape(sewn_path, F);
    const ScalarField* distance = find_field(sewn.vertex_fields, "distance_to_verified");
    if (!distance || distance->values.size() != sewn.V.rows())
      throw GeometryError("the sewn drape has no distance_to_verified vertex field", sewn_path.string());
    // Millimetres, per face: the same colour on both drapes marks the same cloth.
    const Eigen::MatrixXf colours = colours_of(1e3 * face_mean_of_vertices(distance->values, F), scale);
    const int body = poses.index_of(run.keys[i].pose, sewn_path.string());
    auto row = [&](const std::string& label, const Mesh& drape) {
      SheetRow r;
      r.label = label;
      r.layers.push_back(render::MeshLayer{&poses.V[static_cast<size_t>(body)], &poses.F, nullptr, nullptr, body_grey});
      r.layers.push_back(render::MeshLayer{&drape.V, &F, &colours, nullptr, {}});
      return r;
    };
    Eigen::AlignedBox3d box;
    for (const Mesh* m : {&reference, &sewn})
      for (Eigen::Index v = 0; v < m->V.rows(); ++v) box.extend(Eigen::Vector3d(m->V.row(v).transpose()));
    const std::vector<render::OrthoCamera> cameras = frame_views(box, sheet);
    const std::vector<SheetRow> rows = {
        row(rest_reference ? "the rest shape's own drape (simulated by export-rest)" : "verified (the rest shape simulated afresh)",
            reference),
        row(settled ? "sewn from the flat pattern, settled at this pose from the drape above" : "sewn from the flat pattern",
            sewn)};
    const std::vector<Views> views = render_views(rows, {cameras, cameras}, sheet);
    char id[160];
    std::snprintf(id, sizeof(id), "%02d_%s", run.keys[i].key, run.keys[i].pose.c_str());
    files[i] = "renders/sewn_" + std::string(id) + ".png";
    fs::create_directories(folder / "renders");
    const std::string title = "Key pose " + std::to_string(i + 1) + " of " + std::to_string(run.keys.size()) + ": " +
                              run.keys[i].pose + ", the sewn garment against the designed drape (mean " + mm(d["mean_m"]) +
                              ", p95 " + mm(d["p95_m"]) + ", max " + mm(d["max_m"]) + " mm)";
    render::write_png(folder / files[i],
                      compose_sheet(title, {{rows[0].label, &views[0]}, {rows[1].label, &views[1]}}, scale, font));
  }
  return files;
}

}  // namespace gp::report
