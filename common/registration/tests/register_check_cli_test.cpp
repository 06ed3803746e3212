// Command-line tests of register-check on meshes the tests build themselves,
// one per failure mode, each asserting the exit code and the message.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>

#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using gp::testing::run_command;
using gp::testing::tool_path;

namespace {

// A stand-in body: an ellipsoid 1.7 tall (y), 0.5 wide, 0.3 deep, with a flat
// bottom like the soles of feet, so that units and up can be inferred.
gp::Mesh make_body(double height = 1.7) {
  gp::Mesh m = gp::testing::make_icosphere(3, 1.0);
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    double y = std::max(m.V(i, 1), -0.9);
    m.V.row(i) = Eigen::RowVector3d(0.25 * m.V(i, 0), 0.5 * (y + 0.9) / 1.9 * 2.0, 0.15 * m.V(i, 2));
  }
  m.V *= height / (m.V.col(1).maxCoeff() - m.V.col(1).minCoeff());
  return m;
}

// Bends the upper half of the body forward a little: another "pose" with the
// same connectivity and moderate edge stretch.
gp::Mesh bend(const gp::Mesh& body, double angle) {
  gp::Mesh m = body;
  const double pivot = 0.85;
  for (Eigen::Index i = 0; i < m.V.rows(); ++i) {
    const double y = m.V(i, 1) - pivot;
    if (y <= 0) continue;
    const double a = angle * std::min(1.0, y / 0.5);
    const double z = m.V(i, 2);
    m.V(i, 1) = pivot + std::cos(a) * y - std::sin(a) * z;
    m.V(i, 2) = std::sin(a) * y + std::cos(a) * z;
  }
  return m;
}

std::string run_check(const std::vector<fs::path>& files, const fs::path& out, const std::string& extra,
                      gp::testing::CommandResult& result) {
  std::string cmd = tool_path("register-check");
  for (const auto& f : files) cmd += " '" + f.string() + "'";
  cmd += " --out '" + out.string() + "' " + extra;
  result = run_command(cmd);
  return result.err;
}

gp::Json read_report(const fs::path& out) { return gp::read_json_file(out / "report.json"); }

}  // namespace

