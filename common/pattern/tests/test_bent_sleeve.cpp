// A rest shape made without seams or a garment file is cut within the
// distortion limit, with no overlapping piece (issue 49). The test builds a
// sleeve bent at the elbow: a tube of 5 cm radius, two straight parts of
// 20 cm joined by a bend of 15 cm radius. Bent by 35 degrees it is a tube
// that no flattening opens within the limit on one cut alone (a saddle on
// the inside of the bend, a dome on the outside); a tailor takes the elbow
// in with a dart, and so must the cutter.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "pattern/export_report.h"
#include "pattern/make_pattern.h"
#include "testing/test_meshes.h"

using namespace gp;

namespace {

// The tube's axis runs down the y axis for `straight` metres, bends by
// `angle` (radians) about the z axis with radius `bend`, and runs straight
// again; rings of edge length about h, both ends open.
Mesh bent_sleeve(double radius, double bend, double angle, double straight, double h) {
  const int nu = std::max(8, static_cast<int>(std::lround(2.0 * M_PI * radius / h)));
  const int ns = std::max(2, static_cast<int>(std::lround(straight / h)));
  const int na = std::max(1, static_cast<int>(std::lround(bend * angle / h)));
  std::vector<double> arcs;
  for (int i = 0; i < ns; ++i) arcs.push_back(straight * i / ns);
  for (int i = 0; i < na; ++i) arcs.push_back(straight + bend * angle * i / na);
  for (int i = 0; i <= ns; ++i) arcs.push_back(straight + bend * angle + straight * i / ns);
  Mesh m;
  m.V.resize(static_cast<int>(arcs.size()) * nu, 3);
  for (size_t i = 0; i < arcs.size(); ++i) {
    const double s = arcs[i];
    Eigen::Vector3d centre, normal;
    if (s <= straight) {
      centre = Eigen::Vector3d(0.0, straight - s, 0.0);
      normal = Eigen::Vector3d(1.0, 0.0, 0.0);
    } else {
      const double a = std::min(angle, (s - straight) / bend), rest = std::max(0.0, s - straight - bend * angle);
      const Eigen::Vector3d tangent(std::sin(a), -std::cos(a), 0.0);
      normal = Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
      centre = Eigen::Vector3d(bend - bend * std::cos(a), -bend * std::sin(a), 0.0) + rest * tangent;
    }
    const Eigen::Vector3d binormal(0.0, 0.0, 1.0);
    for (int k = 0; k < nu; ++k) {
      const double t = 2.0 * M_PI * k / nu;
      m.V.row(static_cast<int>(i) * nu + k) = (centre + radius * (std::cos(t) * normal + std::sin(t) * binormal)).transpose();
    }
  }
  m.F.resize(2 * static_cast<int>(arcs.size() - 1) * nu, 3);
  int f = 0;
  for (int i = 0; i + 1 < static_cast<int>(arcs.size()); ++i)
    for (int k = 0; k < nu; ++k) {
      const int a = i * nu + k, b = i * nu + (k + 1) % nu, c = (i + 1) * nu + k, d = (i + 1) * nu + (k + 1) % nu;
      m.F.row(f++) = Eigen::RowVector3i(a, c, b);
      m.F.row(f++) = Eigen::RowVector3i(b, c, d);
    }
  return m;
}

}  // namespace

TEST_CASE("a bent sleeve made without seams is cut within the limit, with no overlap", "[cutter][issue49]") {
  const Mesh sleeve = bent_sleeve(0.05, 0.15, 35.0 * M_PI / 180.0, 0.2, 0.015);
  const PatternOptions options;

  // One topology cut and no dart: over the limit, so the test can fail.
  PatternOptions plain = options;
  plain.darts.max_darts = 0;
  plain.panels.max_pieces = 1;
  const Pattern opened = make_pattern(sleeve.V, sleeve.F, {}, plain);
  REQUIRE(opened.pieces.size() == 1);
  CHECK(!opened.meets_limit);
  CHECK(opened.pieces[0].stats.worst1_compression > options.limit.compression_worst1);

  const Pattern pattern = make_pattern(sleeve.V, sleeve.F, {}, options);
  INFO("pieces " << pattern.pieces.size() << ", compression " << pattern.pieces[0].stats.worst1_compression
                 << ", ease " << pattern.pieces[0].stats.worst5_ease);
  CHECK(pattern.meets_limit);
  CHECK(pattern.pieces.size() <= 2);  // a tailor's sleeve: one piece or two
  int darts = 0;
  for (const auto& s : pattern.seams) darts += s.kind == "dart";
  CHECK(darts >= 1);  // the elbow is taken in, not cut apart
  double area_3d = 0.0, area_2d = 0.0;
  for (const auto& p : pattern.pieces) {
    CHECK(p.meets_limit);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(p.flat.stats.flipped_triangles == 0);
    CHECK(p.stats.worst1_compression <= options.limit.compression_worst1);
    CHECK(p.stats.worst5_ease <= options.limit.ease_worst5);
    area_3d += p.stats.area_3d;
    area_2d += p.stats.area_2d;
  }
  // Within the limit the flat cloth is the tube's within a few per cent
  // (ease, never much less: compression is bounded tightly).
  CHECK(area_2d / area_3d == Approx(1.0).margin(0.05));
  CHECK(area_2d / area_3d > 0.99);
}

TEST_CASE("the worst region of a piece is reported at its densest spot, not between its parts", "[report][issue49]") {
  // A strip of faces 1 cm apart along x, compressed by 1 % everywhere but
  // at two spots 40 cm apart (5 % at x = 0.10 m, three faces; 4 % at
  // x = 0.50 m, two faces): the worst 5 % of the area is both spots.
  std::vector<MaterialFace> faces;
  for (int i = 0; i < 100; ++i) {
    MaterialFace m;
    m.area = 1e-4;
    m.centroid = Eigen::Vector3d(0.01 * i, 1.2, 0.1);
    const double c = (i >= 9 && i <= 11) ? 0.05 : (i == 50 || i == 51) ? 0.04 : 0.01;
    m.stretch = Eigen::Vector2d(1.0, 1.0 - c);
    faces.push_back(m);
  }
  const Eigen::Vector3d at = worst_region_centroid(faces, 0.05, true, 0.06);
  // The whole region's centroid would be at x = 0.26 m, on neither spot.
  CHECK(at.x() == Approx(0.10).margin(1e-9));
  CHECK(at.y() == Approx(1.2));
  // Within a radius that holds both, their centroid again.
  const Eigen::Vector3d wide = worst_region_centroid(faces, 0.05, true, 1.0);
  CHECK(wide.x() == Approx((3 * 0.10 + 0.50 + 0.51) / 5.0).margin(1e-9));
}
