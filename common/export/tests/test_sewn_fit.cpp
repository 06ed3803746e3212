// The sewn-fit check on a small generated scene: a cap pinned around a
// sphere body in two poses (a, and b 1 % larger). The cap is doubly curved,
// so its pattern has darts or seams; sewn back from its flat pieces it must
// fit both poses as its rest shape does, and a pattern shrunk by 5 % must
// not: export-rest exits 8 and names the pose and the piece.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

#include <Eigen/Geometry>

#include "adapt/garment_fit.h"
#include "core/error.h"
#include "core/sha256.h"
#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "mesh/topology.h"
#include "export/fit_settings.h"
#include "pattern/layout.h"
#include "pattern/make_pattern.h"
#include "export/sewn_fit.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "spec/option_fields.h"
#include "testing/command.h"
#include "testing/files.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using namespace gp;

namespace {

struct CapScene {
  fs::path dir;
  PoseSet poses;
  GarmentFile garment;
  Mesh cap;
};

// poses.json (pose "a": an icosphere of radius 0.2 m; "b": the same 1 %
// larger), motion.json (a -> b), garment.json and garment.ply: the body's
// faces above y = 0.1 at the comfort offset (1 cm), its rim pinned.
CapScene write_cap_scene(const std::string& name) {
  CapScene s;
  s.dir = testing::fresh_temp_dir(name);
  const double r = 0.2, offset = 0.01;
  const Mesh body = testing::make_icosphere(3, r);
  write_mesh(s.dir / "a.ply", body);
  PoseSetManifest manifest;
  manifest.vertex_count = body.V.rows();
  manifest.face_count = body.F.rows();
  manifest.topology_sha256 = topology_checksum(body.F);
  manifest.reference = "a";
  Mesh grown = body;
  grown.V *= 1.01;  // pose b: the body 1 % larger, so that the cloth moves between the key poses
  write_mesh(s.dir / "b.ply", grown);
  manifest.poses = {{"a", "a.ply", sha256_file_hex(s.dir / "a.ply"), "test"},
                    {"b", "b.ply", sha256_file_hex(s.dir / "b.ply"), "test"}};
  write_pose_set_manifest(s.dir / "poses.json", manifest);
  s.poses = load_pose_set(s.dir / "poses.json");

  std::vector<int> cap_faces;
  for (int f = 0; f < body.F.rows(); ++f) {
    bool above = true;
    for (int k = 0; k < 3; ++k) above = above && body.V(body.F(f, k), 1) > 0.1;
    if (above) cap_faces.push_back(f);
  }
  const gp::testing::SubMesh sub = gp::testing::face_subset(body, cap_faces);
  s.cap = sub.mesh;
  s.cap.V *= (r + offset) / r;
  write_mesh(s.dir / "garment.ply", s.cap);

  GarmentFile& g = s.garment;
  g.name = "cap";
  g.mesh_file = "garment.ply";
  g.mesh_sha256 = sha256_file_hex(s.dir / "garment.ply");
  g.vertex_count = s.cap.V.rows();
  g.face_count = s.cap.F.rows();
  g.body.source = "poses.json";
  g.body.source_sha256 = sha256_file_hex(s.dir / "poses.json");
  g.body.design_pose = "a";
  g.body.vertex_count = body.V.rows();
  g.body.face_count = body.F.rows();
  g.body.topology_sha256 = manifest.topology_sha256;
  g.spec_file = "none";
  g.spec_sha256 = "none";
  g.target_edge_length = 0.05;
  g.offset = offset;
  const std::vector<std::vector<int>> loops = boundary_loops(s.cap.F);
  REQUIRE(loops.size() == 1);
  GarmentLoop loop;
  loop.name = "rim";
  loop.pinned = true;
  const std::vector<std::vector<int>> incident = vertex_faces(body.F, static_cast<int>(body.V.rows()));
  for (int v : loops[0]) {
    loop.vertex_ids.push_back(v);
    const int b = sub.vertex_ids[static_cast<size_t>(v)];
    SurfacePoint p;
    p.face = incident[static_cast<size_t>(b)][0];
    for (int k = 0; k < 3; ++k) p.bary(k) = body.F(p.face, k) == b ? 1.0 : 0.0;
    loop.binding.push_back(p);
  }
  g.loops.push_back(loop);
  g.paint.assign(static_cast<size_t>(s.cap.F.rows()), 1.0);
  write_garment_file(s.dir / "garment.json", g);
  write_json_file(s.dir / "motion.json", {{"schema", "motion/1"}, {"steps", 10}, {"sequence", {"a", "b"}}});
  return s;
}

// The fit of the cap through a -> b without adaptation (its rest shape is the
// design), with a stretch limit of 1.04: simulate-adapt's report, which the
// sewn-fit check takes its settings from.
// flags: more of simulate-adapt's (" --no-verify"); folder: its output's name.
fs::path write_fit_report(const CapScene& s, const std::string& flags = "", const std::string& folder = "fit") {
  const auto run = testing::run_command(
      testing::tool_path("simulate-adapt") + " --no-adapt --delta 0.04 --workers 1 -q --poses " +
      (s.dir / "poses.json").string() + " --motion " + (s.dir / "motion.json").string() + " --garment " +
      (s.dir / "garment.json").string() + flags + " --out " + (s.dir / folder).string());
  INFO(run.err);
  REQUIRE((run.exit_code == 0 || run.exit_code == 8));
  return s.dir / folder / "report.json";
}

// export-rest on `rest_mesh` of scene s with the fit report `fit`, into s.dir / out.
testing::CommandResult export_with_fit(const CapScene& s, const fs::path& fit, const fs::path& rest_mesh,
                                       const std::string& out, const std::string& flags = "") {
  return testing::run_command(testing::tool_path("export-rest") + " --garment " + (s.dir / "garment.json").string() +
                              " -q --fit " + fit.string() + flags + " " + rest_mesh.string() + " --out " +
                              (s.dir / out).string());
}

// The cap shrunk by 5 % about its centroid (every flat piece 5 % too small), written as shrunk.ply.
fs::path write_shrunk_cap(const CapScene& s) {
  Mesh shrunk = s.cap;
  const Eigen::RowVector3d centre = shrunk.V.colwise().mean();
  shrunk.V = ((shrunk.V.rowwise() - centre) * 0.95).rowwise() + centre;
  write_mesh(s.dir / "shrunk.ply", shrunk);
  return s.dir / "shrunk.ply";
}

}  // namespace

