// Both sides of the body cut alike (piece_mirror.h, make_pattern.h).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pattern/make_pattern.h"
#include "pattern/piece_mirror.h"
#include "pattern/piece_names.h"
#include "pattern/seam_spec.h"
#include "testing/test_meshes.h"
#include <Eigen/Geometry>

using namespace gp;

namespace {

// A sheet facing the front (+z) with two bumps at x = -+a, the body's
// right one `right_height` and its left one `left_height` high: a scanned
// body's two shoulder blades, never quite alike.
Mesh two_bumps(double right_height, double left_height) {
  const int nx = 40, ny = 32;
  const double sx = 0.5, sy = 0.4, a = 0.11, s = 0.035;
  Mesh m = testing::make_grid(nx, ny, sx, sy);  // x in [0, sx], z in [0, sy], y = 0
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double x = m.V(v, 0) - 0.5 * sx, y = m.V(v, 2) - 0.5 * sy;
    const auto bump = [&](double cx, double h) { return h * std::exp(-((x - cx) * (x - cx) + y * y) / (2 * s * s)); };
    m.V.row(v) = Eigen::RowVector3d(x, y, bump(-a, right_height) + bump(a, left_height));
  }
  // make_grid's normals point to +y; the sheet faces +z after the swap of
  // y and z, so its faces are turned back.
  m.F.col(1).swap(m.F.col(2));
  return m;
}

// The darts' tips (their last vertices), in 3D.
std::vector<Eigen::Vector3d> dart_tip_points(const Pattern& pattern) {
  std::vector<Eigen::Vector3d> tips;
  for (const PatternSeam& s : pattern.seams)
    if (s.kind == "dart") tips.push_back(pattern.mesh.V.row(s.vertex_ids.back()).transpose());
  return tips;
}


// A user seam from the bottom edge to the top along the grid column at x.
std::vector<SeamPath> vertical_seam(double x) {
  const int nx = 40, ny = 32;
  const int i = static_cast<int>(std::lround((x + 0.25) / 0.5 * nx));
  SeamPath seam;
  seam.name = "seam";
  for (int j = 0; j <= ny; ++j) seam.vertex_ids.push_back(j * (nx + 1) + i);
  seam.click_ids = {seam.vertex_ids.front(), seam.vertex_ids.back()};
  seam.where = "test";
  return {seam};
}

int count_kind(const Pattern& pattern, const std::string& kind) {
  int n = 0;
  for (const PatternSeam& s : pattern.seams) n += s.kind == kind;
  return n;
}

// Every added cut of `kind` names a mirror image, which names it back.
void check_mirrored(const Pattern& pattern, const std::string& kind) {
  for (const PatternSeam& s : pattern.seams) {
    if (s.kind != kind) continue;
    INFO(s.name << ": " << s.reason);
    REQUIRE(!s.mirror.empty());
    const auto image = std::find_if(pattern.seams.begin(), pattern.seams.end(),
                                    [&](const PatternSeam& t) { return t.name == s.mirror; });
    REQUIRE(image != pattern.seams.end());
    CHECK(image->mirror == s.name);
    CHECK(image->kind == kind);
  }
}

// Two dart tips are mirror images across x = plane_x within `tolerance`.
void check_mirror_tips(const std::vector<Eigen::Vector3d>& tips, double plane_x, double tolerance) {
  REQUIRE(tips.size() == 2);
  INFO("tips " << tips[0].transpose() << " and " << tips[1].transpose() << ", plane x = " << plane_x);
  CHECK(std::abs(tips[0].x() + tips[1].x() - 2.0 * plane_x) < tolerance);
  CHECK(std::abs(tips[0].y() - tips[1].y()) < tolerance);
  CHECK(std::abs(tips[0].x() - tips[1].x()) > 0.15);
}

void check_sound(const Pattern& pattern) {
  for (const PatternPiece& p : pattern.pieces) {
    INFO(p.name);
    CHECK(p.flat.stats.flipped_triangles == 0);
    CHECK(!p.flat.boundary_overlaps);
    CHECK(p.stats.worst5_ease < 0.2);
  }
}

}  // namespace

