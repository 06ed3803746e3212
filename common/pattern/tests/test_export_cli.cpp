#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "pattern/make_pattern.h"
#include "pattern/pdf_writer.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"
#include "testing/test_meshes.h"

using namespace gp;
namespace fs = std::filesystem;

namespace {

// A minimal DXF reader: closed POLYLINE entities on `layer`, as lists of (x, y).
std::vector<std::vector<Eigen::Vector2d>> read_dxf_polylines(const fs::path& path, const std::string& layer) {
  std::ifstream in(path);
  std::vector<std::pair<int, std::string>> pairs;
  std::string code, value;
  while (std::getline(in, code) && std::getline(in, value)) pairs.emplace_back(std::stoi(code), value);
  std::vector<std::vector<Eigen::Vector2d>> polylines;
  bool in_polyline = false, keep = false;
  std::string entity;
  Eigen::Vector2d vertex(0, 0);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const auto& [c, v] = pairs[i];
    if (c == 0) {
      if (entity == "VERTEX" && in_polyline && keep) polylines.back().push_back(vertex);
      entity = v;
      if (v == "POLYLINE") in_polyline = true, keep = false;
      if (v == "SEQEND") in_polyline = false;
      continue;
    }
    if (entity == "POLYLINE" && c == 8) {
      keep = v == layer;
      if (keep) polylines.emplace_back();
    }
    if (entity == "VERTEX" && c == 10) vertex.x() = std::stod(v);
    if (entity == "VERTEX" && c == 20) vertex.y() = std::stod(v);
  }
  return polylines;
}

double closed_length(const std::vector<Eigen::Vector2d>& p) {
  double s = 0.0;
  for (size_t i = 0; i < p.size(); ++i) s += (p[(i + 1) % p.size()] - p[i]).norm();
  return s;
}

struct CylinderCase {
  fs::path dir;
  int nu = 24, nv = 10;
  double radius = 0.12, height = 0.5;
  CylinderCase() {
    dir = testing::fresh_temp_dir("export-rest-cli");
    const Mesh cyl = testing::make_open_cylinder(nu, nv, radius, height);
    write_mesh(dir / "rest.ply", cyl);
    GarmentFile g;
    g.name = "sleeve";
    g.mesh_file = "rest.ply";
    g.mesh_sha256 = "0";
    g.vertex_count = cyl.V.rows();
    g.face_count = cyl.F.rows();
    g.body = {"none", "0", "tpose", 0, 0, "0", ""};
    g.spec_file = "none";
    g.spec_sha256 = "0";
    g.target_edge_length = 0.03;
    GarmentLoop hem, top;
    hem.name = "cuff";
    top.name = "armhole";
    for (int i = 0; i < nu; ++i) hem.vertex_ids.push_back(i), top.vertex_ids.push_back(nv * nu + i);
    g.loops = {hem, top};
    g.paint.assign(static_cast<size_t>(cyl.F.rows()), 1.0);
    write_garment_file(dir / "garment.json", g);
    write_spec("seams.json", R"({"schema": "seam-spec/1", "seams": [{"name": "underarm", "points": [0, 240]}]})");
  }
  void write_spec(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
  }
  testing::CommandResult run(const std::string& out, const std::string& seams = "seams.json",
                             const std::string& extra = "") const {
    return testing::run_command(testing::tool_path("export-rest") + " " + (dir / "rest.ply").string() +
                                " --garment " + (dir / "garment.json").string() + " --seams " +
                                (dir / seams).string() + " --out " + (dir / out).string() + " -q " + extra);
  }
};

}  // namespace

