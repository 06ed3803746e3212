#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>

#include "core/error.h"
#include "garment/extend_boundary.h"
#include "garment/make_garment.h"
#include "garment/surface_path.h"
#include "io/mesh_io.h"
#include "mesh/measures.h"
#include "core/sha256.h"
#include "mesh/topology.h"
#include "pose/pose_set.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using gp::Json;

namespace {

constexpr double kRadius = 0.2;

// Clicks (as 3D points, snapped by make_garment) on the circle of angular
// radius `theta` around direction `axis` of the sphere of radius kRadius.
Json circle_points(const Eigen::Vector3d& axis, double theta, int count = 8) {
  const Eigen::Vector3d a = axis.normalized();
  const Eigen::Vector3d u = a.unitOrthogonal(), w = a.cross(u);
  Json points = Json::array();
  for (int j = 0; j < count; ++j) {
    const double phi = 2 * M_PI * j / count;
    const Eigen::Vector3d p = kRadius * (std::cos(theta) * a + std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * w));
    points.push_back({p[0], p[1], p[2]});
  }
  return points;
}

// A "shirt" on a sphere: four caps cut away (neck, waist, two cuffs).
Json shirt_spec() {
  Json j;
  j["schema"] = "garment-spec/1";
  j["name"] = "sphere-shirt";
  j["loops"] = Json::array({
      {{"name", "neck"}, {"pinned", true}, {"points", circle_points({0, 1, 0}, 0.5)}},
      {{"name", "waist"}, {"points", circle_points({0, -1, 0}, 0.6)}},
      {{"name", "cuff_left"}, {"pinned", true}, {"points", circle_points({1, 0, 0}, 0.45)}},
      {{"name", "cuff_right"}, {"pinned", true}, {"points", circle_points({-1, 0, 0}, 0.45)}},
  });
  j["region"] = {0.0, 0.0, kRadius};
  j["resolution"] = {{"edge_length", 0.012}};
  j["offset"] = 0.015;
  j["paint"] = Json::array({{{"name", "front"}, {"factor", 1.2}, {"disc", {{"center", {0.0, 0.0, kRadius}}, {"radius", 0.05}}}}});
  return j;
}

const gp::Mesh& sphere_body() {
  static const gp::Mesh body = gp::testing::make_icosphere(5, kRadius);
  return body;
}

double distance_to_polyline(const Eigen::Vector3d& x, const Eigen::MatrixXd& P) {
  double best = 1e300;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d a = P.row(i), b = P.row((i + 1) % P.rows());
    const double t = std::clamp((x - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-300), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - x).norm());
  }
  return best;
}

template <class F>
std::string error_where(F&& f, gp::ExitCode expected) {
  try {
    f();
  } catch (const gp::Error& e) {
    CHECK(e.code() == expected);
    return e.message();
  }
  FAIL("no error thrown");
  return "";
}

}  // namespace

TEST_CASE("a shirt with four loops is one manifold piece with Euler characteristic -2", "[garment]") {
  const gp::GarmentSpec spec = gp::parse_garment_spec(shirt_spec(), "shirt.json");
  const gp::Mesh& body = sphere_body();
  const gp::MakeGarmentResult r = gp::make_garment(body.V, body.F, spec);
  CHECK(r.component_count == 1);
  CHECK(r.boundary_loop_count == 4);
  CHECK(r.euler_characteristic == -2);
  CHECK(gp::boundary_loops(r.mesh.F).size() == 4);
  // Triangle quality.
  CHECK(r.quality.fraction_min_angle_over_20 >= 0.99);
  CHECK(r.quality.fraction_edges_within_30 >= 0.95);
  CHECK(std::abs(r.quality.mean_edge_length / 0.012 - 1.0) < 0.1);
  // Boundary on its curve, every vertex at the comfort offset.
  CHECK(r.boundary_curve_error < 1e-3);
  CHECK(r.offset_error.max_error < 1e-3);
  for (Eigen::Index v = 0; v < r.mesh.V.rows(); ++v)
    REQUIRE(std::abs(r.mesh.V.row(v).norm() - (kRadius + 0.015)) < 1e-3);
  // Pins and paint.
  CHECK(r.file.loops[0].pinned);
  CHECK_FALSE(r.file.loops[1].pinned);
  int painted = 0;
  for (double p : r.file.paint) {
    CHECK((p == 1.0 || std::abs(p - 1.2) < 1e-12));
    painted += p != 1.0;
  }
  // A disc of radius 5 cm on the sphere covers about pi r^2 / area-per-triangle.
  const double tri_area = r.mesh.F.rows() > 0 ? gp::face_areas(r.mesh.V, r.mesh.F).mean() : 1.0;
  CHECK(painted > 0.5 * M_PI * 0.05 * 0.05 / tri_area);
  CHECK(painted < 2.0 * M_PI * 0.05 * 0.05 / tri_area);
}