TEST_CASE("pieces pair with their mirror images, mutually", "[pattern][mirror]") {
  const Mesh m = two_bumps(0.02, 0.04);
  PatternOptions o;
  o.darts.max_darts = 0;
  o.panels.max_pieces = 1;  // the user's seam only
  // Down the middle: two halves, each the other's image.
  const Pattern halves = make_pattern(m.V, m.F, vertical_seam(0.0), o);
  REQUIRE(halves.pieces.size() == 2);
  const PieceMirror a = mirror_pieces(halves, o.panels.mirror_overlap);
  CHECK(a.partner == std::vector<int>{1, 0});
  // The plane through the area centroid, nudged to the higher bump's side.
  CHECK(a.plane_x > 0.0);
  CHECK(a.plane_x < 0.005);
  // At x = 0.15: the wide piece is its own image; the strip's image lies in
  // the wide piece, which is not the strip's, so the strip has none.
  const Pattern strip = make_pattern(m.V, m.F, vertical_seam(0.15), o);
  REQUIRE(strip.pieces.size() == 2);
  const PieceMirror b = mirror_pieces(strip, o.panels.mirror_overlap);
  const int wide = strip.pieces[0].stats.area_3d > strip.pieces[1].stats.area_3d ? 0 : 1;
  CHECK(b.partner[static_cast<size_t>(wide)] == wide);
  CHECK(b.partner[static_cast<size_t>(1 - wide)] == -1);
}

TEST_CASE("two mirrored pieces are cut alike: darts", "[pattern][mirror]") {
  // The body's left bump (49 degrees of curvature within the kernel) takes a
  // dart; its right half, half as high (15 degrees), meets the limit
  // without one but has the curvature a dart needs.
  const Mesh m = two_bumps(0.02, 0.04);
  PatternOptions o;
  o.darts.min_dart_angle = 0.2;
  o.panels.mirror = false;
  const Pattern alone = make_pattern(m.V, m.F, vertical_seam(0.0), o);
  CHECK(count_kind(alone, "dart") == 1);
  o.panels.mirror = true;
  const Pattern both = make_pattern(m.V, m.F, vertical_seam(0.0), o);
  REQUIRE(both.pieces.size() == 2);
  CHECK(count_kind(both, "dart") == 2);
  for (const PatternPiece& p : both.pieces) CHECK(p.dart_seams.size() == 1);
  check_mirrored(both, "dart");
  check_mirror_tips(dart_tip_points(both), mirror_pieces(both, o.panels.mirror_overlap).plane_x, 0.005);
  check_sound(both);
  for (const PatternPiece& p : both.pieces) CHECK(p.meets_limit);

  // A bump a quarter as high (4 degrees) has too little curvature for a
  // dart, whose sides would cross: that side stays uncut, with a note.
  const Mesh flat_right = two_bumps(0.01, 0.04);
  const Pattern one = make_pattern(flat_right.V, flat_right.F, vertical_seam(0.0), o);
  CHECK(count_kind(one, "dart") == 1);
  bool noted = false;
  for (const std::string& n : one.notes) noted = noted || n.find("where its mirror image has one") != std::string::npos;
  CHECK(noted);
  check_sound(one);
}

TEST_CASE("two mirrored pieces are cut alike: panel seams, kept together", "[pattern][mirror]") {
  const Mesh m = two_bumps(0.01, 0.04);
  PatternOptions o;
  o.darts.max_darts = 0;
  o.panels.mirror = false;
  const Pattern alone = make_pattern(m.V, m.F, vertical_seam(0.0), o);
  CHECK(count_kind(alone, "panel") == 1);
  CHECK(alone.pieces.size() == 3);
  o.panels.mirror = true;
  const Pattern both = make_pattern(m.V, m.F, vertical_seam(0.0), o);
  CHECK(count_kind(both, "panel") == 2);
  CHECK(both.pieces.size() == 4);
  check_mirrored(both, "panel");
  check_sound(both);
  // Judged together: both carry the pair's relief.
  for (const PatternSeam& s : both.seams)
    if (s.kind == "panel") CHECK(s.reason.find("two mirrored pieces'") != std::string::npos);
}

