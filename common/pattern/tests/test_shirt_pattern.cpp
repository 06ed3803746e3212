// The pattern of a shirt on a generated body (the demo customer: make-avatar,
// make-garment, the demo's side and shoulder seams), cut by export-rest: a
// few recognisable pieces, and cuts that noise of 1e-7 m on the rest shape
// does not change.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <utility>

#include "io/mesh_io.h"
#include "pattern/piece_names.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"

namespace fs = std::filesystem;
using namespace gp;

namespace {

// make-avatar and make-garment once for all test cases of this file.
struct Shirt {
  fs::path dir;
  fs::path seams;
  bool ok = false;
  std::string error;
  Shirt() {
    dir = testing::fresh_temp_dir("export-rest-shirt");
    const fs::path customer = testing::source_dir() / "testdata" / "customers" / "small-shirt";
    seams = testing::source_dir() / "pipelines" / "customers" / "demo" / "seams.json";
    auto r = testing::run_command(testing::tool_path("make-avatar") + " " + (customer / "avatar.json").string() +
                                  " --poses apose,tpose -q --out " + (dir / "body").string());
    if (r.exit_code != 0) {
      error = "make-avatar: " + r.err;
      return;
    }
    r = testing::run_command(testing::tool_path("make-garment") + " " + (customer / "garment-spec.json").string() +
                             " --poses " + (dir / "body" / "poses.json").string() + " -q --out " +
                             (dir / "garment").string());
    if (r.exit_code != 0) {
      error = "make-garment: " + r.err;
      return;
    }
    ok = true;
  }
  testing::CommandResult cut(const fs::path& rest, const std::string& out, const std::string& extra = "") const {
    return testing::run_command(testing::tool_path("export-rest") + " " + rest.string() + " --garment " +
                                (dir / "garment" / "garment.json").string() + " --seams " + seams.string() +
                                " --body " + (dir / "body" / "poses.json").string() + " -q --out " +
                                (dir / out).string() + " " + extra);
  }
};

const Shirt& shirt() {
  static const Shirt s;
  return s;
}

// The seams of seams.obj: name -> polyline (#points by 3).
std::map<std::string, Eigen::MatrixXd> read_seams(const fs::path& path) {
  std::ifstream in(path);
  std::map<std::string, std::vector<Eigen::Vector3d>> points;
  std::string line, name;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "o") words >> name;
    if (tag == "v") {
      Eigen::Vector3d x;
      words >> x.x() >> x.y() >> x.z();
      points[name].push_back(x);
    }
  }
  std::map<std::string, Eigen::MatrixXd> out;
  for (const auto& [n, p] : points) {
    Eigen::MatrixXd P(static_cast<int>(p.size()), 3);
    for (size_t i = 0; i < p.size(); ++i) P.row(static_cast<int>(i)) = p[i].transpose();
    out[n] = P;
  }
  return out;
}