TEST_CASE("the sewn triangles are the flat pieces' and cover every rest face", "[sewn_fit]") {
  const CapScene s = write_cap_scene("sewn-fit-triangles");
  const Pattern pattern = make_pattern(s.cap.V, s.cap.F, {}, PatternOptions{});
  REQUIRE(pattern.pieces.size() >= 1);
  CHECK(pattern.seams.size() >= 1);  // doubly curved: darts or seams
  const Layout layout = layout_pattern(pattern, LayoutOptions{});
  // A rest face that a cut splits has its parts' mean metric: about the flattening's area.
  const auto sewn = sewn_rest_triangles(pattern, layout, static_cast<int>(s.cap.F.rows()));
  double flat_area = 0.0, piece_area = 0.0;
  for (const auto& t : sewn) flat_area += t.area;
  for (const auto& p : pattern.pieces) piece_area += p.flat.stats.area_2d;
  CHECK(flat_area == Approx(piece_area).epsilon(1e-3));
  // Every rest face and vertex is in a piece.
  for (int c : piece_of_rest_face(pattern)) CHECK((c >= 0 && c < static_cast<int>(pattern.pieces.size())));
  for (int c : piece_of_rest_vertex(pattern)) CHECK((c >= 0 && c < static_cast<int>(pattern.pieces.size())));
  CHECK_THROWS_AS(sewn_rest_triangles(pattern, layout, static_cast<int>(s.cap.F.rows()) + 1), GeometryError);

  // A face whose flat triangle is squeezed to a segment (one corner moved
  // onto the middle of the opposite side) keeps its rest shape's triangle.
  std::vector<int> parts(static_cast<size_t>(s.cap.F.rows()), 0);
  for (int g = 0; g < pattern.mesh.F.rows(); ++g) ++parts[static_cast<size_t>(pattern.mesh.rest_face[static_cast<size_t>(g)])];
  int g = 0;
  while (parts[static_cast<size_t>(pattern.mesh.rest_face[static_cast<size_t>(g)])] != 1) ++g;
  const int f = pattern.mesh.rest_face[static_cast<size_t>(g)];
  const int c = pattern.piece_of_face[static_cast<size_t>(g)];
  const PatternPiece& piece = pattern.pieces[static_cast<size_t>(c)];
  const int local = static_cast<int>(std::find(piece.face_ids.begin(), piece.face_ids.end(), g) - piece.face_ids.begin());
  Layout squeezed = layout;
  Eigen::MatrixXd& UV = squeezed.pieces[static_cast<size_t>(c)].UV;
  UV.row(piece.F(local, 2)) = 0.5 * (UV.row(piece.F(local, 0)) + UV.row(piece.F(local, 1)));
  CHECK_NOTHROW(sewn_rest_triangles(pattern, squeezed, static_cast<int>(s.cap.F.rows())));
  std::vector<int> from_rest;
  const auto kept = sewn_rest_triangles(pattern, squeezed, static_cast<int>(s.cap.F.rows()), &from_rest);
  CHECK(std::find(from_rest.begin(), from_rest.end(), f) != from_rest.end());
  const Eigen::Vector3d a = s.cap.V.row(s.cap.F(f, 0)), b = s.cap.V.row(s.cap.F(f, 1)), d = s.cap.V.row(s.cap.F(f, 2));
  CHECK(kept[static_cast<size_t>(f)].area == Approx(0.5 * (b - a).cross(d - a).norm()).epsilon(1e-9));
  std::vector<int> none;
  sewn_rest_triangles(pattern, layout, static_cast<int>(s.cap.F.rows()), &none);
  CHECK(none.empty());
}