TEST_CASE("of two darts whose piece overlaps, the one whose sides crossed goes", "[pattern][darts]") {
  // With a low curvature bar both bumps get a dart; the low bump's (9
  // degrees) has too little to take in, its sides cross and the piece's
  // outline overlaps. Taking out that dart, not the first one placed (the
  // high bump's, 49 degrees), leaves the piece within reach of the limit.
  const Mesh m = two_bumps(0.016, 0.04);
  PatternOptions o;
  o.darts.min_dart_angle = 0.1;
  o.panels.mirror = false;
  const Pattern pattern = make_pattern(m.V, m.F, {}, o);
  REQUIRE(pattern.pieces.size() == 1);
  const std::vector<Eigen::Vector3d> tips = dart_tip_points(pattern);
  REQUIRE(tips.size() == 1);
  CHECK(tips[0].x() > 0.09);  // the high bump's, on the body's left
  CHECK(!pattern.pieces[0].flat.boundary_overlaps);
  bool removed = false;
  for (const std::string& n : pattern.notes) removed = removed || n.find("its sides crossed") != std::string::npos;
  CHECK(removed);
  CHECK(pattern.pieces[0].stats.worst1_compression < 0.03);
}

namespace {

// A pattern of single-triangle pieces (3D rest = piece, each its own face),
// with a left limb "cuff_left": limb_of[i] is piece i's limb, -1 for none.
Pattern pattern_of_triangles(const std::vector<Eigen::Matrix3d>& triangles, const std::vector<int>& limb_of) {
  Pattern pattern;
  pattern.limbs = {{"cuff_left", true}};
  pattern.mesh.rest_V.resize(3 * static_cast<Eigen::Index>(triangles.size()), 3);
  pattern.mesh.rest_F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (size_t i = 0; i < triangles.size(); ++i) {
    PatternPiece piece;
    piece.V = triangles[i];
    piece.F = Eigen::RowVector3i(0, 1, 2);
    piece.face_ids = {static_cast<int>(i)};
    pattern.pieces.push_back(piece);
    pattern.mesh.rest_V.middleRows(3 * static_cast<Eigen::Index>(i), 3) = triangles[i];
    pattern.mesh.rest_F.row(static_cast<Eigen::Index>(i)) = Eigen::RowVector3i(0, 1, 2).array() + 3 * static_cast<int>(i);
    pattern.mesh.rest_face.push_back(static_cast<int>(i));
    pattern.limb_of_rest_face.push_back(limb_of[i]);
  }
  return pattern;
}

// A small triangle facing +z (front) or -z (back) at (x, y, z).
Eigen::Matrix3d facing_triangle(double x, double y, double z, bool front) {
  Eigen::Matrix3d t;
  const double w = front ? 0.05 : -0.05;
  t << x, y, z, x + w, y, z, x, y + 0.05, z;
  return t;
}

}  // namespace

TEST_CASE("a sleeve in four parts is named upper and lower, front and back", "[pattern][names]") {
  // A torso triangle about the origin and a left sleeve (+x) of four small
  // triangles: two near the body (x = 0.3) and two near the cuff (x = 0.6),
  // in front (z > 0) and behind.
  std::vector<Eigen::Matrix3d> triangles;
  Eigen::Matrix3d torso;
  torso << -0.2, 1.0, 0.1, 0.2, 1.0, 0.1, 0.0, 1.4, 0.1;
  triangles.push_back(torso);
  for (double x : {0.3, 0.6})
    for (double z : {0.04, -0.04}) {
      Eigen::Matrix3d t;
      t << x, 1.3, z, x + 0.05, 1.3, z, x, 1.35, z;
      triangles.push_back(t);
    }
  Pattern pattern = pattern_of_triangles(triangles, {-1, 0, 0, 0, 0});
  name_pieces(pattern);
  CHECK(pattern.pieces[1].name == "upper left sleeve front");
  CHECK(pattern.pieces[2].name == "upper left sleeve back");
  CHECK(pattern.pieces[3].name == "lower left sleeve front");
  CHECK(pattern.pieces[4].name == "lower left sleeve back");
  CHECK(mirror_name(pattern.pieces[3].name) == "lower right sleeve front");
}