// Largest distance from a point of A to the polyline B.
double one_sided_hausdorff(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  double worst = 0.0;
  for (int i = 0; i < A.rows(); ++i) {
    double d = std::numeric_limits<double>::infinity();
    for (int j = 0; j + 1 < B.rows(); ++j) {
      const Eigen::Vector3d a = B.row(j), b = B.row(j + 1), q = A.row(i);
      const double l2 = (b - a).squaredNorm();
      const double t = l2 > 0.0 ? std::clamp((q - a).dot(b - a) / l2, 0.0, 1.0) : 0.0;
      d = std::min(d, (a + t * (b - a) - q).norm());
    }
    if (B.rows() == 1) d = (A.row(i) - B.row(0)).norm();
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace

TEST_CASE("a generated shirt's pattern has a few recognisable pieces", "[cli][shirt]") {
  const Shirt& s = shirt();
  INFO(s.error);
  REQUIRE(s.ok);
  const auto r = s.cut(s.dir / "garment" / "garment.ply", "pattern");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const Json report = read_json_file(s.dir / "pattern" / "report.json");
  const Json& sum = report["summary"];
  INFO(sum.dump());
  CHECK(sum["pieces"].get<int>() <= 12);
  CHECK(sum["most_darts_in_a_piece"].get<int>() <= 2);
  // No piece under 100 cm^2 unless the user's seams make it: the demo's
  // short sleeves are halved by its shoulder and side seams, so only their
  // halves (between those seams and the armhole) may be smaller.
  for (const auto& p : report["pieces"])
    if (p["area_3d"].get<double>() < 0.01) CHECK(p["name"].get<std::string>().find("sleeve") != std::string::npos);
  CHECK(sum["flipped_triangles"] == 0);
  CHECK(sum["seams_within_tolerance"] == true);
  CHECK(sum["total_seam_length"].get<double>() <=
        2.0 * (sum["user_seam_length"].get<double>() + sum["boundary_length"].get<double>()));
  // Named by body region, every name once: a front and a back, and sleeves.
  std::map<std::string, int> names;
  bool front = false, back = false, sleeve = false;
  for (const auto& p : report["pieces"]) {
    const std::string n = p["name"];
    ++names[n];
    front = front || n.find("front") != std::string::npos;
    back = back || n.find("back") != std::string::npos;
    sleeve = sleeve || n.find("sleeve") != std::string::npos;
  }
  for (const auto& [n, count] : names) CHECK(count == 1);
  CHECK(front);
  CHECK(back);
  CHECK(sleeve);
  // Every dart is a wedge drawn as one: a fold line and a drill hole per dart.
  const std::string svg = testing::read_file(s.dir / "pattern" / "pattern.svg");
  auto count = [&](const std::string& what) {
    size_t n = 0;
    for (size_t at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
    return static_cast<int>(n);
  };
  CHECK(count("class=\"drill\"") == sum["darts"].get<int>());
  CHECK(count("class=\"fold\"") == sum["darts"].get<int>());
}

TEST_CASE("noise of 1e-7 m on the rest shape changes no cut", "[cli][shirt][reproducibility]") {
  const Shirt& s = shirt();
  INFO(s.error);
  REQUIRE(s.ok);
  const Mesh rest = read_mesh(s.dir / "garment" / "garment.ply").mesh;
  // The plain flattening's pieces stay within 0.1 mm: they are converged,
  // not stopped where the last bits say. The limit weighting (the default)
  // weighs a triangle by its excess over 80 % of the limit, and the rounds
  // before the kept one carry those weights: 1e-7 m of noise moves its
  // printed pieces by 0.26-0.64 mm (the same pieces and cuts), under a
  // cutter's millimetre, and that is what it is held to.
  for (const auto& [flags, flat_tolerance] :
       {std::pair<std::string, double>{"--limit-rounds 0 --min-relief-share 0", 1e-4}, {"", 1e-3}}) {
    INFO("flags '" << flags << "'");
    const std::string tag = flags.empty() ? "d" : "p";
    const auto base = s.cut(s.dir / "garment" / "garment.ply", "noise0" + tag, flags);
    REQUIRE(base.exit_code == 0);
    const Json reference = read_json_file(s.dir / ("noise0" + tag) / "report.json");
    const auto seams0 = read_seams(s.dir / ("noise0" + tag) / "seams.obj");
    const Mesh flat0 = read_mesh(s.dir / ("noise0" + tag) / "pieces_flat.ply").mesh;
    for (unsigned seed : {1u, 2u, 3u}) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> noise(-1e-7, 1e-7);
      Mesh moved = rest;
      for (int i = 0; i < moved.V.size(); ++i) moved.V.data()[i] += noise(rng);
      const fs::path file = s.dir / ("noisy" + std::to_string(seed) + ".ply");
      write_mesh(file, moved);
      const std::string out = "noise" + std::to_string(seed) + tag;
      const auto r = s.cut(file, out, flags);
      INFO("seed " << seed << ": " << r.err);
      REQUIRE(r.exit_code == 0);
      const Json report = read_json_file(s.dir / out / "report.json");
      // The same pieces...
      REQUIRE(report["pieces"].size() == reference["pieces"].size());
      for (size_t i = 0; i < report["pieces"].size(); ++i) {
        CHECK(report["pieces"][i]["name"] == reference["pieces"][i]["name"]);
        CHECK(report["pieces"][i]["darts"] == reference["pieces"][i]["darts"]);
        CHECK(report["pieces"][i]["area_3d"].get<double>() ==
              Approx(reference["pieces"][i]["area_3d"].get<double>()).margin(1e-6));
      }
      // ... the same cuts, running within 0.1 mm of where they ran, their
      // lengths within 0.1 mm.
      REQUIRE(report["seams"].size() == reference["seams"].size());
      const auto seams = read_seams(s.dir / out / "seams.obj");
      for (size_t i = 0; i < report["seams"].size(); ++i) {
        const std::string name = reference["seams"][i]["name"];
        INFO("seed " << seed << ", seam " << name);
        CHECK(report["seams"][i]["name"] == name);
        CHECK(report["seams"][i]["kind"] == reference["seams"][i]["kind"]);
        CHECK(std::abs(report["seams"][i]["length_3d"].get<double>() -
                       reference["seams"][i]["length_3d"].get<double>()) < 1e-4);
        REQUIRE(seams.count(name) == 1);
        const Eigen::MatrixXd& a = seams.at(name);
        const Eigen::MatrixXd& b = seams0.at(name);
        CHECK(std::max(one_sided_hausdorff(a, b), one_sided_hausdorff(b, a)) < 1e-4);
      }
      // ... and the printed pieces, laid out, within the tolerance of where they were.
      const Mesh flat = read_mesh(s.dir / out / "pieces_flat.ply").mesh;
      REQUIRE(flat.V.rows() == flat0.V.rows());
      REQUIRE(flat.F == flat0.F);
      INFO("seed " << seed);
      CHECK((flat.V - flat0.V).rowwise().norm().maxCoeff() < flat_tolerance);
    }
  }
}

TEST_CASE("a nearly symmetric shirt's sleeves are mirrored pairs", "[cli][shirt]") {
  const Shirt& s = shirt();
  INFO(s.error);
  REQUIRE(s.ok);
  const auto r = s.cut(s.dir / "garment" / "garment.ply", "mirror");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const Json report = read_json_file(s.dir / "mirror" / "report.json");
  std::map<std::string, const Json*> pieces;
  for (const auto& p : report["pieces"]) pieces[p["name"].get<std::string>()] = &p;
  // Every sleeve part on one side has its mirror image, named alike, on the
  // other, of about the same size (the generated body is symmetric, the
  // garment's clicked loops and its remeshing nearly so). Its parts are
  // named front and back by how they lie, not by where each faces: with the
  // arms held out, both halves of one sleeve used to face sideways.
  int pairs = 0;
  for (const auto& [name, p] : pieces) {
    if (name.find("sleeve") == std::string::npos) continue;
    INFO(name);
    REQUIRE(pieces.count(mirror_name(name)) == 1);
    CHECK(mirror_name(name) != name);
    const Json& q = *pieces.at(mirror_name(name));
    const double a = (*p)["area_3d"].get<double>(), b = q["area_3d"].get<double>();
    CHECK(std::abs(a - b) <= 0.05 * std::max(a, b));
    const double la = (*p)["outline_length"].get<double>(), lb = q["outline_length"].get<double>();
    CHECK(std::abs(la - lb) <= 0.05 * std::max(la, lb));
    ++pairs;
  }
  CHECK(pairs == 4);  // two halves of each short sleeve
  // Both sleeves are cut at one armhole distance, so each side's sleeve has
  // the same cloth in all (2.3 % apart when each armhole was placed alone).
  double left = 0.0, right = 0.0;
  for (const auto& [name, p] : pieces) {
    if (name.rfind("left sleeve", 0) == 0) left += (*p)["area_3d"].get<double>();
    if (name.rfind("right sleeve", 0) == 0) right += (*p)["area_3d"].get<double>();
  }
  INFO("sleeve cloth left " << left << " m^2, right " << right << " m^2");
  CHECK(left == Approx(right).epsilon(0.01));
  CHECK(pieces.count("left sleeve front") == 1);
  CHECK(pieces.count("right sleeve back") == 1);
}

TEST_CASE("panel seams that relieve too little are taken out again", "[cli][shirt]") {
  const Shirt& s = shirt();
  INFO(s.error);
  REQUIRE(s.ok);
  // The generated shirt's front and back used to be split into a centre, a
  // side and an upper and lower back (11 pieces) whose worst distortion was
  // the same as without them: the seams moved the excess from one piece to
  // the other. Kept only when they relieve their length's worth (default),
  // against any relief at all (0).
  // The relief bound alone: no relief share (which keeps a seam that
  // relieves half of its piece's excess, whatever its length) and the plain
  // flattening.
  const std::string plain = "--min-relief-share 0 --limit-rounds 0";
  const auto a = s.cut(s.dir / "garment" / "garment.ply", "relief", plain);
  INFO(a.err);
  REQUIRE(a.exit_code == 0);
  const auto b = s.cut(s.dir / "garment" / "garment.ply", "relief0", plain + " --min-panel-relief 0");
  INFO(b.err);
  REQUIRE(b.exit_code == 0);
  const Json ra = read_json_file(s.dir / "relief" / "report.json");
  const Json rb = read_json_file(s.dir / "relief0" / "report.json");
  const Json& sa = ra["summary"];
  const Json& sb = rb["summary"];
  INFO(sa.dump() << "\n" << sb.dump());
  CHECK(ra["options"]["pattern"]["min_panel_relief_m2_per_m"].get<double>() == Approx(0.01));
  // Fewer pieces and less seam, no worse at its worst.
  CHECK(sa["pieces"].get<int>() <= 8);
  CHECK(sa["pieces"].get<int>() < sb["pieces"].get<int>());
  CHECK(sa["total_seam_length"].get<double>() < sb["total_seam_length"].get<double>() - 0.5);
  CHECK(sa["worst_compression"].get<double>() <= sb["worst_compression"].get<double>() + 0.005);
  CHECK(sa["worst_ease"].get<double>() <= sb["worst_ease"].get<double>() + 0.005);
  // Every panel seam taken out is listed and says what it relieved; every
  // one kept says so too.
  int removed = 0;
  for (const auto& m : ra["merged_cuts"])
    if (m.get<std::string>().rfind("panel", 0) == 0) ++removed;
  CHECK(removed >= 1);
  int notes = 0;
  for (const auto& n : ra["notes"])
    if (n.get<std::string>().find("removed: it relieved only") != std::string::npos) ++notes;
  CHECK(notes == removed);
  for (const auto& c : ra["added_cuts"])
    if (c["kind"] == "panel") CHECK(c["reason"].get<std::string>().find("it relieved") != std::string::npos);
  // A front and a back, each one piece or a mirrored pair.
  std::map<std::string, int> names;
  for (const auto& p : ra["pieces"]) ++names[p["name"].get<std::string>()];
  CHECK((names.count("front") + names.count("left front") + names.count("right front")) >= 1);
  CHECK((names.count("back") + names.count("left back") + names.count("right back")) >= 1);
}

TEST_CASE("a generated rest shape without seams is cut with no overlap, and a piece over the limit is located",
          "[cli][shirt][overlap]") {
  // The generated shirt as designed, cut with neither seams nor a garment
  // file (issue 49: "rest shapes cut without seams"). Every pattern written
  // has no overlapping piece and no flipped triangle. Measured on
  // 2026-12-01: 6 pieces, none overlapping, but the limit is not met (the
  // fronts and backs compressed by 3.4-4.2 % over their worst 1 % at the
  // shoulders; README, "Patterns within their own limit"): a piece over it
  // is named with its figures and the rest-shape point its worst 1 % lies
  // around.
  const Shirt& s = shirt();
  INFO(s.error);
  REQUIRE(s.ok);
  const auto r = testing::run_command(testing::tool_path("export-rest") + " " +
                                      (s.dir / "garment" / "garment.ply").string() + " --out " +
                                      (s.dir / "no-seams").string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const Json report = read_json_file(s.dir / "no-seams" / "report.json");
  const Json& sum = report["summary"];
  INFO(sum.dump());
  CHECK(sum["overlapping_pieces"] == 0);
  CHECK(sum["flipped_triangles"] == 0);
  CHECK(sum["pieces"].get<int>() <= 10);
  for (const auto& p : report["pieces"]) {
    INFO(p["name"]);
    CHECK(p["boundary_overlaps"] == false);
    REQUIRE(p["worst_at"]["compression_worst1_m"].size() == 3);
    if (p["meets_limit"] == false) {
      CHECK(r.err.find(p["name"].get<std::string>() + " (compression") != std::string::npos);
      // The point lies on the garment: within its bounding box.
      const double y = p["worst_at"]["compression_worst1_m"][1].get<double>();
      CHECK(y > 0.5);
      CHECK(y < 2.0);
    }
  }
  if (sum["meets_distortion_limit"] == false) CHECK(r.err.find("its worst") != std::string::npos);
}

TEST_CASE("a sleeve cut without seams is opened under the arm", "[cli][shirt]") {
  // The generated shirt at twice the test's resolution, cut with neither
  // seams nor a garment file: each sleeve, a tube between its cuff and its
  // armhole, needs a cut to flatten. A tailor's runs under the arm; joined
  // anywhere along the loop, this shirt's right sleeve was opened over the
  // shoulder (its join 1.6 cm above its armhole's centre, the armpit's saddle
  // in the middle of the piece, eased by 14.3 % over its worst 5 %) and the
  // left one under the arm (6 cm below, 9.4 %); now both under the arm (the
  // right one 10.8 %).
  const Shirt& s = shirt();
  INFO(s.error);
  REQUIRE(s.ok);
  const fs::path customer = testing::source_dir() / "testdata" / "customers" / "small-shirt";
  Json spec = read_json_file(customer / "garment-spec.json");
  spec["resolution"]["vertex_count"] = 2200;
  std::ofstream(s.dir / "spec-2200.json") << spec.dump(2);
  auto r = testing::run_command(testing::tool_path("make-garment") + " " + (s.dir / "spec-2200.json").string() +
                                " --poses " + (s.dir / "body" / "poses.json").string() + " -q --out " +
                                (s.dir / "garment-2200").string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  r = testing::run_command(testing::tool_path("export-rest") + " " + (s.dir / "garment-2200" / "garment.ply").string() +
                           " -q --out " + (s.dir / "sleeves-2200").string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const Json report = read_json_file(s.dir / "sleeves-2200" / "report.json");
  CHECK(report["summary"]["overlapping_pieces"] == 0);
  const auto seams = read_seams(s.dir / "sleeves-2200" / "seams.obj");
  std::vector<Eigen::Vector3d> armholes;
  for (const auto& c : report["added_cuts"])
    if (c["kind"] == "armhole") armholes.push_back(seams.at(c["name"].get<std::string>()).colwise().mean().transpose());
  REQUIRE(armholes.size() == 2);
  int sleeve_joins = 0;
  for (const auto& c : report["added_cuts"]) {
    const std::string reason = c["reason"];
    if (c["kind"] != "topology" || reason.find("sleeve") == std::string::npos) continue;
    ++sleeve_joins;
    INFO(reason);
    const Eigen::Vector3d join = seams.at(c["name"].get<std::string>()).colwise().mean().transpose();
    const Eigen::Vector3d& armhole =
        (join - armholes[0]).norm() < (join - armholes[1]).norm() ? armholes[0] : armholes[1];
    // Under the arm: well below the armhole's centre (the arm's radius is
    // about 5 cm here), on the side of the body it faces.
    CHECK(join.y() < armhole.y() - 0.03);
    CHECK(std::abs(join.x()) < std::abs(armhole.x()));
    CHECK(reason.find("under the arm") != std::string::npos);
  }
  CHECK(sleeve_joins == 2);
  for (const auto& p : report["pieces"]) {
    if (p["name"].get<std::string>().find("sleeve") == std::string::npos) continue;
    INFO(p["name"]);
    CHECK(p["distortion"]["ease_worst5"].get<double>() < 0.12);
  }
}
