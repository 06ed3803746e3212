// The contact surface: a hand-like thin part (a U of two fingers on a palm,
// 1 cm thick) gets one outward hull that closes the gap between the fingers;
// thick bodies, small thin parts and hulls switched off get none; the copies
// follow the body in another pose; bad input is refused.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include <Eigen/Geometry>

#include "collision/contact_surface.h"
#include "core/error.h"
#include "testing/test_meshes.h"

using gp::collision::contact_surface;
using gp::collision::ContactSurface;
using gp::collision::ContactSurfaceOptions;
using Eigen::Vector3d;

namespace {

// A closed, outward prism over the filled cells of a 2D mask (cells of side
// `cell` [m] in the xy-plane), `thickness` [m] deep along z.
gp::Mesh extruded_mask(const std::vector<std::vector<int>>& mask, double cell, double thickness) {
  const int ny = static_cast<int>(mask.size()), nx = static_cast<int>(mask[0].size());
  auto filled = [&](int i, int j) { return i >= 0 && j >= 0 && i < nx && j < ny && mask[j][i] != 0; };
  std::map<std::array<int, 3>, int> id;
  std::vector<Vector3d> points;
  auto vertex = [&](int i, int j, int k) {
    auto [it, added] = id.emplace(std::array<int, 3>{i, j, k}, static_cast<int>(points.size()));
    if (added) points.emplace_back(i * cell, j * cell, k * thickness);
    return it->second;
  };
  std::vector<std::array<int, 3>> faces;
  auto quad = [&](int a, int b, int c, int d) {  // counter-clockwise seen from outside
    faces.push_back({a, b, c});
    faces.push_back({a, c, d});
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (!filled(i, j)) continue;
      quad(vertex(i, j, 1), vertex(i + 1, j, 1), vertex(i + 1, j + 1, 1), vertex(i, j + 1, 1));  // top, +z
      quad(vertex(i, j, 0), vertex(i, j + 1, 0), vertex(i + 1, j + 1, 0), vertex(i + 1, j, 0));  // bottom, -z
      if (!filled(i, j - 1)) quad(vertex(i, j, 0), vertex(i + 1, j, 0), vertex(i + 1, j, 1), vertex(i, j, 1));
      if (!filled(i, j + 1)) quad(vertex(i + 1, j + 1, 0), vertex(i, j + 1, 0), vertex(i, j + 1, 1), vertex(i + 1, j + 1, 1));
      if (!filled(i - 1, j)) quad(vertex(i, j + 1, 0), vertex(i, j, 0), vertex(i, j, 1), vertex(i, j + 1, 1));
      if (!filled(i + 1, j)) quad(vertex(i + 1, j, 0), vertex(i + 1, j + 1, 0), vertex(i + 1, j + 1, 1), vertex(i + 1, j, 1));
    }
  }
  gp::Mesh m;
  m.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t v = 0; v < points.size(); ++v) m.V.row(static_cast<Eigen::Index>(v)) = points[v].transpose();
  m.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) m.F(static_cast<Eigen::Index>(f), k) = faces[f][static_cast<size_t>(k)];
  }
  return m;
}

// Two fingers 2 cm wide and 10 cm long, 2 cm apart, on a 6 by 2 cm palm.
gp::Mesh two_finger_hand() {
  std::vector<std::vector<int>> mask(12, std::vector<int>(6, 0));
  for (int j = 0; j < 12; ++j) {
    for (int i = 0; i < 6; ++i) mask[j][i] = j < 2 || i < 2 || i >= 4;
  }
  return extruded_mask(mask, 0.01, 0.01);
}