TEST_CASE("export-rest writes a 1:1 pattern of a sleeve", "[cli]") {
  const CylinderCase c;
  const auto r = c.run("out");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  for (const char* f : {"pattern.svg", "pattern.dxf", "pieces.obj", "pieces_flat.ply", "report.json", "timing.json"})
    CHECK(fs::exists(c.dir / "out" / f));
  const Json report = read_json_file(c.dir / "out" / "report.json");
  CHECK(report["schema"] == "export-rest-report/1");
  CHECK(report["summary"]["pieces"] == 1);
  CHECK(report["summary"]["meets_distortion_limit"] == true);
  CHECK(report["options"]["layout"]["seam_allowance_m"] == 0.01);
  CHECK(report["options"]["pattern"]["mirror"] == true);
  CHECK(report["options"]["pattern"]["flatten"]["ease_weight"] == 0.1);
  // The options read back, strictly, to those the stage ran with.
  PatternOptions back;
  back.darts.max_darts = 99;
  back.flatten.ease_weight = 1.0;
  read_options(SpecObject(report["options"]["pattern"], "report.json", "/options/pattern"), true, back,
               PatternOptionFields{});
  CHECK(back.darts.max_darts == PatternOptions{}.darts.max_darts);
  CHECK(back.flatten.ease_weight == PatternOptions{}.flatten.ease_weight);
  CHECK(back.seams.smoothing.trace.max_steps == PatternOptions{}.seams.smoothing.trace.max_steps);
  CHECK(report["sewn_fit"]["checked"] == false);
  const double width = c.nu * 2.0 * c.radius * std::sin(M_PI / c.nu);
  const double outline = report["pieces"][0]["outline_length"];
  CHECK(outline == Approx(2.0 * (width + c.height)).epsilon(1e-6));
  CHECK(report["pieces"][0]["area_2d"].get<double>() == Approx(width * c.height).epsilon(1e-6));
  REQUIRE(report["seams"].size() == 1);
  CHECK(report["seams"][0]["mismatch"].get<double>() < 1e-6);
  CHECK(report["seams"][0]["left"]["length_2d"].get<double>() == Approx(c.height).epsilon(1e-6));
  // Notches: at 0, 0.1, ..., 0.5 m on each side.
  CHECK(report["seams"][0]["notches"] == 12);
  // The cutting line of a rectangle offset by 1 cm with mitred corners.
  CHECK(report["pieces"][0]["cutting_line_length"].get<double>() ==
        Approx(2.0 * (width + c.height) + 8 * 0.01).epsilon(1e-6));
  // Flat, like the other stages': the tool, seconds per phase and the total.
  const Json timing = read_json_file(c.dir / "out" / "timing.json");
  CHECK(timing["schema"] == "timing/1");
  CHECK(timing["tool"] == "export-rest");
  CHECK(!timing.contains("seconds"));
  REQUIRE(timing.contains("total_s"));
  CHECK(timing["total_s"].get<double>() >= 0.0);
  for (auto it = timing.begin(); it != timing.end(); ++it) CHECK(!it.value().is_object());

  // The flat mesh: one component, z = 0, as many triangles as the rest shape.
  const Mesh flat = read_mesh(c.dir / "out" / "pieces_flat.ply").mesh;
  CHECK(flat.F.rows() == 2 * c.nu * c.nv);
  CHECK(flat.V.col(2).cwiseAbs().maxCoeff() == 0.0);

  SECTION("the SVG is XML with millimetre dimensions") {
    const std::string script =
        "import sys, xml.etree.ElementTree as ET\n"
        "r = ET.parse(sys.argv[1]).getroot()\n"
        "ns = {'s': 'http://www.w3.org/2000/svg'}\n"
        "w, h = r.get('width'), r.get('height')\n"
        "vb = r.get('viewBox').split()\n"
        "assert w.endswith('mm') and h.endswith('mm'), (w, h)\n"
        "assert abs(float(w[:-2]) - float(vb[2])) < 1e-6 and abs(float(h[:-2]) - float(vb[3])) < 1e-6\n"
        "print(len(r.findall('.//s:path[@class=\"sew\"]', ns)), len(r.findall('.//s:line[@class=\"notch\"]', ns)), w, h)\n";
    std::ofstream(c.dir / "check_svg.py") << script;
    const auto py = testing::run_command("/usr/bin/python3 " + (c.dir / "check_svg.py").string() + " " +
                                         (c.dir / "out" / "pattern.svg").string());
    INFO(py.err);
    REQUIRE(py.exit_code == 0);
    std::istringstream words(py.out);
    int sew = 0, notches = 0;
    std::string w, h;
    words >> sew >> notches >> w >> h;
    CHECK(sew == 1);
    CHECK(notches == 12);
    // Width of the sheet: the piece (its shorter side across, after turning
    // the grain up) plus allowance and margins, in mm.
    CHECK(std::stod(w) > 1000.0 * (std::min(width, c.height)));
  }

  SECTION("the plain DXF reads back with the same outline lengths") {
    REQUIRE(c.run("plain", "seams.json", "--dxf-profile plain").exit_code == 0);
    const auto sew = read_dxf_polylines(c.dir / "plain" / "pattern.dxf", "SEW");
    const auto cut = read_dxf_polylines(c.dir / "plain" / "pattern.dxf", "CUT");
    REQUIRE(sew.size() == 1);
    REQUIRE(cut.size() == 1);
    CHECK(closed_length(sew[0]) == Approx(1000.0 * outline).margin(0.01));
    CHECK(closed_length(cut[0]) == Approx(1000.0 * report["pieces"][0]["cutting_line_length"].get<double>()).margin(0.01));
    const std::string script =
        "import sys, ezdxf, math\n"
        "doc = ezdxf.readfile(sys.argv[1])\n"
        "for e in doc.modelspace().query('POLYLINE[layer==\"SEW\"]'):\n"
        "    p = [(v.dxf.location.x, v.dxf.location.y) for v in e.vertices]\n"
        "    print(sum(math.dist(p[i], p[(i + 1) % len(p)]) for i in range(len(p))))\n";
    std::ofstream(c.dir / "check_dxf.py") << script;
    if (testing::run_command("/usr/bin/python3 -c 'import ezdxf'").exit_code != 0) {
      WARN("skipped the ezdxf check: python3-ezdxf is not installed");
    } else {
      const auto py = testing::run_command("/usr/bin/python3 " + (c.dir / "check_dxf.py").string() + " " +
                                           (c.dir / "plain" / "pattern.dxf").string());
      INFO(py.err);
      REQUIRE(py.exit_code == 0);
      CHECK(std::stod(py.out) == Approx(1000.0 * outline).margin(0.01));
    }
  }

  SECTION("the same inputs give byte-identical outputs") {
    const auto again = c.run("again");
    REQUIRE(again.exit_code == 0);
    for (const char* f : {"pattern.svg", "pattern.dxf", "pieces.obj", "pieces_flat.ply", "report.json"})
      CHECK(gp::testing::read_file(c.dir / "out" / f) == gp::testing::read_file(c.dir / "again" / f));
  }

  SECTION("an existing output folder needs --force") {
    const auto r2 = c.run("out");
    CHECK(r2.exit_code == 2);
    CHECK(c.run("out", "seams.json", "--force").exit_code == 0);
  }
}