TEST_CASE("the sewn-fit check passes a good pattern and fails one shrunk by 5 %", "[sewn_fit][cli]") {
  const CapScene s = write_cap_scene("sewn-fit-cli");
  const fs::path fit = write_fit_report(s);
  const FitSettings settings = read_fit_settings(fit);
  CHECK(settings.delta() == 0.04);
  CHECK(!settings.run.adaptation.enabled);
  const std::string base = testing::tool_path("export-rest") + " --garment " + (s.dir / "garment.json").string() +
                           " -q --fit " + fit.string();

  // The design as rest shape: its pattern sewn back fits both poses.
  const auto good = testing::run_command(base + " " + (s.dir / "garment.ply").string() + " --out " +
                                         (s.dir / "good").string());
  INFO(good.err);
  REQUIRE(good.exit_code == 0);
  const Json report = read_json_file(s.dir / "good" / "report.json");
  const Json& sewn = report["sewn_fit"];
  CHECK(sewn["checked"] == true);
  CHECK(sewn["verdict"] == "pass");
  CHECK(sewn["delta"] == 0.04);
  REQUIRE(sewn["key_poses"].size() == 2);
  for (size_t i = 0; i < 2; ++i) {
    const Json& k = sewn["key_poses"][i];
    INFO("pose " << k["pose"] << " p99 " << k["p99_stretch"] << " max " << k["max_stretch"] << " above "
                 << k["area_fraction_above_limit"]);
    CHECK(k["verdict"] == "pass");
    CHECK(k["p99_stretch"].get<double>() < 1.06);
    CHECK(k["p99_stretch"].get<double>() > 0.95);
    CHECK(fs::exists(s.dir / "good" / k["mesh"].get<std::string>()));
  }
  CHECK(sewn["key_poses"][0]["pose"] == "a");
  CHECK(sewn["key_poses"][1]["pose"] == "b");
  // The pattern cut within its limit by default (the limit weighting) sews
  // into a garment that fails pose b at this fit's tight delta (4 %): the
  // stage keeps the plain cut, whose garment passes, and says why.
  CHECK(report["cut"]["plain_after_sewn_fit"] == true);
  CHECK(report["cut"]["because"].get<std::string>().find("key pose 1 (b)") != std::string::npos);
  CHECK(report["cut"]["because"].get<std::string>().find("the plain cut's garment passes") != std::string::npos);
  CHECK(report["options"]["pattern"]["flatten"]["limit_rounds"] == 0);
  {
    const auto plain_only = testing::run_command(base + " " + (s.dir / "garment.ply").string() +
                                                    " --out " + (s.dir / "plain-cut").string() +
                                                    " --limit-rounds 0 --min-relief-share 0");
    INFO(plain_only.err);
    CHECK(plain_only.exit_code == 0);
    const Json plain_cut = read_json_file(s.dir / "plain-cut" / "report.json");
    CHECK(plain_cut["cut"]["plain_after_sewn_fit"] == false);
    CHECK(plain_cut["summary"] == report["summary"]);  // the same cut the fallback made
  }
  // The sewn drape against the fit's drape of the same rest shape (the
  // design here): both measured, and the pattern of an undistorted cap
  // drapes within a few millimetres of it.
  REQUIRE(sewn["drape"]["measured"] == true);
  CHECK(sewn["drape"]["verdict"] == "pass");
  // Unbounded by default (sewn_fit.h, DrapeCriteria), the figures measured.
  CHECK(sewn["drape"]["criteria"]["max_mean_m"] == 0.0);
  CHECK(sewn["drape"]["criteria"]["max_p95_m"] == 0.0);
  for (const Json& k : sewn["key_poses"]) {
    const Json& d = k["distance_to_verified"];
    INFO("pose " << k["pose"] << " mean " << d["mean_m"] << " p95 " << d["p95_m"] << " max " << d["max_m"]);
    CHECK(d["verdict"] == "pass");
    CHECK(d["mean_m"].get<double>() > 0.0);
    CHECK(d["mean_m"].get<double>() < 0.003);
    CHECK(d["p95_m"].get<double>() >= d["mean_m"].get<double>() * 0.5);
    CHECK(d["max_m"].get<double>() >= d["p95_m"].get<double>());
    CHECK(d["drape_area_ratio"].get<double>() == Approx(1.0).margin(0.03));
  }
  {
    const MeshReadResult drape = read_mesh(s.dir / "good" / "sewn_01_b.ply");
    const ScalarField* dist = find_field(drape.mesh.vertex_fields, "distance_to_verified");
    REQUIRE(dist != nullptr);
    CHECK(dist->values.maxCoeff() == Approx(sewn["key_poses"][1]["distance_to_verified"]["max_m"].get<double>()));
  }
  // A drape bound tighter than any pattern meets: exit 8, the pose named.
  const auto tight = testing::run_command(base + " --drape-mean-limit 1e-7 " + (s.dir / "garment.ply").string() +
                                          " --out " + (s.dir / "tight").string());
  INFO(tight.err);
  CHECK(tight.exit_code == 8);
  CHECK(tight.err.find("mean distance to the verified drape") != std::string::npos);
  CHECK(read_json_file(s.dir / "tight" / "report.json")["sewn_fit"]["drape"]["verdict"] == "fail");
  // Same inputs, same outputs.
  const auto again = testing::run_command(base + " " + (s.dir / "garment.ply").string() + " --out " +
                                          (s.dir / "again").string());
  REQUIRE(again.exit_code == 0);
  for (const char* name : {"report.json", "sewn_01_b.ply"})
    CHECK(testing::read_file(s.dir / "good" / name) == testing::read_file(s.dir / "again" / name));

  // The rest shape shrunk by 5 % about its centroid: every flat piece is 5 %
  // too small, and sewn it stretches over the body beyond 1.04.
  const auto bad = export_with_fit(s, fit, write_shrunk_cap(s), "bad");
  INFO(bad.err);
  CHECK(bad.exit_code == 8);
  CHECK(bad.err.find("error[check]") != std::string::npos);
  CHECK(bad.err.find("key pose 0 (a)") != std::string::npos);
  const Json failed = read_json_file(s.dir / "bad" / "report.json")["sewn_fit"];
  CHECK(failed["verdict"] == "fail");
  for (const Json& k : failed["key_poses"]) {
    INFO("pose " << k["pose"] << " p99 " << k["p99_stretch"] << " above " << k["area_fraction_above_limit"]);
    CHECK(k["verdict"] == "fail");
    CHECK(k["area_fraction_above_limit"].get<double>() > 0.5);
    REQUIRE(!k["where"]["pieces_above_limit"].empty());
    CHECK(k["where"]["pieces_above_limit"][0]["piece"].is_string());
  }
  CHECK(failed["failure"].get<std::string>().find("worst in") != std::string::npos);
  CHECK(fs::exists(s.dir / "bad" / "pattern.svg"));  // the pattern is still written

  // Without --fit: not checked; and --fit needs the garment file.
  const auto plain = testing::run_command(testing::tool_path("export-rest") + " " + (s.dir / "garment.ply").string() +
                                          " --garment " + (s.dir / "garment.json").string() + " -q --out " +
                                          (s.dir / "plain").string());
  REQUIRE(plain.exit_code == 0);
  CHECK(read_json_file(s.dir / "plain" / "report.json")["sewn_fit"]["checked"] == false);
  const auto no_garment = testing::run_command(testing::tool_path("export-rest") + " " +
                                               (s.dir / "garment.ply").string() + " -q --fit " + fit.string() +
                                               " --out " + (s.dir / "x").string());
  CHECK(no_garment.exit_code == 2);
  CHECK(no_garment.err.find("--fit") != std::string::npos);
}

