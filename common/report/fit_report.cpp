#include "report/fit_report.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/base64.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "core/text_format.h"
#include "io/gltf_writer.h"
#include "io/mesh_io.h"
#include "mesh/measures.h"
#include "mesh/principal_stretches.h"
#include "pose/pose_set.h"
#include "render/colour_scale.h"
#include "render/png_file.h"
#include "render/rasterizer.h"
#include "report/html_report.h"
#include "report/report_assets.h"
#include "report/sewn_sheet.h"
#include "report/svg_to_png.h"

namespace fs = std::filesystem;

namespace gp::report {
namespace {

const char* kGenerator = "fit-report (custom-fit garment pipeline)";



// The files of three.js the page loads, by their place in the package.
const std::pair<const char*, const char*> kThreeFiles[] = {{"build/three.min.js", "three.min.js"},
                                                           {"examples/js/loaders/GLTFLoader.js", "GLTFLoader.js"},
                                                           {"examples/js/controls/OrbitControls.js", "OrbitControls.js"},
                                                           {"LICENSE", "LICENSE"}};

struct Drape {
  Eigen::MatrixXd V;           // garment on the body, #V by 3
  Eigen::VectorXd stretch;     // largest principal stretch per face
  int body_pose = 0;           // index into the pose set
};

// A draped garment and its stretch per face: the max_stretch face field that
// simulate-adapt writes, or, where the file has none, computed against `V_rest`.
Drape read_drape(const fs::path& path, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_rest) {
  MeshReadResult read = read_mesh(path);
  if (read.mesh.F != F)
    throw GeometryError("the draped garment does not have the garment's triangles", path.string());
  Drape d;
  d.V = std::move(read.mesh.V);
  if (!d.V.allFinite()) throw GeometryError("the draped garment has non-finite coordinates", path.string());
  if (const ScalarField* f = find_field(read.mesh.face_fields, "max_stretch"))
    d.stretch = f->values;
  else
    d.stretch = principal_stretches(V_rest, d.V, F).col(0);
  return d;
}

Eigen::MatrixXf face_colours(const Eigen::VectorXd& values, const render::ColourScale& scale) {
  Eigen::MatrixXf C(values.size(), 3);
  for (Eigen::Index f = 0; f < values.size(); ++f) {
    const render::Rgb c = scale.colour(values(f));
    C.row(f) << c.r, c.g, c.b;
  }
  return C;
}

// A mesh whose vertices are split per face, so that each face carries its own
// colour and value: 3 #F vertices, smooth normals of the original mesh.
GltfMesh split_by_face(const std::string& name, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                       const Eigen::VectorXd& values, const render::ColourScale& scale, const std::string& attribute) {
  const Eigen::MatrixXd N = vertex_normals(V, F);
  GltfMesh m;
  m.name = name;
  const Eigen::Index n = 3 * F.rows();
  m.V.resize(n, 3);
  m.N.resize(n, 3);
  m.colours.resize(n, 3);
  m.F.resize(F.rows(), 3);
  GltfAttribute a{attribute, Eigen::VectorXf(n)};
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const render::Rgb c = scale.colour(values(f));
    for (int k = 0; k < 3; ++k) {
      const Eigen::Index r = 3 * f + k;
      m.V.row(r) = V.row(F(f, k));
      m.N.row(r) = N.row(F(f, k));
      m.colours.row(r) << c.r, c.g, c.b;
      a.values(r) = static_cast<float>(values(f));
      m.F(f, k) = static_cast<int>(r);
    }
  }
  m.attributes.push_back(std::move(a));
  return m;
}

GltfMesh plain_mesh(const std::string& name, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, render::Rgb colour) {
  GltfMesh m;
  m.name = name;
  m.V = V;
  m.F = F;
  m.N = vertex_normals(V, F);
  m.base_colour[0] = colour.r;
  m.base_colour[1] = colour.g;
  m.base_colour[2] = colour.b;
  return m;
}

void write_text(const fs::path& path, const std::string& text) {
  write_file_atomic(path, [&](std::ostream& s) { s << text; }, false);
}

void copy_into(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (ec) throw OutputError("cannot copy " + from.string() + ": " + ec.message(), to.string());
}

Eigen::AlignedBox3d box_of(const Eigen::MatrixXd& V) {
  Eigen::AlignedBox3d b;
  for (Eigen::Index v = 0; v < V.rows(); ++v) b.extend(Eigen::Vector3d(V.row(v).transpose()));
  return b;
}

// Where the body held the cloth: the drape where the run stopped, its held
// faces in the mark colour and each holding place ringed in every view
// (drawn over the render, so that a place under the cloth still shows).
// Returns the sheet's path relative to `folder`.
std::string write_held_sheet(const HeldPose& h, const render::ColourScale& stretch, const render::Font& font,
                             const SheetOptions& sheet, const fs::path& folder) {
  const render::Rgb mark{0.85f, 0.0f, 0.85f};
  // The held run's own garment: make fit extends the design again on the
  // opened body, so its triangles may differ from the fit's.
  const Mesh held_rest = read_mesh(h.rest).mesh;
  const Drape held_drape = read_drape(h.drape, held_rest.F, held_rest.V);
  const Eigen::MatrixXi& held_F = held_rest.F;
  Eigen::MatrixXf held_colours = face_colours(held_drape.stretch, stretch);
  Eigen::AlignedBox3d box = box_of(held_drape.V);
  for (const HeldPatch& p : h.patches) {
    for (int f : p.faces)
      if (f >= 0 && f < held_F.rows()) held_colours.row(f) << mark.r, mark.g, mark.b;
    box.extend(Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
  }
  Mesh held_body;
  SheetRow row;
  row.label = h.folder == "fit" ? "where the run stopped" : "as captured, where the held run stopped (fit-held/)";
  if (!h.body.empty()) {
    held_body = read_mesh(h.body).mesh;
    row.layers.push_back(render::MeshLayer{&held_body.V, &held_body.F, nullptr, nullptr, render::body_colour()});
  }
  row.layers.push_back(render::MeshLayer{&held_drape.V, &held_F, &held_colours, nullptr, {}});
  const std::vector<render::OrthoCamera> cameras = frame_views(box, sheet);
  std::vector<Views> views = render_views({row}, {cameras}, sheet);
  const double ring = std::max(8.0, 0.025 * sheet.view_height);
  for (size_t c = 0; c < cameras.size(); ++c)
    for (const HeldPatch& p : h.patches) {
      const Eigen::Vector2d at = render::project(cameras[c], Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
      render::draw_ring(views[0][c], at.x(), at.y(), ring, std::max(2.0, 0.2 * ring), mark);
    }
  char id[160];
  std::snprintf(id, sizeof(id), "%02d_%s", h.key, h.pose.c_str());
  const std::string file = "renders/held_" + std::string(id) + ".png";
  render::write_png(folder / file,
                    compose_sheet("Where the body held the cloth: " + h.pose + " after " + std::to_string(h.settle_steps) +
                                      " settling steps (held faces and places in magenta)",
                                  {{row.label, &views[0]}}, stretch, font));
  return file;
}

// The meshes of a report: the pose set, the design, the rest shape and the
// drapes of every key pose (adapted, and as designed where fit-noadapt/ ran).
struct FitMeshes {
  PoseSet poses;
  Mesh design, rest;
  std::vector<Drape> drapes, drapes_no_adapt;
};

FitMeshes load_meshes(const FitRun& run) {
  FitMeshes m;
  m.poses = load_pose_set(run.poses_manifest);
  m.design = read_mesh(run.design_mesh).mesh;
  m.rest = read_mesh(run.rest_mesh).mesh;
  if (m.rest.F != m.design.F)
    throw GeometryError("the rest shape does not have the designed garment's triangles", run.rest_mesh.string());
  const Eigen::MatrixXi& F = m.design.F;
  auto drapes_of = [&](const std::vector<KeyPoseRun>& keys, const Eigen::MatrixXd& V_rest) {
    std::vector<Drape> out;
    for (const KeyPoseRun& k : keys) {
      Drape d = read_drape(k.shown_mesh(), F, V_rest);
      d.body_pose = m.poses.index_of(k.pose, k.shown_mesh().string());
      out.push_back(std::move(d));
    }
    return out;
  };
  m.drapes = drapes_of(run.keys, m.rest.V);
  m.drapes_no_adapt = drapes_of(run.keys_no_adapt, m.design.V);
  return m;
}

// Each face's area on the rest shape over its area on the design (1 where the design's is 0).
Eigen::VectorXd face_growth_of(const FitMeshes& m) {
  const Eigen::MatrixXi& F = m.design.F;
  const Eigen::VectorXd area_design = face_areas(m.design.V, F);
  const Eigen::VectorXd area_rest = face_areas(m.rest.V, F);
  Eigen::VectorXd face_growth(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    face_growth(f) = area_design(f) > 0.0 ? area_rest(f) / area_design(f) : 1.0;
  return face_growth;
}

// The sheet of every key pose, and its before/after sheet where fit-noadapt/
// ran: one frame for every pose, so that they compare at a glance. Fills
// files.poses.
void write_pose_sheets(const FitRun& run, const FitMeshes& m, const FitReportOptions& options,
                       const render::ColourScale& stretch, const render::Font& font, const fs::path& folder,
                       ReportFiles& files) {
  const Eigen::MatrixXi& F = m.design.F;
  const render::Rgb body_grey = render::body_colour();
  auto garment_row = [&](const std::string& label, const Drape& d, const Eigen::MatrixXf& colours) {
    SheetRow row;
    row.label = label;
    render::MeshLayer body;
    body.V = &m.poses.V[static_cast<size_t>(d.body_pose)];
    body.F = &m.poses.F;
    body.colour = body_grey;
    render::MeshLayer cloth;
    cloth.V = &d.V;
    cloth.F = &F;
    cloth.face_colours = &colours;
    row.layers = {body, cloth};
    return row;
  };
  // Every view of every pose in one parallel batch: the adapted garment's
  // views serve both its own sheet and the before/after sheet.
  const size_t n = run.keys.size();
  std::vector<Eigen::MatrixXf> colours, colours_before;
  for (const Drape& d : m.drapes) colours.push_back(face_colours(d.stretch, stretch));
  for (const Drape& d : m.drapes_no_adapt) colours_before.push_back(face_colours(d.stretch, stretch));
  // Each pose framed on its garment (with the design's drape, where there is
  // one), so that the cloth fills the views.
  std::vector<SheetRow> rows;
  std::vector<std::vector<render::OrthoCamera>> cameras;
  for (size_t i = 0; i < n; ++i) {
    Eigen::AlignedBox3d box = box_of(m.drapes[i].V);
    if (!m.drapes_no_adapt.empty()) box.extend(box_of(m.drapes_no_adapt[i].V));
    cameras.push_back(frame_views(box, options.sheet));
    rows.push_back(garment_row("adapted", m.drapes[i], colours[i]));
  }
  for (size_t i = 0; i < m.drapes_no_adapt.size(); ++i) {
    cameras.push_back(cameras[i]);
    rows.push_back(garment_row("as designed", m.drapes_no_adapt[i], colours_before[i]));
  }
  const std::vector<Views> views = render_views(rows, cameras, options.sheet);
  const std::string limit = format_fixed(1.0 + run.delta, 2);
  auto figures_of = [&](const StageReport& report, const KeyPoseRun& k) {
    const Json& e = *lookup(report, k.shown_pointer());
    return "max stretch " + format_fixed(e["max_stretch"].get<double>(), 3) + ", p99 " + format_fixed(e["p99_stretch"].get<double>(), 3) +
           ", area above " + limit + ": " + format_fixed(100.0 * e["area_fraction_above_limit"].get<double>(), 2) + " %";
  };
  for (size_t i = 0; i < n; ++i) {
    const KeyPoseRun& k = run.keys[i];
    char id[160];
    std::snprintf(id, sizeof(id), "%02d_%s", k.key, k.pose.c_str());
    ReportFiles::Pose pf;
    pf.model_id = std::string("pose_") + id;
    pf.sheet = "renders/pose_" + std::string(id) + ".png";
    pf.glb = "models/pose_" + std::string(id) + ".glb";
    const std::string title = "Key pose " + std::to_string(i + 1) + " of " + std::to_string(n) + ": " + k.pose;
    const std::string shown = k.verified_pointer.empty() ? "adapted" : "adapted, verified (simulated afresh)";
    render::write_png(folder / pf.sheet, compose_sheet(title + " (" + figures_of(run.fit, k) + ")",
                                                       {{shown, &views[i]}}, stretch, font));
    if (!m.drapes_no_adapt.empty()) {
      pf.before_after = "renders/before_after_" + std::string(id) + ".png";
      render::write_png(folder / pf.before_after,
                        compose_sheet(title + ": the design and the adapted garment",
                                      {{"as designed, not adapted: " + figures_of(*run.fit_no_adapt, run.keys_no_adapt[i]),
                                        &views[n + i]},
                                       {shown + ": " + figures_of(run.fit, k), &views[i]}},
                                      stretch, font));
    }
    files.poses.push_back(pf);
  }
}

// The rest shape off the body, against the design, at their own frame.
void write_rest_sheet(const FitMeshes& m, const Eigen::VectorXd& face_growth, const FitReportOptions& options,
                      const render::Font& font, const fs::path& folder, ReportFiles& files) {
  const Eigen::MatrixXi& F = m.design.F;
  const render::ColourScale growth = render::growth_scale();
  const Eigen::VectorXd area_design = face_areas(m.design.V, F);
  const Eigen::VectorXd area_rest = face_areas(m.rest.V, F);
  Eigen::AlignedBox3d rest_box = box_of(m.design.V);
  rest_box.extend(box_of(m.rest.V));
  const Eigen::MatrixXf rest_colours = face_colours(face_growth, growth);
  render::MeshLayer d_layer{&m.design.V, &F, nullptr, nullptr, render::Rgb{0.86f, 0.86f, 0.80f}};
  render::MeshLayer r_layer{&m.rest.V, &F, &rest_colours, nullptr, {}};
  files.rest_sheet = "renders/rest_vs_design.png";
  const double total_growth = area_rest.sum() / std::max(area_design.sum(), 1e-300);
  render::write_png(folder / files.rest_sheet,
                    picture_sheet("The rest shape against the design (area x" + format_fixed(total_growth, 3) + ")",
                                  {SheetRow{"as designed", {d_layer}}, SheetRow{"adapted rest shape", {r_layer}}},
                                  frame_views(rest_box, options.sheet), growth, font, options.sheet));
}

// glTF: body and garment per key pose (with the same bytes in base64 for the
// page, which adds their scripts to `scripts`); the rest shape and the design.
void write_models(const FitMeshes& m, const Eigen::VectorXd& face_growth, const render::ColourScale& stretch,
                  const fs::path& folder, ReportFiles& files, std::vector<std::string>& scripts) {
  const Eigen::MatrixXi& F = m.design.F;
  const render::Rgb body_grey = render::body_colour();
  for (size_t i = 0; i < files.poses.size(); ++i) {
    const Drape& d = m.drapes[i];
    const std::vector<GltfMesh> meshes = {plain_mesh("body", m.poses.V[static_cast<size_t>(d.body_pose)], m.poses.F, body_grey),
                                          split_by_face("garment", d.V, F, d.stretch, stretch, "MAX_STRETCH")};
    const std::vector<std::uint8_t> bytes = glb_bytes(meshes, kGenerator);
    const std::string& glb = files.poses[i].glb;
    write_file_atomic(folder / glb, [&](std::ostream& s) {
      s.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    });
    write_text(folder / (glb + ".js"), "(window.GP_MODELS = window.GP_MODELS || {})[\"" + files.poses[i].model_id +
                                          "\"] = \"" + base64_encode(bytes) + "\";\n");
    scripts.push_back(glb + ".js");
  }
  files.rest_glb = "models/rest_shape.glb";
  files.design_glb = "models/design.glb";
  write_glb(folder / files.rest_glb,
            {split_by_face("rest_shape", m.rest.V, F, face_growth, render::growth_scale(), "AREA_GROWTH")}, kGenerator);
  write_glb(folder / files.design_glb, {plain_mesh("design", m.design.V, F, render::Rgb{0.86f, 0.86f, 0.80f})}, kGenerator);
}

// The pattern and its picture, and the shop floor's files where export-rest
// and make-marker wrote them, copied beside the page.
void copy_pattern_files(const FitRun& run, const FitReportOptions& options, const fs::path& folder, ReportFiles& files) {
  files.pattern_svg = "pattern.svg";
  files.pattern_png = "pattern.png";
  copy_into(run.pattern_svg, folder / files.pattern_svg);
  svg_to_png(run.pattern_svg, folder / files.pattern_png, options.pattern_width);
  const std::pair<const char*, const char*> shop_files[] = {
      {"pattern/pattern.dxf", "pattern CAD (Gerber AccuMark, Lectra, Optitex, CLO): DXF, ASTM D6673 or as export-rest's --dxf-profile chose"},
      {"pattern/pattern-a4.pdf", "home printer, A4: tiled pages, cover with test square and page map"},
      {"pattern/pattern-letter.pdf", "home printer, Letter: tiled pages, 10 cm and 4 in test squares"},
      {"pattern/pattern-a0.pdf", "copy shop, A0 plotter"},
      {"pattern/pattern-roll914.pdf", "roll plotter, 914 mm"},
      {"marker/marker.pdf", "cutting table: the marker, the pieces nested on the fabric width"},
      {"marker/marker.svg", "the marker as SVG"}};
  for (const auto& [from, what] : shop_files) {
    const fs::path source = run.dir / from;
    if (!fs::is_regular_file(source)) continue;
    fs::create_directories(folder / "files");
    const std::string to = "files/" + fs::path(from).filename().string();
    copy_into(source, folder / to);
    files.downloads.push_back({to, what});
    if (fs::path(from).filename() == "marker.svg") files.marker_svg = to;
  }
}

// The garment's name on the page: the spec's name, else the fit folder's,
// with the fabric the spec chose (the paper's default is not named).
std::string page_title(const FitRun& run, FitReportResult& result) {
  std::string title = lookup(run.garment, "/options/effective_spec/name") &&
                              lookup(run.garment, "/options/effective_spec/name")->is_string()
                          ? lookup(run.garment, "/options/effective_spec/name")->get<std::string>()
                          : run.dir.filename().string();
  const Json* fabric = lookup(run.garment, "/options/effective_spec/material/fabric");
  if (fabric && fabric->is_string()) result.fabric = fabric->get<std::string>();
  if (!result.fabric.empty() && result.fabric != "paper") title += " in " + result.fabric;
  return title;
}

}  // namespace

fs::path default_three_dir() { return GP_THREE_DIR; }

FitReportResult write_fit_report(const FitRun& run, const FitReportOptions& options, const fs::path& folder) {
  FitReportResult result;
  auto t = Clock::now();
  const fs::path three = options.three_dir.empty() ? default_three_dir() : options.three_dir;
  for (const auto& [from, to] : kThreeFiles)
    if (!fs::is_regular_file(three / from))
      throw InputError("three.js is not installed (run `make deps`, which installs it from npm)", (three / from).string());
  const render::Font font(options.font.empty() ? render::default_font_path() : options.font);
  const FitMeshes meshes = load_meshes(run);
  result.load_seconds = seconds_since(t);

  t = Clock::now();
  fs::create_directories(folder / "renders");
  fs::create_directories(folder / "models");
  fs::create_directories(folder / "three");
  const render::ColourScale stretch = render::stretch_scale(run.delta);
  ReportFiles files;
  {
    std::ostringstream front;
    front << options.sheet.front.x() << "," << options.sheet.front.y() << "," << options.sheet.front.z();
    files.front = front.str();
  }
  write_pose_sheets(run, meshes, options, stretch, font, folder, files);
  if (run.held) files.held_sheet = write_held_sheet(*run.held, stretch, font, options.sheet, folder);
  const std::vector<std::string> sewn_sheets = write_sewn_sheets(run, meshes.poses, meshes.design.F, font, options.sheet, folder);
  for (size_t i = 0; i < run.keys.size(); ++i) files.poses[i].sewn_sheet = sewn_sheets[i];
  const Eigen::VectorXd face_growth = face_growth_of(meshes);
  write_rest_sheet(meshes, face_growth, options, font, folder, files);
  result.render_seconds = seconds_since(t);

  t = Clock::now();
  std::vector<std::string> scripts = {"three/three.min.js", "three/GLTFLoader.js", "three/OrbitControls.js"};
  write_models(meshes, face_growth, stretch, folder, files, scripts);
  result.model_seconds = seconds_since(t);

  t = Clock::now();
  copy_pattern_files(run, options, folder, files);
  result.pattern_seconds = seconds_since(t);

  for (const auto& [from, to] : kThreeFiles) copy_into(three / from, folder / "three" / to);
  write_text(folder / "viewer.js", viewer_js());
  write_text(folder / "timing.js", timing_script(run));
  scripts.push_back("timing.js");
  scripts.push_back("viewer.js");
  files.scripts = scripts;

  result.checks = fit_checks(run);
  write_text(folder / "index.html", html_report(run, files, result.checks, page_title(run, result)));

  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) result.files.push_back(fs::relative(entry.path(), folder).generic_string());
  std::sort(result.files.begin(), result.files.end());
  return result;
}

}  // namespace gp::report