TEST_CASE("export-rest writes the industry DXF (ASTM D6673, AAMA) that ezdxf reads back as the SVG", "[cli][dxf]") {
  const CylinderCase c;
  // Two seams: two pieces, so that "one block per piece" is a real check.
  c.write_spec("two.json", R"({"schema": "seam-spec/1", "seams": [{"name": "underarm", "points": [0, 240]},
                                                                  {"name": "top", "points": [12, 252]}]})");
  if (testing::run_command("/usr/bin/python3 -c 'import ezdxf'").exit_code != 0) {
    WARN("skipped: python3-ezdxf is not installed (scripts/install-deps.sh installs it)");
    return;
  }
  const std::string script = (testing::source_dir() / "common/pattern/tests/check_industry_dxf.py").string();
  for (const std::string profile : {"astm", "aama"}) {
    INFO(profile);
    const auto r = c.run(profile, "two.json", "--dxf-profile " + profile + " --size 'Ann O\xc3\xa9' --creation-date 2026-12-01");
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const Json report = read_json_file(c.dir / profile / "report.json");
    CHECK(report["options"]["dxf"]["profile"] == profile);
    const auto py = testing::run_command("/usr/bin/python3 " + script + " " + (c.dir / profile / "pattern.dxf").string() +
                                         " " + (c.dir / profile / "pattern.svg").string() + " " + profile);
    INFO(py.out << py.err);
    REQUIRE(py.exit_code == 0);
    const Json figures = Json::parse(py.out);
    CHECK(figures["blocks"] == report["summary"]["pieces"]);
    CHECK(figures["blocks"].get<int>() == 2);
    CHECK(figures["worst_mm"].get<double>() < 0.1);
    int notches = 0;
    for (const auto& s : report["seams"]) notches += s["notches"].get<int>();
    CHECK(figures["notches"] == notches);
    CHECK(figures["style"][1] == "Creation Date: 2026-12-01");
    CHECK(figures["style"][3] == "Sample Size: Ann O?");  // UTF-8 "e acute" as one '?' 
  }
}