TEST_CASE("the sewn drape against the rest shape's own drape: close when the pattern is true, far when eased 10 %",
          "[sewn_fit][cli]") {
  const CapScene s = write_cap_scene("sewn-fit-reference");
  // A fit without verification names no drape of its rest shape: export-rest
  // simulates the rest shape itself, with the fit's settings, as the reference.
  const fs::path fit = write_fit_report(s, " --no-verify");
  REQUIRE(read_fit_settings(fit).verified.empty());
  const std::string base = testing::tool_path("export-rest") + " --garment " + (s.dir / "garment.json").string() +
                           " -q --fit " + fit.string() + " --drape-after-motion --drape-mean-limit 0.005 --drape-p95-limit 0.015 ";

  const auto good = testing::run_command(base + (s.dir / "garment.ply").string() + " --out " + (s.dir / "good").string());
  INFO(good.err);
  REQUIRE(good.exit_code == 0);
  const Json sewn = read_json_file(s.dir / "good" / "report.json")["sewn_fit"];
  REQUIRE(sewn["drape"]["measured"] == true);
  CHECK(sewn["drape"]["reference"] == "the rest shape simulated by export-rest");
  CHECK(sewn["drape"]["verdict"] == "pass");
  CHECK(sewn["drape"]["criteria"]["max_mean_m"] == 0.005);
  for (const Json& k : sewn["key_poses"]) {
    const Json& d = k["distance_to_verified"];
    INFO("pose " << k["pose"] << " mean " << d["mean_m"] << " p95 " << d["p95_m"] << " max " << d["max_m"]);
    CHECK(d["verified_mesh_in"] == "pattern");
    CHECK(fs::exists(s.dir / "good" / d["verified_mesh"].get<std::string>()));
    // The cap's pattern (darts on a sphere) is within its limit: its drape
    // lies within a millimetre of the rest shape's.
    CHECK(d["mean_m"].get<double>() < 0.001);
    CHECK(d["p95_m"].get<double>() < 0.002);
    // The sewn garment's own stretch figures beside its reference's: the
    // flattening's distortion (about 1 %) shows in the p99.
    CHECK(k["reference"]["p99_stretch"].get<double>() == Approx(k["p99_stretch"].get<double>()).margin(0.02));
    CHECK(k["area_fraction_above_limit"].is_number());
  }

  // The eased pattern of the next test, through the stage: the rest shape
  // eased by 10 % about its centroid (every piece 10 % too large) against
  // the drapes of a fit of the design with verification. It passes the
  // stretch bounds (it is loose, not tight) but hangs away from the designed
  // drape: exit 8, the drape named.
  Mesh eased = s.cap;
  const Eigen::RowVector3d centre = eased.V.colwise().mean();
  eased.V = ((eased.V.rowwise() - centre) * 1.10).rowwise() + centre;
  write_mesh(s.dir / "eased.ply", eased);
  const fs::path verified = write_fit_report(s, "", "fit-verified");
  const auto bad = testing::run_command(testing::tool_path("export-rest") + " --garment " +
                                        (s.dir / "garment.json").string() + " -q --fit " + verified.string() +
                                        " --drape-after-motion --drape-mean-limit 0.005 --drape-p95-limit 0.015 " +
                                        (s.dir / "eased.ply").string() + " --out " + (s.dir / "eased").string());
  INFO(bad.err);
  CHECK(bad.exit_code == 8);
  CHECK(bad.err.find("mean distance to the verified drape") != std::string::npos);
  const Json failed = read_json_file(s.dir / "eased" / "report.json")["sewn_fit"];
  CHECK(failed["verdict"] == "fail");
  CHECK(failed["drape"]["reference"] == "the fit's verified drapes");
  CHECK(failed["drape"]["verdict"] == "fail");
  for (const Json& k : failed["key_poses"]) {
    const Json& d = k["distance_to_verified"];
    INFO("pose " << k["pose"] << " mean " << d["mean_m"] << " p95 " << d["p95_m"] << " p99 " << k["p99_stretch"]);
    CHECK(d["verified_mesh_in"] == "fit");
    CHECK(!k.contains("reference"));
    CHECK(k["verdict"] == "pass");  // not tight
    CHECK(d["verdict"] == "fail");
    CHECK(d["mean_m"].get<double>() > 0.005);
  }
}