TEST_CASE("the boundary binding reproduces the loop on another pose", "[garment]") {
  gp::Json j = shirt_spec();
  j["offset"] = 0.0;
  const gp::GarmentSpec spec = gp::parse_garment_spec(j, "shirt.json");
  const gp::Mesh& body = sphere_body();
  const gp::MakeGarmentResult r = gp::make_garment(body.V, body.F, spec);
  // Another pose: stretched, sheared and rotated, same triangles.
  Eigen::Matrix3d A;
  A << 1.3, 0.2, 0.0, 0.0, 0.8, 0.1, 0.1, 0.0, 1.1;
  A = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix() * A;
  const Eigen::MatrixXd V2 = (body.V * A.transpose()).rowwise() + Eigen::RowVector3d(0.3, -0.1, 2.0);
  const Eigen::MatrixXd N2 = gp::vertex_normals(V2, body.F);
  for (size_t k = 0; k < r.file.loops.size(); ++k) {
    const auto& loop = r.file.loops[k];
    REQUIRE(loop.binding.size() == loop.vertex_ids.size());
    const Eigen::MatrixXd curve = gp::evaluate_curve(V2, body.F, r.cut.curves[k]);
    double worst = 0.0;
    for (const auto& b : loop.binding)
      worst = std::max(worst, distance_to_polyline(gp::evaluate_binding(V2, N2, body.F, b, 0.0), curve));
    CHECK(worst < 1e-9);
    // And in the design pose the binding gives the garment's boundary vertices.
    for (size_t i = 0; i < loop.vertex_ids.size(); ++i)
      CHECK((gp::evaluate(body.V, body.F, loop.binding[i]) - r.mesh.V.row(loop.vertex_ids[i]).transpose()).norm() < 1e-9);
  }
}

TEST_CASE("the curves are smooth loops on the surface, not the jagged edge path", "[garment]") {
  const gp::GarmentSpec spec = gp::parse_garment_spec(shirt_spec(), "shirt.json");
  const gp::Mesh& body = sphere_body();
  const gp::MakeGarmentResult r = gp::make_garment(body.V, body.F, spec);
  // Neck: circle of angular radius 0.5 -> length 2 pi R sin(0.5); the edge
  // path zig-zags and is longer, the smoothed curve is close to the circle.
  const double circle = 2 * M_PI * kRadius * std::sin(0.5);
  const double length = gp::curve_length(body.V, body.F, r.cut.curves[0]);
  CHECK(std::abs(length / circle - 1.0) < 0.05);
  // Every curve point lies on the body (the sphere).
  const Eigen::MatrixXd P = gp::evaluate_curve(body.V, body.F, r.cut.curves[0]);
  for (Eigen::Index i = 0; i < P.rows(); ++i) CHECK(P.row(i).norm() <= kRadius + 1e-12);
}

TEST_CASE("outputs are deterministic", "[garment]") {
  const gp::GarmentSpec spec = gp::parse_garment_spec(shirt_spec(), "shirt.json");
  const gp::Mesh& body = sphere_body();
  const gp::MakeGarmentResult a = gp::make_garment(body.V, body.F, spec);
  const gp::MakeGarmentResult b = gp::make_garment(body.V, body.F, spec);
  CHECK(a.mesh.V == b.mesh.V);
  CHECK(a.mesh.F == b.mesh.F);
  CHECK(gp::to_json(a.file).dump() == gp::to_json(b.file).dump());
}

