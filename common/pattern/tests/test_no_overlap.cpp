// No pattern is written with a piece whose outline overlaps itself (issue
// 49): a developable fan that winds 1.5 times around its centre flattens
// isometrically onto 540 degrees of the plane, so its outline crosses
// itself whatever the flattening. The cutter splits it through the
// crossing; with the split turned off export-rest fails (exit 6) and writes
// nothing.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "io/mesh_io.h"
#include "pattern/make_pattern.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"

namespace fs = std::filesystem;
using namespace gp;

namespace {

// A fan of planar triangles around one centre vertex, winding `turns`
// times (n spokes per turn), rising 0.1 m per turn, radius 0.3 m, with a
// second ring halfway along every spoke (in the same planes): a disk with
// no interior vertex, so no Gaussian curvature, and a flat angle at the
// centre of about 360 * turns degrees.
Mesh winding_fan(double turns, int per_turn) {
  const int n = static_cast<int>(std::lround(turns * per_turn));
  const double R = 0.3, rise = 0.1;
  Mesh m;
  m.V.resize(1 + 2 * (n + 1), 3);
  m.V.row(0) = Eigen::RowVector3d(0.0, 1.0, 0.0);
  for (int k = 0; k <= n; ++k) {
    const double t = 2.0 * M_PI * k / per_turn;
    const Eigen::RowVector3d p(R * std::cos(t), 1.0 - 0.5 * rise * turns + rise * t / (2.0 * M_PI), R * std::sin(t));
    m.V.row(1 + 2 * k) = 0.5 * (m.V.row(0) + p);  // mid ring
    m.V.row(2 + 2 * k) = p;                       // outer ring
  }
  std::vector<Eigen::Vector3i> faces;
  for (int k = 0; k < n; ++k) {
    const int a = 1 + 2 * k, b = 2 + 2 * k, c = 3 + 2 * k, d = 4 + 2 * k;
    faces.emplace_back(0, c, a);
    faces.emplace_back(a, c, d);
    faces.emplace_back(a, d, b);
  }
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (size_t i = 0; i < faces.size(); ++i) m.F.row(static_cast<int>(i)) = faces[i].transpose();
  return m;
}

// A band one quad wide (inner radius 0.24 m, outer 0.3 m, rising 0.1 m per
// turn) winding `turns` times: developable, and every vertex on its outline,
// so that a cut through it can only run along one of its rungs, as in a
// narrow side piece at a coarse resolution.
Mesh winding_band(double turns, int per_turn) {
  const int n = static_cast<int>(std::lround(turns * per_turn));
  const double inner = 0.24, outer = 0.3, rise = 0.1;
  Mesh m;
  m.V.resize(2 * (n + 1), 3);
  for (int k = 0; k <= n; ++k) {
    const double t = 2.0 * M_PI * k / per_turn, y = 1.0 + rise * t / (2.0 * M_PI);
    m.V.row(2 * k) = Eigen::RowVector3d(inner * std::cos(t), y, inner * std::sin(t));
    m.V.row(2 * k + 1) = Eigen::RowVector3d(outer * std::cos(t), y, outer * std::sin(t));
  }
  m.F.resize(2 * n, 3);
  for (int k = 0; k < n; ++k) {
    const int a = 2 * k, b = 2 * k + 1, c = 2 * k + 2, d = 2 * k + 3;
    m.F.row(2 * k) = Eigen::RowVector3i(a, c, b);
    m.F.row(2 * k + 1) = Eigen::RowVector3i(b, c, d);
  }
  return m;
}

PatternOptions plain_options() {
  PatternOptions o;
  o.panels.mirror = false;
  o.armholes.enabled = false;
  return o;
}

// The mesh cut as one piece, its overlap left in place.
Pattern unsplit(const Mesh& m) {
  PatternOptions o = plain_options();
  o.panels.max_overlap_splits = 0;
  return make_pattern(m.V, m.F, {}, o);
}

}  // namespace

TEST_CASE("a fan winding past a full turn is split until no piece overlaps itself", "[cutter][overlap]") {
  const Mesh fan = winding_fan(1.5, 36);
  const Pattern whole = unsplit(fan);
  REQUIRE(whole.pieces.size() == 1);
  CHECK(whole.pieces[0].flat.boundary_overlaps);  // 540 degrees cannot lie flat without overlapping
  CHECK(whole.pieces[0].stats.worst1_compression < 0.01);  // developable: no distortion, only the overlap

  const Pattern split = make_pattern(fan.V, fan.F, {}, plain_options());
  CHECK(split.pieces.size() >= 2);
  CHECK(split.pieces.size() <= 4);
  for (const PatternPiece& p : split.pieces) {
    INFO(p.name);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(p.flat.stats.flipped_triangles == 0);
  }
  CHECK(split.meets_limit);
  bool said = false;
  for (const PatternSeam& s : split.seams) said = said || s.reason.find("overlapped itself") != std::string::npos;
  CHECK(said);
}

TEST_CASE("export-rest writes no pattern with an overlapping piece", "[cli][overlap]") {
  const fs::path dir = testing::fresh_temp_dir("export-rest-overlap");
  write_mesh(dir / "fan.ply", winding_fan(1.5, 36));
  const std::string base = testing::tool_path("export-rest") + " " + (dir / "fan.ply").string() + " -q --no-mirror";
  const auto ok = testing::run_command(base + " --out " + (dir / "ok").string());
  INFO(ok.err);
  REQUIRE(ok.exit_code == 0);
  CHECK(read_json_file(dir / "ok" / "report.json")["summary"]["overlapping_pieces"] == 0);
  const auto bad = testing::run_command(base + " --max-overlap-splits 0 --out " + (dir / "bad").string());
  INFO(bad.err);
  CHECK(bad.exit_code == 6);
  CHECK(bad.err.find("error[numerical]") != std::string::npos);
  CHECK(bad.err.find("overlaps itself") != std::string::npos);
  CHECK(!fs::exists(dir / "bad"));  // nothing written
}

TEST_CASE("a band with no inner vertex, winding past a full turn, is split along its rungs", "[cutter][overlap]") {
  const Mesh band = winding_band(1.5, 48);
  const Pattern whole = unsplit(band);
  REQUIRE(whole.pieces.size() == 1);
  CHECK(whole.pieces[0].flat.boundary_overlaps);

  const Pattern split = make_pattern(band.V, band.F, {}, plain_options());
  CHECK(split.pieces.size() >= 2);
  CHECK(split.pieces.size() <= 4);
  double area = 0.0;
  for (const PatternPiece& p : split.pieces) {
    INFO(p.name);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(p.flat.stats.flipped_triangles == 0);
    area += p.stats.area_3d;
  }
  // The band's own area, 1.5 turns of the annulus (the rise tilts it by under 4 %):
  // the cuts remove no cloth.
  CHECK(area == Approx(whole.pieces[0].stats.area_3d).epsilon(1e-9));
}