TEST_CASE("settled at each key pose from the verified drape: the pattern as cut stays, one eased by 10 % sags",
          "[sewn_fit][cli]") {
  const CapScene s = write_cap_scene("sewn-fit-settled");
  const fs::path fit = write_fit_report(s);
  const std::string base = testing::tool_path("export-rest") + " --garment " + (s.dir / "garment.json").string() +
                           " -q --fit " + fit.string() + " --drape-mean-limit 0.005 --drape-p95-limit 0.015 ";
  const auto good = testing::run_command(base + (s.dir / "garment.ply").string() + " --out " + (s.dir / "good").string());
  INFO(good.err);
  REQUIRE(good.exit_code == 0);
  const Json sewn = read_json_file(s.dir / "good" / "report.json")["sewn_fit"];
  CHECK(sewn["drape"]["judged"] == "the sewn garment settled at each key pose alone from the reference drape");
  CHECK(sewn["drape"]["settled_worst_mean_m"].get<double>() < 0.001);
  for (const Json& k : sewn["key_poses"]) {
    const Json& d = k["settled_from_reference"];
    INFO("pose " << k["pose"] << " sewn " << d["sewn"] << " rest shape " << d["rest_shape"]);
    CHECK(d["verdict"] == "pass");
    CHECK(d["sewn"]["mean_m"].get<double>() < 0.001);
    CHECK(d["sewn"]["p95_m"].get<double>() < 0.002);
    // The verified drape settled again with the rest shape's own triangles
    // stays where it was: the floor of the figure.
    CHECK(d["rest_shape"]["mean_m"].get<double>() < 0.0005);
    // The distance after the motion is reported, not bounded.
    CHECK(k["distance_to_verified"]["failures"].empty());
    // The settled drape is written with its distance per vertex.
    const fs::path mesh = s.dir / "good" / d["mesh"].get<std::string>();
    REQUIRE(fs::exists(mesh));
    const ScalarField* dist = find_field(read_mesh(mesh).mesh.vertex_fields, "distance_to_verified");
    REQUIRE(dist != nullptr);
    CHECK(dist->values.maxCoeff() == Approx(d["sewn"]["max_m"].get<double>()));
  }
  Mesh eased = s.cap;
  const Eigen::RowVector3d centre = eased.V.colwise().mean();
  eased.V = ((eased.V.rowwise() - centre) * 1.10).rowwise() + centre;
  write_mesh(s.dir / "eased.ply", eased);
  const auto bad = testing::run_command(base + (s.dir / "eased.ply").string() + " --out " + (s.dir / "eased").string());
  INFO(bad.err);
  CHECK(bad.exit_code == 8);
  CHECK(bad.err.find("settled at this pose alone from the verified drape, mean distance") != std::string::npos);
  const Json failed = read_json_file(s.dir / "eased" / "report.json")["sewn_fit"];
  CHECK(failed["drape"]["verdict"] == "fail");
  for (const Json& k : failed["key_poses"]) {
    const Json& d = k["settled_from_reference"];
    INFO("pose " << k["pose"] << " sewn " << d["sewn"]);
    CHECK(d["verdict"] == "fail");
    CHECK(d["sewn"]["mean_m"].get<double>() > 0.005);
  }
}