TEST_CASE("a skirt extended from the waist loop has the requested girth and no flipped band triangles", "[garment]") {
  // A top: the sphere above a waist loop below the equator, with a neck.
  Json j;
  j["schema"] = "garment-spec/1";
  j["loops"] = Json::array({{{"name", "neck"}, {"pinned", true}, {"points", circle_points({0, 1, 0}, 0.5)}},
                            {{"name", "waist"}, {"pinned", true}, {"points", circle_points({0, -1, 0}, 1.2)}}});
  j["region"] = {kRadius, 0.0, 0.0};
  j["resolution"] = {{"edge_length", 0.015}};
  j["offset"] = 0.008;
  const gp::GarmentSpec spec = gp::parse_garment_spec(j, "top.json");
  const gp::Mesh& body = sphere_body();
  const gp::MakeGarmentResult top = gp::make_garment(body.V, body.F, spec);
  const Json e = {{"schema", "extend-spec/1"}, {"loop", "waist"}, {"target", {{"point", {0.0, -0.6, 0.0}}}}, {"girth", 2.0}};
  const gp::ExtendSpec extend = gp::parse_extend_spec(e, "extend.json");
  const gp::ExtendResult r = gp::extend_boundary(top.mesh, top.file, extend);
  CHECK(std::abs(r.new_girth / 2.0 - 1.0) < 0.01);
  CHECK(r.band_faces > 0);
  CHECK(r.band_flipped_faces == 0);
  CHECK(r.axis.dot(Eigen::Vector3d(0, -1, 0)) > 0.99);
  CHECK(r.unpinned);
  // Still one manifold piece with two loops; the neck is untouched.
  CHECK(gp::boundary_loops(r.mesh.F).size() == 2);
  Eigen::VectorXi component;
  CHECK(gp::face_components(r.mesh.F, component) == 1);
  CHECK(r.file.loops[0].vertex_ids == top.file.loops[0].vertex_ids);
  for (int v : top.file.loops[0].vertex_ids) CHECK(r.mesh.V.row(v) == top.mesh.V.row(v));
  CHECK(r.file.loops[1].binding.empty());
  CHECK_FALSE(r.file.loops[1].pinned);
  CHECK(r.file.paint.size() == static_cast<size_t>(r.mesh.F.rows()));
  // The new loop lies at the target height.
  for (int v : r.file.loops[1].vertex_ids) CHECK(std::abs(r.mesh.V(v, 1) + 0.6) < 0.03);
  // The band is tessellated at the garment's edge length.
  const gp::MeshQuality q = gp::measure_quality(r.mesh.V, r.mesh.F, top.file.target_edge_length);
  CHECK(q.fraction_min_angle_over_20 > 0.97);

  SECTION("a target behind the loop is a spec error") {
    const Json behind = {{"schema", "extend-spec/1"}, {"loop", "waist"}, {"target", {{"point", {0.0, 0.5, 0.0}}}}};
    const std::string msg = error_where([&] { gp::extend_boundary(top.mesh, top.file, gp::parse_extend_spec(behind, "x.json")); },
                                        gp::ExitCode::spec);
    CHECK(msg.find("/target/point") != std::string::npos);
  }
  SECTION("a zero scale is a spec error") {
    const Json zero = {{"schema", "extend-spec/1"}, {"loop", "waist"}, {"target", {{"distance", 0.2}}}, {"scale", 0.0}};
    const std::string msg = error_where([&] { gp::parse_extend_spec(zero, "x.json"); }, gp::ExitCode::spec);
    CHECK(msg.find("/scale") != std::string::npos);
  }
  SECTION("an unknown loop is a spec error") {
    const Json other = {{"schema", "extend-spec/1"}, {"loop", "hem"}, {"target", {{"distance", 0.2}}}};
    const std::string msg = error_where([&] { gp::extend_boundary(top.mesh, top.file, gp::parse_extend_spec(other, "x.json")); },
                                        gp::ExitCode::spec);
    CHECK(msg.find("/loop") != std::string::npos);
  }
}