double signed_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int first_face) {
  double volume = 0.0;
  for (int f = first_face; f < F.rows(); ++f) {
    const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

// Inside the convex hull faces [first_face, #F) of (V, F), outward.
bool inside_hull(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int first_face, const Vector3d& p) {
  for (int f = first_face; f < F.rows(); ++f) {
    const Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    if ((b - a).cross(c - a).dot(p - a) > 0.0) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("contact surface: a hand-like thin part gets one outward hull over its finger gap",
          "[collision][contact_surface]") {
  const gp::Mesh hand = two_finger_hand();
  REQUIRE(signed_volume(hand.V, hand.F, 0) == Approx(2 * (0.02 * 0.10) * 0.01 + 0.06 * 0.02 * 0.01).epsilon(1e-9));
  const ContactSurface s = contact_surface(hand.V, hand.F);
  CHECK(s.hull_count == 1);
  CHECK(s.body_vertex_count == hand.V.rows());
  CHECK(s.body_face_count == hand.F.rows());
  REQUIRE(s.F.rows() > hand.F.rows());
  CHECK(s.F.topRows(hand.F.rows()) == hand.F);
  // The hull is its own closed surface, over copies of body vertices.
  const Eigen::MatrixXd X = s.positions(hand.V);
  REQUIRE(X.rows() == hand.V.rows() + static_cast<Eigen::Index>(s.sources.size()));
  for (Eigen::Index f = hand.F.rows(); f < s.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) CHECK(s.F(f, k) >= hand.V.rows());
  }
  // Outward, and the volume of the box that bounds the U (convex).
  CHECK(signed_volume(X, s.F, s.body_face_count) == Approx(0.06 * 0.12 * 0.01).epsilon(1e-9));
  // The gap between the fingers is inside the hull, not inside the body.
  CHECK(inside_hull(X, s.F, s.body_face_count, Vector3d(0.03, 0.08, 0.005)));
  CHECK_FALSE(inside_hull(X, s.F, s.body_face_count, Vector3d(0.03, 0.08, 0.02)));
}

TEST_CASE("contact surface: thick bodies, small thin parts and hulls switched off keep the body only",
          "[collision][contact_surface]") {
  SECTION("a sphere 10 cm across is not thin") {
    const gp::Mesh ball = gp::testing::make_icosphere(3, 0.05);
    const ContactSurface s = contact_surface(ball.V, ball.F);
    CHECK(s.hull_count == 0);
    CHECK(s.F == ball.F);
    CHECK(s.sources.empty());
  }
  SECTION("a hand at half the size is shorter than the minimum extent") {
    gp::Mesh small = two_finger_hand();
    small.V *= 0.5;
    ContactSurfaceOptions options;
    options.thin = 0.015;
    CHECK(contact_surface(small.V, small.F, options).hull_count == 0);
    options.min_extent = 0.05;
    CHECK(contact_surface(small.V, small.F, options).hull_count == 1);
  }
  SECTION("a palm thicker than `thin` is not thin") {
    const gp::Mesh hand = two_finger_hand();
    ContactSurfaceOptions options;
    options.thin = 0.009;
    CHECK(contact_surface(hand.V, hand.F, options).hull_count == 0);
  }
  SECTION("switched off") {
    const gp::Mesh hand = two_finger_hand();
    ContactSurfaceOptions options;
    options.hulls = false;
    const ContactSurface s = contact_surface(hand.V, hand.F, options);
    CHECK(s.hull_count == 0);
    CHECK(s.F == hand.F);
  }
}

TEST_CASE("contact surface: the hull follows the body into another pose, at any scale",
          "[collision][contact_surface]") {
  for (const double scale : {1e-3, 1.0, 1e3}) {
    gp::Mesh hand = two_finger_hand();
    hand.V *= scale;
    ContactSurfaceOptions options;
    options.thin *= scale;
    options.min_extent *= scale;
    const ContactSurface s = contact_surface(hand.V, hand.F, options);
    REQUIRE(s.hull_count == 1);
    // Another pose: the hand turned and moved; the copies go with it.
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    Eigen::MatrixXd moved = (hand.V * R.transpose()).rowwise() + Eigen::RowVector3d(0.1, -0.2, 0.3) * scale;
    const Eigen::MatrixXd X = s.positions(moved);
    for (size_t k = 0; k < s.sources.size(); ++k) {
      CHECK((X.row(s.body_vertex_count + static_cast<Eigen::Index>(k)) - moved.row(s.sources[k])).norm() == 0.0);
    }
    CHECK(signed_volume(X, s.F, s.body_face_count) ==
          Approx(0.06 * 0.12 * 0.01 * scale * scale * scale).epsilon(1e-9));
  }
}

TEST_CASE("contact surface: the hull's faces follow from the body alone, not from the heap",
          "[collision][contact_surface]") {
  // A rounded thin part (a disc of a hand's thickness with a noisy rim), so that the hull has many
  // faces in general position. Whatever the heap holds between two builds (CGAL's corner order
  // within a face follows its storage), the surface is the same, and each hull face starts at its
  // smallest vertex: the contact queries that walk it, and so the cloth, do not depend on the run.
  gp::Mesh disc = gp::testing::make_icosphere(3, 0.08);
  disc.V.col(2) *= 0.01 / 0.16;
  for (Eigen::Index v = 0; v < disc.V.rows(); ++v) disc.V(v, 0) *= 1.0 + 0.05 * std::sin(7.0 * static_cast<double>(v));
  const ContactSurface first = contact_surface(disc.V, disc.F);
  REQUIRE(first.hull_count == 1);
  REQUIRE(first.hull_faces[0] > 20);
  for (Eigen::Index f = first.body_face_count; f < first.F.rows(); ++f) {
    const int smallest = std::min({first.sources[first.F(f, 0) - first.body_vertex_count],
                                   first.sources[first.F(f, 1) - first.body_vertex_count],
                                   first.sources[first.F(f, 2) - first.body_vertex_count]});
    CHECK(first.sources[first.F(f, 0) - first.body_vertex_count] == smallest);
  }
  // Coplanar hull points are fanned, not left as slivers: every face has an area.
  const Eigen::MatrixXd X = first.positions(disc.V);
  for (Eigen::Index f = first.body_face_count; f < first.F.rows(); ++f) {
    const Vector3d a = X.row(first.F(f, 0)), b = X.row(first.F(f, 1)), c = X.row(first.F(f, 2));
    CHECK((b - a).cross(c - a).norm() > 1e-12);
  }
  CHECK(signed_volume(X, first.F, first.body_face_count) > 0.0);
  std::vector<std::vector<double>> clutter;
  for (int round = 0; round < 6; ++round) {
    clutter.emplace_back(static_cast<size_t>(17 + 301 * round), 1.0);  // a different heap each build
    const ContactSurface again = contact_surface(disc.V, disc.F);
    CHECK(again.F == first.F);
    CHECK(again.sources == first.sources);
  }
}

TEST_CASE("contact surface: bad input is refused", "[collision][contact_surface]") {
  gp::Mesh hand = two_finger_hand();
  const ContactSurface s = contact_surface(hand.V, hand.F);
  CHECK_THROWS_AS(s.positions(hand.V.topRows(10)), gp::UsageError);
  ContactSurfaceOptions bad;
  bad.thin = 0.0;
  CHECK_THROWS_AS(contact_surface(hand.V, hand.F, bad), gp::UsageError);
  hand.V(7, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(contact_surface(hand.V, hand.F), gp::GeometryError);
  Eigen::MatrixXi out_of_range = hand.F;
  out_of_range(0, 0) = static_cast<int>(hand.V.rows());
  CHECK_THROWS_AS(contact_surface(two_finger_hand().V, out_of_range), gp::UsageError);
}