TEST_CASE("a pattern eased by 10 % drapes away from its rest shape's own drape", "[sewn_fit]") {
  const CapScene s = write_cap_scene("sewn-fit-eased");
  const fs::path fit = write_fit_report(s, " --no-verify");
  const FitSettings settings = read_fit_settings(fit);
  const PoseSet poses = load_pose_set(settings.poses);
  const MotionSpec motion = read_motion_spec(settings.motion, poses);
  InterpolationOptions interp;
  interp.anchor = motion.anchor;
  PoseInterpolator interpolator(poses, interp);
  PatternOptions cut;
  cut.panels.stretch_budget = settings.delta();  // as export-rest cuts with --fit
  // The plain cut, which export-rest keeps for this cap (the pattern within
  // its limit sews into a garment that fails pose b at delta 0.04).
  cut.flatten.limit_rounds = 0;
  cut.panels.min_relief_share = 0.0;
  const Pattern pattern = make_pattern(s.cap.V, s.cap.F, {}, cut);
  const Layout layout = layout_pattern(pattern, LayoutOptions{});
  const adapt::FitVerification reference = rest_shape_drapes(interpolator, motion, s.cap.V, s.cap.V, s.cap.F, s.garment,
                                                             settings.run, settings.criteria);
  std::vector<Eigen::MatrixXd> V_reference;
  for (const adapt::PoseCheck& c : reference.poses) V_reference.push_back(c.figures.V_draped);
  const std::vector<std::string> names(V_reference.size(), "reference");
  DrapeCriteria goal;
  goal.max_mean = 0.005;
  goal.max_p95 = 0.015;
  auto sewn_against_reference = [&](double scale) {
    Layout scaled = layout;
    for (auto& piece : scaled.pieces) piece.UV *= scale;
    SewnFitResult r = sewn_fit_check(interpolator, motion, s.cap.V, s.cap.F, s.garment, pattern, scaled, settings.run,
                                     settings.criteria);
    compare_with_verified(r, V_reference, names, s.cap.F, goal);
    return r;
  };
  // The pattern as cut: within a millimetre of the rest shape's drape.
  const SewnFitResult as_cut = sewn_against_reference(1.0);
  REQUIRE(as_cut.drape.size() == 2);
  for (const DrapeDistance& d : as_cut.drape) {
    INFO("pose " << d.pose << " mean " << d.mean << " p95 " << d.p95);
    CHECK(d.mean < 0.001);
    CHECK(d.p95 < 0.002);
  }
  CHECK(as_cut.passed());
  // Every piece scaled up by 10 % (21 % more cloth): loose, so the stretch
  // bounds pass, but the drape fails both bounds.
  const SewnFitResult eased = sewn_against_reference(1.10);
  CHECK(eased.sewn_rest_area / eased.rest_area == Approx(1.21 * as_cut.sewn_rest_area / as_cut.rest_area).epsilon(1e-6));
  CHECK(eased.verification.passed());
  CHECK(!eased.drape_passed());
  CHECK(!eased.passed());
  for (const DrapeDistance& d : eased.drape) {
    INFO("pose " << d.pose << " mean " << d.mean << " p95 " << d.p95 << " max " << d.max);
    CHECK(d.mean > 0.005);
    CHECK(d.failures.size() >= 1);
  }
  CHECK(sewn_fit_failure(eased, pattern).find("mean distance to the verified drape") != std::string::npos);
}