TEST_CASE("a back in four panels is named centre and side back, alike on both sides", "[pattern][names]") {
  // A front across the axis (x = -0.2 .. 0.2) and a back cut by a centre
  // seam and a panel seam on each side: panels at |x| = 0.03 beside the
  // spine and |x| = 0.13 beyond. The centroids of the inner panels lie
  // within 4 cm of the axis, and still they are a left and a right piece.
  std::vector<Eigen::Matrix3d> triangles;
  Eigen::Matrix3d front;
  front << -0.2, 1.0, 0.1, 0.2, 1.0, 0.1, 0.0, 1.4, 0.1;
  triangles.push_back(front);
  for (double x : {-0.13, -0.045, 0.015, 0.1}) triangles.push_back(facing_triangle(x, 1.2, -0.1, false));
  Pattern pattern = pattern_of_triangles(triangles, {-1, -1, -1, -1, -1});
  name_pieces(pattern);
  CHECK(pattern.pieces[0].name == "front");
  CHECK(pattern.pieces[1].name == "right side back");
  CHECK(pattern.pieces[2].name == "right centre back");
  CHECK(pattern.pieces[3].name == "left centre back");
  CHECK(pattern.pieces[4].name == "left side back");
  CHECK(mirror_name(pattern.pieces[2].name) == pattern.pieces[3].name);
}

TEST_CASE("a sleeve in three parts is named by the part that runs its length", "[pattern][names]") {
  // A left sleeve whose back runs its whole length (x = 0.45) and whose
  // front is cut in two along the arm (x = 0.3 and 0.6).
  std::vector<Eigen::Matrix3d> triangles;
  Eigen::Matrix3d torso;
  torso << -0.2, 1.0, 0.1, 0.2, 1.0, 0.1, 0.0, 1.4, 0.1;
  triangles.push_back(torso);
  triangles.push_back(facing_triangle(0.6, 1.3, 0.04, true));
  triangles.push_back(facing_triangle(0.45, 1.3, -0.04, false));
  triangles.push_back(facing_triangle(0.3, 1.3, 0.04, true));
  Pattern pattern = pattern_of_triangles(triangles, {-1, 0, 0, 0});
  name_pieces(pattern);
  CHECK(pattern.pieces[1].name == "lower left sleeve front");
  CHECK(pattern.pieces[2].name == "left sleeve back");
  CHECK(pattern.pieces[3].name == "upper left sleeve front");
}

TEST_CASE("mirrored pieces are named from their average, as mirror images", "[pattern][names]") {
  // Two back panels, mirror images but for the scan's asymmetry: the left one
  // turns a little more sideways than it faces back, the right one not.
  auto triangle_facing = [](const Eigen::Vector3d& at, const Eigen::Vector3d& normal) {
    const Eigen::Vector3d n = normal.normalized();
    const Eigen::Vector3d u = 0.05 * n.cross(Eigen::Vector3d::UnitY()).normalized();
    const Eigen::Vector3d v = n.cross(u);  // u x v points along n
    Eigen::Matrix3d t;
    t.row(0) = at.transpose();
    t.row(1) = (at + u).transpose();
    t.row(2) = (at + v).transpose();
    return t;
  };
  std::vector<Eigen::Matrix3d> triangles;
  Eigen::Matrix3d front;
  front << -0.2, 1.0, 0.1, 0.2, 1.0, 0.1, 0.0, 1.4, 0.1;
  triangles.push_back(front);
  triangles.push_back(triangle_facing({0.15, 1.2, -0.05}, {0.6, 0.0, -0.5}));
  triangles.push_back(triangle_facing({-0.15, 1.2, -0.05}, {-0.4, 0.0, -0.6}));
  Pattern alone = pattern_of_triangles(triangles, {-1, -1, -1});
  name_pieces(alone);
  CHECK(alone.pieces[1].name == "side");  // each the only one facing its way
  CHECK(alone.pieces[2].name == "back");
  Pattern paired = pattern_of_triangles(triangles, {-1, -1, -1});
  PieceMirror mirror;
  mirror.plane_x = area_centroid(paired.mesh.rest_V, paired.mesh.rest_F).x();
  mirror.partner = {-1, 2, 1};
  name_pieces(paired, mirror);
  CHECK(paired.pieces[0].name == "front");
  CHECK(paired.pieces[1].name == "left back");
  CHECK(paired.pieces[2].name == "right back");
}