TEST_CASE("export-rest writes tiled PDFs whose test square prints true to size", "[cli][pdf]") {
  const CylinderCase c;
  if (testing::run_command("command -v pdftoppm pdftotext pdfinfo >/dev/null").exit_code != 0) {
    WARN("skipped: poppler-utils is not installed (scripts/install-deps.sh installs it)");
    return;
  }
  const auto r = c.run("out");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const Json report = read_json_file(c.dir / "out" / "report.json");
  REQUIRE(report["sheets"].size() == 4);
  const std::string script = (testing::source_dir() / "common/pattern/tests/check_pdf.py").string();
  auto check = [&](const std::string& file, const std::string& squares) {
    const auto py = testing::run_command("/usr/bin/python3 " + script + " " + (c.dir / "out" / file).string() + " " +
                                         (c.dir / "out" / "report.json").string() + " " + squares);
    INFO(file << ": " << py.out << py.err);
    REQUIRE(py.exit_code == 0);
    return Json::parse(py.out);
  };
  // The sleeve's piece (about 0.75 x 0.5 m with allowance) needs several A4 pages.
  const Json a4 = check("pattern-a4.pdf", "100");
  CHECK(a4["rows"].get<int>() * a4["columns"].get<int>() >= 4);
  const Json letter = check("pattern-letter.pdf", "100 101.6");
  CHECK(letter["pages"].get<int>() >= 5);
  const Json a0 = check("pattern-a0.pdf", "100");
  CHECK(a0["pages"] == 2);  // the cover and one A0 page
  check("pattern-roll914.pdf", "100");
  // The same inputs give the same PDF.
  REQUIRE(c.run("again").exit_code == 0);
  CHECK(testing::read_file(c.dir / "out" / "pattern-a4.pdf") == testing::read_file(c.dir / "again" / "pattern-a4.pdf"));
}

TEST_CASE("tile_pages leaves out the pages no piece reaches", "[pdf]") {
  // Two small squares at opposite corners of a 60 x 60 cm sheet: on A4 (19 x
  // 27.7 cm printable, 1 cm overlap) 4 columns and 3 rows, of which only the
  // two corner tiles are printed.
  Layout layout;
  layout.width = 0.6;
  layout.height = 0.6;
  auto square = [](double x, double y, double a) {
    LaidOutPiece p;
    p.outline = {{x, y}, {x + a, y}, {x + a, y + a}, {x, y + a}};
    return p;
  };
  // Columns start at 0, 0.18, 0.36, 0.54 m (the third ends at 0.55), rows
  // end downwards at 0.323, 0.056 and below.
  layout.pieces = {square(0.01, 0.54, 0.05), square(0.56, 0.01, 0.03)};
  PdfOptions o;
  o.paper = paper_a4();
  const PdfSummary s = tile_pages(layout, o);
  CHECK(s.columns * s.rows == 12);
  int printed = 0;
  for (const PdfPage& t : s.tiles) printed += t.printed ? 1 : 0;
  CHECK(printed == 2);
  CHECK(s.pages == 3);
  CHECK(s.tiles.front().printed);
  CHECK(s.tiles.back().printed);
  CHECK(s.tiles.front().label == "A1");
}

TEST_CASE("export-rest: bad seam specs exit with their category and name the seam", "[cli][errors]") {
  const CylinderCase c;
  c.write_spec("far.json", R"({"schema": "seam-spec/1", "seams": [{"name": "collar", "points": [0, [3.0, 0.0, 0.0]]}]})");
  auto r = c.run("o1", "far.json");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("export-rest: error[spec]") != std::string::npos);
  CHECK(r.err.find("seam 'collar'") != std::string::npos);

  c.write_spec("inside.json", R"({"schema": "seam-spec/1", "seams": [{"name": "pocket", "points": [50, 54]}]})");
  r = c.run("o2", "inside.json");
  CHECK(r.exit_code == 5);
  CHECK(r.err.find("error[geometry]") != std::string::npos);
  CHECK(r.err.find("seam 'pocket'") != std::string::npos);

  c.write_spec("typo.json", R"({"schema": "seam-spec/1", "seamz": []})");
  r = c.run("o3", "typo.json");
  CHECK(r.exit_code == 4);
  CHECK(!fs::exists(c.dir / "o1"));
  CHECK(!fs::exists(c.dir / "o2"));

  r = c.run("o4", "seams.json", "--p95-limit 0.1 --max-limit 0.05");
  CHECK(r.exit_code == 2);
  r = testing::run_command(testing::tool_path("export-rest") + " " + (c.dir / "missing.ply").string() + " --out " +
                           (c.dir / "o5").string());
  CHECK(r.exit_code == 3);
}