TEST_CASE("the distance between two drapes of one mesh, by area", "[sewn_fit]") {
  const Mesh m = testing::make_icosphere(2, 0.2);
  // A rigid shift by 4 mm: every figure is 4 mm.
  Eigen::MatrixXd shifted = m.V;
  shifted.col(0).array() += 0.004;
  const DrapeDistance d = drape_distance(shifted, m.V, m.F, DrapeCriteria{});
  CHECK(d.mean == Approx(0.004).epsilon(1e-9));
  CHECK(d.p95 == Approx(0.004).epsilon(1e-9));
  CHECK(d.max == Approx(0.004).epsilon(1e-9));
  CHECK(d.passed());
  CHECK(d.sewn_area == Approx(d.verified_area).epsilon(1e-12));
  // One vertex 5 cm off: the max sees it, the p95 and the mean hardly.
  Eigen::MatrixXd bump = m.V;
  bump.row(7) *= 1.25;
  const DrapeDistance b = drape_distance(bump, m.V, m.F, DrapeCriteria{});
  CHECK(b.max == Approx(0.05).epsilon(1e-9));
  CHECK(b.max_vertex == 7);
  CHECK(b.p95 == 0.0);
  CHECK(b.mean < 0.05 / 100.0);
  CHECK(b.passed());
  // With the goal's bounds (5 mm mean, 15 mm p95): 2 cm everywhere fails
  // both, 8 mm only the mean; the default bounds nothing.
  DrapeCriteria goal;
  goal.max_mean = 0.005;
  goal.max_p95 = 0.015;
  const DrapeDistance far = drape_distance(m.V * 1.1, m.V, m.F, goal);
  CHECK(far.failures.size() == 2);
  CHECK(drape_distance(m.V * 1.1, m.V, m.F, DrapeCriteria{}).failures.empty());
  const DrapeDistance mid = drape_distance(m.V * 1.04, m.V, m.F, goal);
  REQUIRE(mid.failures.size() == 1);
  CHECK(mid.failures[0].find("mean distance") != std::string::npos);
  CHECK(mid.sewn_area / mid.verified_area == Approx(1.04 * 1.04).epsilon(1e-9));
  CHECK_THROWS_AS(drape_distance(m.V.topRows(5), m.V, m.F, DrapeCriteria{}), GeometryError);
}