TEST_CASE("design errors name the spec field", "[garment][errors]") {
  const gp::Mesh& body = sphere_body();
  auto run = [&](const Json& j, const gp::Mesh& m) { gp::make_garment(m.V, m.F, gp::parse_garment_spec(j, "s.json")); };

  SECTION("a loop that does not close") {
    Json j = shirt_spec();
    j["loops"][1]["points"] = Json::array({10, 20});
    CHECK(error_where([&] { run(j, body); }, gp::ExitCode::spec).find("/loops/1/points") != std::string::npos);
  }
  SECTION("a loop that crosses itself") {
    Json j = shirt_spec();
    // Clicks around the circle in the order 0 4 2 6 1 5 3 7: the paths cross.
    const Json circle = circle_points({0, -1, 0}, 0.6);
    j["loops"][1]["points"] = Json::array({circle[0], circle[4], circle[2], circle[6], circle[1], circle[5], circle[3], circle[7]});
    const std::string msg = error_where([&] { run(j, body); }, gp::ExitCode::geometry);
    CHECK(msg.find("/loops/1") != std::string::npos);
  }
  SECTION("a region point on a loop") {
    Json j = shirt_spec();
    j["region"] = j["loops"][0]["points"][0];
    CHECK(error_where([&] { run(j, body); }, gp::ExitCode::geometry).find("/region") != std::string::npos);
  }
  SECTION("a region point outside a loop") {
    Json j = shirt_spec();
    j["region"] = {0.0, kRadius, 0.0};  // inside the neck cap
    const std::string msg = error_where([&] { run(j, body); }, gp::ExitCode::geometry);
    CHECK(msg.find("/region") != std::string::npos);
    CHECK(msg.find("outside loop") != std::string::npos);
  }
  SECTION("a loop that leaks (a meridian of a torus does not separate it)") {
    const gp::Mesh torus = gp::testing::make_torus(48, 24, 0.3, 0.1);
    Json j;
    j["schema"] = "garment-spec/1";
    // Meridian: the tube circle at angle 0 around the ring (points at x ~ 0.3 +- 0.1, y).
    Json points = Json::array();
    for (int k = 0; k < 8; ++k) {
      const double a = 2 * M_PI * k / 8;
      points.push_back({0.3 + 0.1 * std::cos(a), 0.1 * std::sin(a), 0.0});
    }
    j["loops"] = Json::array({{{"name", "band"}, {"points", points}}});
    j["region"] = {-0.4, 0.0, 0.0};
    j["resolution"] = {{"edge_length", 0.02}};
    const std::string msg = error_where([&] { run(j, torus); }, gp::ExitCode::geometry);
    CHECK(msg.find("'band'") != std::string::npos);
    CHECK(msg.find("/loops/0") != std::string::npos);
  }
  SECTION("picks on another component, and a region outside every loop") {
    gp::Mesh two = body;
    const gp::Mesh other = gp::testing::make_icosphere(3, kRadius);
    two.V.conservativeResize(body.V.rows() + other.V.rows(), 3);
    two.V.bottomRows(other.V.rows()) = other.V.rowwise() + Eigen::RowVector3d(1.0, 0, 0);
    two.F.conservativeResize(body.F.rows() + other.F.rows(), 3);
    two.F.bottomRows(other.F.rows()) = other.F.array() + static_cast<int>(body.V.rows());
    Json j = shirt_spec();
    j["loops"][2]["points"][3] = {1.0, kRadius, 0.0};
    std::string msg = error_where([&] { run(j, two); }, gp::ExitCode::geometry);
    CHECK(msg.find("/loops/2/points") != std::string::npos);
    CHECK(msg.find("different connected components") != std::string::npos);
    Json k = shirt_spec();
    k["region"] = {1.0, 0.0, kRadius};
    msg = error_where([&] { run(k, two); }, gp::ExitCode::geometry);
    CHECK(msg.find("outside every loop") != std::string::npos);
  }
  SECTION("an empty or degenerate region") {
    Json j;
    j["schema"] = "garment-spec/1";
    // A loop around one triangle, the region inside it.
    const int a = body.F(0, 0), b = body.F(0, 1), c = body.F(0, 2);
    j["loops"] = Json::array({{{"name", "tiny"}, {"points", {a, b, c}}}});
    j["region"] = {a};
    j["region"] = a;
    j["resolution"] = {{"edge_length", 0.01}};
    CHECK(error_where([&] { run(j, body); }, gp::ExitCode::geometry).find("s.json") != std::string::npos);
  }
  SECTION("strict spec reading") {
    Json j = shirt_spec();
    j["offest"] = 0.01;
    CHECK(error_where([&] { run(j, body); }, gp::ExitCode::spec).find("offest") != std::string::npos);
    Json k = shirt_spec();
    k["loops"][0]["points"][0] = 99999999;
    CHECK(error_where([&] { run(k, body); }, gp::ExitCode::spec).find("/loops/0/points/0") != std::string::npos);
    Json f = shirt_spec();
    f["loops"][0]["points"][0] = {0.0, 5.0, 0.0};  // far from the body
    CHECK(error_where([&] { run(f, body); }, gp::ExitCode::spec).find("snap tolerance") != std::string::npos);
    Json s = shirt_spec();
    s["schema"] = "garment-spec/2";
    CHECK_THROWS_AS(run(s, body), gp::SpecError);
  }
}