TEST_CASE("register-check passes two poses of a valid body and normalizes them", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_pass");
  const gp::Mesh body = make_body();
  gp::write_mesh(dir / "stand.ply", body);
  gp::write_mesh(dir / "bow.obj", bend(body, 0.4));
  gp::testing::CommandResult r;
  run_check({dir / "stand.ply", dir / "bow.obj"}, dir / "out", "", r);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::Json report = read_report(dir / "out");
  CHECK(report["schema"] == "register-check-report/1");
  CHECK(report["verdict"] == "pass");
  CHECK(report["units"]["units"] == "m");
  CHECK(report["units"]["up"] == "+y");
  CHECK(report["units"]["up_ambiguous"] == false);
  const gp::Json& ratios = report["poses"][1]["edge_ratio"];
  CHECK(ratios["median"].get<double>() == Approx(1.0).margin(0.02));
  CHECK(ratios["worst_factor"].get<double>() > 1.0);
  CHECK(ratios["worst_edges"].size() == 10);
  // The normalized set loads back with the same connectivity and positions.
  const gp::PoseSet set = gp::load_pose_set(dir / "out" / "poses.json");
  REQUIRE(set.names == std::vector<std::string>{"stand", "bow"});
  CHECK(set.F == body.F);
  CHECK((set.V[0] - body.V).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(fs::exists(dir / "out" / "timing.json"));
  fs::remove_all(dir);
}

TEST_CASE("register-check converts centimetres and z-up scans to metres, +y up", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_units");
  const gp::Mesh body = make_body();
  gp::Mesh scan = body;
  // Centimetres, z up: (x, y, z)_metres -> (x, -z, y) * 100.
  for (Eigen::Index i = 0; i < scan.V.rows(); ++i)
    scan.V.row(i) = 100.0 * Eigen::RowVector3d(body.V(i, 0), -body.V(i, 2), body.V(i, 1));
  gp::write_mesh(dir / "scan.ply", scan);
  gp::testing::CommandResult r;
  run_check({dir / "scan.ply"}, dir / "out", "", r);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::Json report = read_report(dir / "out");
  CHECK(report["units"]["units"] == "cm");
  CHECK(report["units"]["up"] == "+z");
  CHECK(report["units"]["height_m"].get<double>() == Approx(1.7).epsilon(1e-9));
  const gp::PoseSet set = gp::load_pose_set(dir / "out" / "poses.json");
  CHECK((set.V[0] - body.V).cwiseAbs().maxCoeff() < 1e-12);

  // --units overrides the guess: the same file read as metres is a 170 m giant
  // and still converts as told.
  run_check({dir / "scan.ply"}, dir / "out2", "--units mm --up +z", r);
  REQUIRE(r.exit_code == 0);
  CHECK(read_report(dir / "out2")["units"]["height_m"].get<double>() == Approx(0.17).epsilon(1e-9));

  // A height that fits no unit is an error naming the way out.
  gp::Mesh tiny = body;
  tiny.V *= 0.01;
  gp::write_mesh(dir / "tiny.ply", tiny);
  run_check({dir / "tiny.ply"}, dir / "out3", "", r);
  CHECK(r.exit_code == 5);
  CHECK_THAT(r.err, Catch::Contains("cannot infer units") && Catch::Contains("--units") &&
                        Catch::Contains("--height"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  fs::remove_all(dir);
}

TEST_CASE("register-check scales a body in unknown units to a known height", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_height");
  const gp::Mesh body = make_body();
  gp::Mesh odd = body;
  odd.V *= 10.72 / 1.7;  // 10.72 units tall: no unit fits
  gp::write_mesh(dir / "odd.ply", odd);
  gp::write_mesh(dir / "odd_bow.ply", bend(odd, 0.0));
  gp::testing::CommandResult r;
  run_check({dir / "odd.ply"}, dir / "out", "", r);
  CHECK(r.exit_code == 5);
  CHECK_THAT(r.err, Catch::Contains("cannot infer units from a body height of 10.72") && Catch::Contains("--height"));
  run_check({dir / "odd.ply", dir / "odd_bow.ply"}, dir / "out2", "--height 1.65", r);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::Json report = read_report(dir / "out2");
  CHECK(report["options"]["height_m"].get<double>() == 1.65);
  CHECK(report["units"]["units"] == "height");
  CHECK(report["units"]["scaled_to_height_m"].get<double>() == 1.65);
  CHECK(report["units"]["scale_to_metres"].get<double>() == Approx(1.65 / 10.72).epsilon(1e-9));
  CHECK(report["units"]["height_m"].get<double>() == Approx(1.65).epsilon(1e-12));
  const gp::PoseSet set = gp::load_pose_set(dir / "out2" / "poses.json");
  for (const Eigen::MatrixXd& V : set.V)
    CHECK(V.col(1).maxCoeff() - V.col(1).minCoeff() == Approx(1.65).epsilon(1e-9));
  CHECK((set.V[0] - body.V * (1.65 / 1.7)).cwiseAbs().maxCoeff() < 1e-9);
  // With --up it takes any orientation; with --units it is a usage error.
  gp::Mesh sideways = odd;
  sideways.V.col(0).swap(sideways.V.col(1));
  sideways.F.col(1).swap(sideways.F.col(2));
  gp::write_mesh(dir / "sideways.ply", sideways);
  run_check({dir / "sideways.ply"}, dir / "out3", "--height 1.8 --up +x", r);
  CHECK(r.exit_code == 0);
  CHECK(read_report(dir / "out3")["units"]["height_m"].get<double>() == Approx(1.8).epsilon(1e-12));
  run_check({dir / "odd.ply"}, dir / "out4", "--height 1.8 --units cm", r);
  CHECK(r.exit_code == 2);
  CHECK_FALSE(fs::exists(dir / "out4"));
  fs::remove_all(dir);
}

TEST_CASE("register-check refuses a body whose up direction it cannot tell, in one line", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_up");
  // An ellipsoid with no flat end and one cross-section at each: nothing says which end is up.
  gp::Mesh egg = gp::testing::make_icosphere(3, 1.0);
  egg.V = egg.V * Eigen::Vector3d(0.25, 0.85, 0.15).asDiagonal();
  gp::write_mesh(dir / "egg.ply", egg);
  gp::testing::CommandResult r;
  run_check({dir / "egg.ply"}, dir / "out", "", r);
  CHECK(r.exit_code == 5);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_THAT(r.err, Catch::StartsWith("register-check: error[geometry]: egg: cannot tell which way is up") &&
                        Catch::Contains("soles say nothing") && Catch::Contains("legs say nothing") &&
                        Catch::Contains("pass --up"));
  const gp::Json report = read_report(dir / "out");
  CHECK(report["verdict"] == "error");
  CHECK(report["units"]["up_ambiguous"] == true);
  CHECK(report["units"]["up_cues"].size() == 2);
  CHECK_FALSE(fs::exists(dir / "out" / "poses.json"));
  // --up settles it.
  run_check({dir / "egg.ply"}, dir / "out2", "--up -y", r);
  CHECK(r.exit_code == 0);
  CHECK(read_report(dir / "out2")["units"]["up"] == "-y");
  CHECK(read_report(dir / "out2")["units"]["up_reason"] == "given by --up");
  // The flat-based stand-in body upside down along z is found as -z.
  const gp::Mesh body = make_body();
  gp::Mesh turned = body;
  for (Eigen::Index i = 0; i < body.V.rows(); ++i)
    turned.V.row(i) = Eigen::RowVector3d(body.V(i, 0), body.V(i, 2), -body.V(i, 1));
  gp::write_mesh(dir / "turned.ply", turned);
  run_check({dir / "turned.ply"}, dir / "out3", "", r);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  const gp::Json turned_report = read_report(dir / "out3");
  CHECK(turned_report["units"]["up"] == "-z");
  CHECK(turned_report["units"]["up_cues"][0]["vote"] == "-z");
  fs::remove_all(dir);
}

TEST_CASE("register-check recovers a permuted vertex order only with --reorder", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_perm");
  const gp::Mesh body = make_body();
  const gp::Mesh pose = bend(body, 0.5);
  // Shuffle vertices and faces and rotate each face's corners.
  std::vector<int> perm(static_cast<size_t>(pose.V.rows()));
  std::iota(perm.begin(), perm.end(), 0);
  std::mt19937 rng(7);
  std::shuffle(perm.begin(), perm.end(), rng);
  gp::Mesh shuffled;
  shuffled.V.resize(pose.V.rows(), 3);
  for (Eigen::Index i = 0; i < pose.V.rows(); ++i) shuffled.V.row(perm[i]) = pose.V.row(i);
  std::vector<int> face_order(static_cast<size_t>(pose.F.rows()));
  std::iota(face_order.begin(), face_order.end(), 0);
  std::shuffle(face_order.begin(), face_order.end(), rng);
  shuffled.F.resize(pose.F.rows(), 3);
  for (Eigen::Index f = 0; f < pose.F.rows(); ++f) {
    const int src = face_order[f], rot = static_cast<int>(f % 3);
    for (int k = 0; k < 3; ++k) shuffled.F(f, k) = perm[pose.F(src, (k + rot) % 3)];
  }
  gp::write_mesh(dir / "a.ply", body);
  gp::write_mesh(dir / "b.ply", shuffled);

  gp::testing::CommandResult r;
  run_check({dir / "a.ply", dir / "b.ply"}, dir / "out", "", r);
  CHECK(r.exit_code == 5);
  CHECK_THAT(r.err, Catch::Contains("vertices in another order") && Catch::Contains("--reorder"));
  CHECK(read_report(dir / "out")["poses"][1]["connectivity"] == "permuted");
  CHECK_FALSE(fs::exists(dir / "out" / "poses.json"));

  run_check({dir / "a.ply", dir / "b.ply"}, dir / "out2", "--reorder", r);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::PoseSet set = gp::load_pose_set(dir / "out2" / "poses.json");
  CHECK(set.F == body.F);
  CHECK((set.V[1] - pose.V).cwiseAbs().maxCoeff() == 0.0);
  CHECK(read_report(dir / "out2")["poses"][1]["reordered"] == true);
  fs::remove_all(dir);
}

TEST_CASE("register-check rejects each kind of broken geometry with exit 5", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_broken");
  const gp::Mesh body = make_body();
  gp::testing::CommandResult r;
  struct Case {
    std::string name;
    gp::Mesh mesh;
    std::string message;
  };
  std::vector<Case> cases;
  {
    gp::Mesh m = body;
    std::swap(m.F(10, 1), m.F(10, 2));
    cases.push_back({"flipped", m, "inconsistent orientation"});
  }
  {
    gp::Mesh m = body;
    gp::Mesh holed;
    holed.V = m.V;
    holed.F.resize(m.F.rows() - 1, 3);
    holed.F << m.F.topRows(17), m.F.bottomRows(m.F.rows() - 18);
    cases.push_back({"hole", holed, "not closed: 1 holes"});
  }
  {
    gp::Mesh m = body;
    m.V(5, 1) = std::nan("");
    cases.push_back({"nan", m, "NaN or infinite coordinates, e.g. vertex 5"});
  }
  {
    // A duplicated vertex that one face uses instead of the original splits the
    // surface open around it.
    gp::Mesh m = body;
    m.V.conservativeResize(m.V.rows() + 1, 3);
    m.V.row(m.V.rows() - 1) = m.V.row(m.F(0, 0));
    m.F(0, 0) = static_cast<int>(m.V.rows() - 1);
    cases.push_back({"duplicate", m, "not closed"});
  }
  {
    gp::Mesh m = body;
    m.V.row(m.F(3, 1)) = m.V.row(m.F(3, 0));  // collapse an edge of face 3
    cases.push_back({"degenerate", m, "degenerate (zero-area) triangles"});
  }
  {
    // Two faces glued onto an existing edge: three faces share it.
    gp::Mesh m = body;
    m.V.conservativeResize(m.V.rows() + 1, 3);
    m.V.row(m.V.rows() - 1) = Eigen::RowVector3d(0, 0, 2);
    m.F.conservativeResize(m.F.rows() + 1, 3);
    m.F.row(m.F.rows() - 1) << m.F(0, 0), m.F(0, 1), static_cast<int>(m.V.rows() - 1);
    cases.push_back({"nonmanifold", m, "non-manifold"});
  }
  for (const Case& c : cases) {
    SECTION(c.name) {
      gp::write_mesh(dir / (c.name + ".ply"), c.mesh);
      run_check({dir / (c.name + ".ply")}, dir / ("out_" + c.name), "", r);
      INFO(r.err);
      CHECK(r.exit_code == 5);
      CHECK_THAT(r.err, Catch::Contains("register-check: error[geometry]: " + c.name) &&
                            Catch::Contains(c.message) && Catch::Contains(c.name + ".ply"));
      // The report is written; the normalized poses are not.
      CHECK(read_report(dir / ("out_" + c.name))["verdict"] == "error");
      CHECK_FALSE(fs::exists(dir / ("out_" + c.name) / "poses.json"));
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("register-check accepts open meshes only with --allow-open", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_open");
  gp::Mesh tube = gp::testing::make_open_cylinder(24, 20, 0.2, 1.7);
  gp::write_mesh(dir / "tube.ply", tube);
  gp::testing::CommandResult r;
  run_check({dir / "tube.ply"}, dir / "out", "--up +y", r);
  CHECK(r.exit_code == 5);
  CHECK_THAT(r.err, Catch::Contains("2 holes"));
  run_check({dir / "tube.ply"}, dir / "out2", "--up +y --allow-open", r);
  CHECK(r.exit_code == 0);
  CHECK(read_report(dir / "out2")["poses"][0]["checks"]["boundary_loops"] == 2);
  // A torus is closed: fine without the flag (genus does not matter).
  gp::Mesh torus = gp::testing::make_torus(40, 16, 0.7, 0.2);
  gp::write_mesh(dir / "torus.ply", torus);
  run_check({dir / "torus.ply"}, dir / "out3", "--up +y --units m", r);
  CHECK(r.exit_code == 0);
  fs::remove_all(dir);
}

TEST_CASE("register-check rejects unreadable files with exit 3 and no output", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_input");
  const gp::Mesh body = make_body();
  gp::write_mesh(dir / "good.ply", body);
  gp::testing::CommandResult r;
  {
    std::ofstream(dir / "empty.ply");
    run_check({dir / "empty.ply"}, dir / "out", "", r);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("error[input]: empty file") && Catch::Contains("empty.ply"));
  }
  {
    // Cut a binary PLY in the middle of its face list.
    const auto size = fs::file_size(dir / "good.ply");
    fs::copy_file(dir / "good.ply", dir / "cut.ply");
    fs::resize_file(dir / "cut.ply", size - 100);
    run_check({dir / "cut.ply"}, dir / "out", "", r);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("truncated binary PLY") && Catch::Contains("cut.ply: face"));
  }
  {
    std::ofstream out(dir / "range.obj");
    out << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n";
    out.close();
    run_check({dir / "range.obj"}, dir / "out", "", r);
    CHECK(r.exit_code == 3);
    CHECK_THAT(r.err, Catch::Contains("vertex index 6 out of range [0, 3)") &&
                          Catch::Contains("range.obj: face 1"));
  }
  run_check({dir / "missing.ply"}, dir / "out", "", r);
  CHECK(r.exit_code == 3);
  CHECK_THAT(r.err, Catch::Contains("no such file"));
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST_CASE("register-check rejects poses that are not one mesh", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_corr");
  gp::write_mesh(dir / "a.ply", make_body());
  // Same vertex count, different triangles: a sphere of the same size with a
  // different tessellation is impossible to relabel onto the first.
  gp::Mesh other = make_body();
  std::swap(other.F(0, 1), other.F(1, 1));
  std::swap(other.F(2, 1), other.F(3, 2));
  gp::write_mesh(dir / "b.ply", other);
  gp::Mesh coarse = gp::testing::make_icosphere(2);
  gp::write_mesh(dir / "c.ply", coarse);
  gp::testing::CommandResult r;
  run_check({dir / "a.ply", dir / "c.ply"}, dir / "out", "", r);
  CHECK(r.exit_code == 5);
  CHECK_THAT(r.err, Catch::Contains("poses not in correspondence: 162 vertices"));
  run_check({dir / "a.ply", dir / "b.ply"}, dir / "out2", "--reorder", r);
  CHECK(r.exit_code == 5);
  CHECK_THAT(r.err, Catch::Contains("b: poses not in correspondence") ||
                        Catch::Contains("b: non-manifold") || Catch::Contains("b: inconsistent"));
  fs::remove_all(dir);
}

TEST_CASE("register-check fails a registration error with exit 8 and writes the report",
          "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_reg");
  const gp::Mesh body = make_body();
  gp::Mesh bad = bend(body, 0.3);
  bad.V.row(100) += Eigen::RowVector3d(0.0, 0.0, 0.8);  // a vertex thrown 80 cm away
  gp::write_mesh(dir / "a.ply", body);
  gp::write_mesh(dir / "b.ply", bad);
  gp::testing::CommandResult r;
  run_check({dir / "a.ply", dir / "b.ply"}, dir / "out", "", r);
  CHECK(r.exit_code == 8);
  // One line: the failed check, and where the rest is.
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_THAT(r.err, Catch::StartsWith("register-check: error[check]: b: registration: an edge changes length") &&
                        Catch::Contains("report.json"));
  const gp::Json report = read_report(dir / "out");
  CHECK(report["verdict"] == "fail");
  const gp::Json& worst = report["poses"][1]["edge_ratio"]["worst_edges"][0];
  CHECK((worst["v0"] == 100 || worst["v1"] == 100));
  // A looser limit lets it through.
  run_check({dir / "a.ply", dir / "b.ply"}, dir / "out2", "--max-edge-ratio 1000", r);
  CHECK(r.exit_code == 0);
  fs::remove_all(dir);
}

TEST_CASE("register-check follows the shared command-line conventions", "[register-check]") {
  const fs::path dir = gp::testing::fresh_temp_dir("rc_cli");
  gp::testing::CommandResult r = run_command(tool_path("register-check") + " --help");
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Catch::Contains("--max-edge-ratio") && Catch::Contains("[ratio]") &&
                        Catch::Contains("--out") && Catch::Contains("--threads") &&
                        Catch::Contains("8"));
  r = run_command(tool_path("register-check") + " --bogus x");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("register-check: error[usage]"));
  gp::write_mesh(dir / "a.ply", make_body());
  r = run_command(tool_path("register-check") + " '" + (dir / "a.ply").string() + "' --out '" +
                  dir.string() + "'");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("--force"));
  fs::remove_all(dir);
}

TEST_CASE("register-check on the shared registered avatars", "[register-check][shared]") {
  const fs::path shared = gp::testing::shared_avatars_dir();
  if (shared.empty()) {
    WARN("skipped: ../shared/avatars not found beside the checkout");
    return;
  }
  const fs::path dir = gp::testing::fresh_temp_dir("rc_shared");
  gp::testing::CommandResult r = run_command(tool_path("register-check") + " '" + shared.string() +
                                             "' --reference slim_apose --threads 2 --out '" +
                                             (dir / "out").string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::Json report = read_report(dir / "out");
  CHECK(report["units"]["units"] == "m");
  CHECK(report["units"]["up"] == "+y");
  CHECK(report["vertex_count"] == 27578);
  for (const auto& pose : report["poses"]) {
    CHECK(pose["connectivity"] == "identical");
    if (pose["name"] == "slim_apose") continue;
    CHECK(pose["edge_ratio"]["median"].get<double>() == Approx(1.0).margin(0.02));
    CHECK(pose["edge_ratio"]["worst_factor"].get<double>() < 8.0);
  }

  // The original data set stored the T-pose re-indexed; --reorder recovers it.
  gp::Mesh tpose = gp::read_mesh(shared / "slim_tpose.ply").mesh;
  std::vector<int> perm(static_cast<size_t>(tpose.V.rows()));
  std::iota(perm.begin(), perm.end(), 0);
  std::mt19937 rng(11);
  std::shuffle(perm.begin(), perm.end(), rng);
  gp::Mesh shuffled = tpose;
  for (Eigen::Index i = 0; i < tpose.V.rows(); ++i) shuffled.V.row(perm[i]) = tpose.V.row(i);
  for (Eigen::Index f = 0; f < tpose.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) shuffled.F(f, k) = perm[tpose.F(f, k)];
  gp::write_mesh(dir / "tpose_shuffled.ply", shuffled);
  r = run_command(tool_path("register-check") + " '" + (shared / "slim_apose.ply").string() + "' '" +
                  (dir / "tpose_shuffled.ply").string() + "' --reorder --no-self-intersections --out '" +
                  (dir / "out2").string() + "'");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const gp::PoseSet set = gp::load_pose_set(dir / "out2" / "poses.json");
  CHECK((set.V[1] - tpose.V).cwiseAbs().maxCoeff() == 0.0);
  fs::remove_all(dir);
}