TEST_CASE("the fit's settings are read from its report, strictly", "[sewn_fit]") {
  const fs::path dir = testing::fresh_temp_dir("sewn-fit-settings");
  // The options as simulate-adapt writes them, every one away from its default.
  adapt::FitOptions fit;
  adapt::MotionRunOptions& m = fit.motion;
  m.solver.dt = 0.005;
  m.schedule.substeps = 2;
  m.adaptation.adapter.delta = 0.08;
  m.settle.max_steps = 700;
  m.settle.damping = 0.5;
  m.contact.continuous = false;
  m.contact.velocity_constraints = false;
  m.contact.surface.hulls = false;
  m.contact.surface.thin = 0.02;
  m.contact.surface.min_extent = 0.12;
  m.contact.sweep.thickness = 1e-3;
  m.solver.strategy = cloth::SolverStrategy::pcg_reused_factor;
  m.solver.cg_max_iterations = 41;
  m.solver.warp_preconditioner = false;
  m.contact.reach = 0.12;
  adapt::FitCriteria criteria;
  criteria.max_area_above = 0.02;
  criteria.p99_margin = 0.03;
  criteria.max_penetration = 0.004;
  criteria.max_crossings = 1;
  OrderedJson options = {{"poses", "p.json"}, {"motion", "m.json"}};
  options.update(write_options(fit, adapt::FitOptionFields{}));
  options["motion_effective"] = {{"schema", "motion/1"}};  // beside the options, not read
  OrderedJson report = {{"schema", "simulate-adapt-report/1"},
                        {"options", options},
                        {"verification", {{"criteria", write_options(criteria, adapt::FitCriteriaFields{})}}}};
  write_json_file(dir / "r.json", report);
  const FitSettings s = read_fit_settings(dir / "r.json");
  CHECK(s.poses == "p.json");
  CHECK(s.motion == "m.json");
  CHECK(s.run.solver.dt == 0.005);
  CHECK(s.run.schedule.substeps == 2);
  CHECK(s.delta() == 0.08);
  CHECK(s.run.settle.max_steps == 700);
  CHECK(s.run.settle.damping == 0.5);
  CHECK(!s.run.contact.continuous);
  CHECK(!s.run.contact.velocity_constraints);
  CHECK(!s.run.contact.surface.hulls);
  CHECK(s.run.contact.surface.thin == 0.02);
  CHECK(s.run.contact.surface.min_extent == 0.12);
  CHECK(s.run.contact.sweep.thickness == 1e-3);
  CHECK(s.run.contact.reach == 0.12);
  CHECK(s.run.solver.strategy == cloth::SolverStrategy::pcg_reused_factor);
  CHECK(s.run.solver.cg_max_iterations == 41);
  CHECK(!s.run.solver.warp_preconditioner);
  CHECK(!s.run.adaptation.enabled);  // the sewn garment is checked, never adapted
  CHECK(s.run.schedule.threads == 1);
  CHECK(s.criteria.max_area_above == 0.02);
  CHECK(s.criteria.p99_margin == 0.03);
  CHECK(s.criteria.max_penetration == 0.004);
  CHECK(s.criteria.max_crossings == 1);
  // A fit without verification: the default bounds.
  report["verification"] = nullptr;
  write_json_file(dir / "r.json", report);
  CHECK(read_fit_settings(dir / "r.json").criteria.max_area_above == adapt::FitCriteria{}.max_area_above);
  // A missing field is named by its pointer; another schema is refused.
  report["options"].erase("delta");
  write_json_file(dir / "r.json", report);
  try {
    read_fit_settings(dir / "r.json");
    FAIL("no error");
  } catch (const SpecError& e) {
    CHECK(e.where().find("delta") != std::string::npos);
  }
  report["options"]["delta"] = 0.1;
  report["options"]["solver"] = "gauss_seidel";
  write_json_file(dir / "r.json", report);
  try {
    read_fit_settings(dir / "r.json");
    FAIL("no error");
  } catch (const SpecError& e) {
    CHECK(e.where().find("/options/solver") != std::string::npos);
  }
  report["options"]["solver"] = "refactor_every_step";
  report["schema"] = "export-rest-report/1";
  write_json_file(dir / "r.json", report);
  CHECK_THROWS_AS(read_fit_settings(dir / "r.json"), SpecError);
}

TEST_CASE("the sewn garment is judged at the in-between frames its fit was judged at", "[sewn_fit][cli][frames]") {
  const CapScene s = write_cap_scene("sewn-fit-frames");
  // The fit's verification solves every 3rd of the 10 frames a -> b: frames 3, 6 and 9.
  const fs::path fit = write_fit_report(s, " --verify-frame-stride 3");
  CHECK(read_fit_settings(fit).frame_stride == 3);
  const auto good = export_with_fit(s, fit, s.dir / "garment.ply", "good");
  INFO(good.err);
  REQUIRE(good.exit_code == 0);
  const Json sewn = read_json_file(s.dir / "good" / "report.json")["sewn_fit"];
  CHECK(sewn["frame_stride"] == 3);
  REQUIRE(sewn["transitions"].size() == 1);
  const Json& t = sewn["transitions"][0];
  CHECK(t["from"] == "a");
  CHECK(t["to"] == "b");
  CHECK(t["frames_solved"] == 3);
  CHECK(t["frames_failed"] == 0);
  CHECK(t["verdict"] == "pass");
  CHECK(t["worst_frame"]["p99_stretch"].get<double>() < 1.06);

  // The pattern 5 % too small fails between the poses too.
  const auto bad = export_with_fit(s, fit, write_shrunk_cap(s), "bad");
  CHECK(bad.exit_code == 8);
  const Json failed = read_json_file(s.dir / "bad" / "report.json")["sewn_fit"]["transitions"][0];
  CHECK(failed["verdict"] == "fail");
  CHECK(failed["frames_failed"] == 3);
  CHECK(failed["worst_frame"]["area_fraction_above_limit"].get<double>() > 0.5);
}