TEST_CASE("make-garment and extend-boundary on the command line", "[garment][cli]") {
  const fs::path dir = gp::testing::fresh_temp_dir("garment_cli");
  gp::write_mesh(dir / "body.ply", sphere_body());
  {
    std::ofstream(dir / "shirt.json") << shirt_spec().dump(2);
    Json bad = shirt_spec();
    bad["offset"] = -1.0;
    std::ofstream(dir / "bad.json") << bad.dump(2);
  }
  const std::string mg = gp::testing::tool_path("make-garment");
  const std::string eb = gp::testing::tool_path("extend-boundary");
  const std::string d = dir.string();
  auto r = gp::testing::run_command(mg + " " + d + "/shirt.json --avatar " + d + "/body.ply --out " + d + "/out1 -q");
  REQUIRE(r.exit_code == 0);
  CHECK(fs::exists(dir / "out1" / "garment.ply"));
  CHECK(fs::exists(dir / "out1" / "report.json"));
  const gp::GarmentFile file = gp::read_garment_file(dir / "out1" / "garment.json");
  CHECK(file.loops.size() == 4);
  CHECK(file.material.k_stretch == 800.0);
  // Same inputs, same bytes.
  r = gp::testing::run_command(mg + " " + d + "/shirt.json --avatar " + d + "/body.ply --out " + d + "/out2 -q");
  REQUIRE(r.exit_code == 0);
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  };
  CHECK(bytes(dir / "out1" / "garment.ply") == bytes(dir / "out2" / "garment.ply"));
  CHECK(bytes(dir / "out1" / "garment.json") == bytes(dir / "out2" / "garment.json"));
  // Errors: spec 4, input 3, usage 2.
  r = gp::testing::run_command(mg + " " + d + "/bad.json --avatar " + d + "/body.ply --out " + d + "/out3");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("make-garment: error[spec]") != std::string::npos);
  CHECK(r.err.find("/offset") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out3"));
  r = gp::testing::run_command(mg + " " + d + "/missing.json --avatar " + d + "/body.ply --out " + d + "/out3");
  CHECK(r.exit_code == 3);
  r = gp::testing::run_command(mg + " " + d + "/shirt.json --out " + d + "/out3");
  CHECK(r.exit_code == 2);
  // A pose set: the design pose is chosen by name; the body is the same
  // sphere, so the garment is the same mesh.
  {
    gp::Mesh stretched = sphere_body();
    stretched.V.col(1) *= 1.5;
    gp::write_mesh(dir / "tall.ply", stretched);
    gp::PoseSetManifest m;
    m.vertex_count = stretched.V.rows();
    m.face_count = stretched.F.rows();
    m.topology_sha256 = gp::topology_checksum(stretched.F);
    m.reference = "tall";
    m.poses.push_back({"tall", "tall.ply", gp::sha256_file_hex(dir / "tall.ply"), "test"});
    m.poses.push_back({"round", "body.ply", gp::sha256_file_hex(dir / "body.ply"), "test"});
    gp::write_pose_set_manifest(dir / "poses.json", m);
  }
  r = gp::testing::run_command(mg + " " + d + "/shirt.json --poses " + d + "/poses.json --pose round --out " + d + "/out4 -q");
  REQUIRE(r.exit_code == 0);
  CHECK(bytes(dir / "out1" / "garment.ply") == bytes(dir / "out4" / "garment.ply"));
  CHECK(gp::read_garment_file(dir / "out4" / "garment.json").body.design_pose == "round");
  r = gp::testing::run_command(mg + " " + d + "/shirt.json --poses " + d + "/poses.json --pose sitting --out " + d + "/out5");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("sitting") != std::string::npos);
  // Extension: a wide sleeve from a cuff.
  std::ofstream(dir / "sleeve.json") << Json({{"schema", "extend-spec/1"}, {"loop", "cuff_left"},
                                              {"target", {{"distance", 0.1}}}, {"scale", 1.5}}).dump();
  r = gp::testing::run_command(eb + " " + d + "/out1/garment.json " + d + "/sleeve.json --out " + d + "/ext -q");
  REQUIRE(r.exit_code == 0);
  const gp::GarmentFile extended = gp::read_garment_file(dir / "ext" / "garment.json");
  CHECK(extended.extensions.size() == 1);
  CHECK(extended.loops[2].binding.empty());
  CHECK(extended.loops[0].binding.size() == extended.loops[0].vertex_ids.size());
  std::ofstream(dir / "behind.json") << Json({{"schema", "extend-spec/1"}, {"loop", "cuff_left"},
                                              {"target", {{"point", {0.0, 0.0, 0.0}}}}}).dump();
  r = gp::testing::run_command(eb + " " + d + "/out1/garment.json " + d + "/behind.json --out " + d + "/ext2");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("/target/point") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("the example shirt on the shared T-pose", "[garment][shared]") {
  const fs::path avatars = gp::testing::shared_avatars_dir();
  if (avatars.empty()) {
    WARN("skipped: ../shared/avatars not found");
    return;
  }
  const gp::MeshReadResult tpose = gp::read_mesh(avatars / "slim_tpose.ply");
  const gp::GarmentSpec spec = gp::read_garment_spec(gp::testing::source_dir() / "pipelines/specs/shirt.json");
  const gp::MakeGarmentResult r = gp::make_garment(tpose.mesh.V, tpose.mesh.F, spec);
  CHECK(r.boundary_loop_count == 4);
  CHECK(r.euler_characteristic == -2);
  CHECK(r.component_count == 1);
  CHECK(r.quality.fraction_min_angle_over_20 >= 0.99);
  CHECK(r.offset_error.max_error < 1e-3);
  CHECK(std::abs(r.mesh.V.rows() - 4000) < 400);
  // The binding follows the body into the A-pose: bound points lie on the
  // loop's curve evaluated there.
  const gp::MeshReadResult apose = gp::read_mesh(avatars / "slim_apose.ply");
  for (size_t k = 0; k < r.file.loops.size(); ++k) {
    const Eigen::MatrixXd curve = gp::evaluate_curve(apose.mesh.V, apose.mesh.F, r.cut.curves[k]);
    for (const auto& b : r.file.loops[k].binding)
      CHECK(distance_to_polyline(gp::evaluate(apose.mesh.V, apose.mesh.F, b), curve) < 1e-6);
  }
}

TEST_CASE("a shortest edge path between mirror-symmetric ties does not follow the last bits", "[garment]") {
  // A square grid: from one corner to the opposite one every monotone
  // staircase has the same length, so only the tie rule decides. Noise of a
  // few ulps on the coordinates must not change the path.
  const int n = 9;
  Eigen::MatrixXd V(n * n, 3);
  std::vector<std::vector<int>> neighbors(n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      V.row(j * n + i) << 0.013 * i, 0.013 * j, 0.0;
      if (i + 1 < n) {
        neighbors[j * n + i].push_back(j * n + i + 1);
        neighbors[j * n + i + 1].push_back(j * n + i);
      }
      if (j + 1 < n) {
        neighbors[j * n + i].push_back((j + 1) * n + i);
        neighbors[(j + 1) * n + i].push_back(j * n + i);
      }
    }
  const std::vector<int> path = gp::shortest_edge_path(V, neighbors, 0, n * n - 1);
  REQUIRE(path.size() == static_cast<size_t>(2 * n - 1));
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd W = V;
    for (int k = 0; k < W.size(); ++k) W(k) += 4e-16 * u(rng);
    CHECK(gp::shortest_edge_path(W, neighbors, 0, n * n - 1) == path);
  }
}
