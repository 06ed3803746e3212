// A bias-cut skirt, from the spec to the pattern: the extension spec turns
// the skirt's grain by 45 degrees (extend-spec "grain"), every skirt face of
// the garment carries a warp at 45 degrees to the body's vertical (as the
// cloth model lays it, cloth::warp_direction), the waistband stays on the
// straight grain, and the grain line the pattern draws on each piece agrees
// with its faces' warp to within 1 degree (common/fabric/README.md).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "cloth/cloth_energy.h"
#include "garment/extend_boundary.h"
#include "garment/make_garment.h"
#include "pattern/layout.h"
#include "pattern/make_pattern.h"
#include "testing/skirt_scene.h"

using namespace gp;

namespace {

constexpr double kPi = 3.14159265358979323846;

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

// The area-weighted mean of a piece's faces' warps (each turned by its rest
// face's grain angle) mapped onto the laid-out sheet, as a unit vector.
Eigen::Vector2d mean_sheet_warp(const Pattern& pattern, const PatternPiece& p, const LaidOutPiece& lp,
                                const std::vector<double>& rest_angles, bool turned) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int f = 0; f < p.F.rows(); ++f) {
    Eigen::Matrix3d X;
    for (int k = 0; k < 3; ++k) X.col(k) = p.V.row(p.F(f, k)).transpose();
    const int rest_face = pattern.mesh.rest_face[static_cast<size_t>(p.face_ids[static_cast<size_t>(f)])];
    const double angle = turned ? rest_angles[static_cast<size_t>(rest_face)] : 0.0;
    const Eigen::Vector3d d = cloth::warp_direction(X, Eigen::Vector3d::UnitY(), angle);
    Eigen::Matrix<double, 3, 2> E;
    E.col(0) = X.col(1) - X.col(0);
    E.col(1) = X.col(2) - X.col(0);
    Eigen::Matrix2d E2;
    E2.col(0) = (lp.UV.row(p.F(f, 1)) - lp.UV.row(p.F(f, 0))).transpose();
    E2.col(1) = (lp.UV.row(p.F(f, 2)) - lp.UV.row(p.F(f, 0))).transpose();
    const double area = 0.5 * E.col(0).cross(E.col(1)).norm();
    mean += area * (E2 * (E.transpose() * E).inverse() * E.transpose() * d).normalized();
  }
  return mean.normalized();
}

double sheet_degrees(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

}  // namespace

TEST_CASE("a bias-cut skirt: its faces' warp at 45 degrees, and the pattern's grain line on it", "[pattern][fabric][grain]") {
  const testing::SkirtScene scene = testing::make_skirt_scene();
  const Eigen::MatrixXd& V_body = scene.avatar.poses.V[static_cast<size_t>(scene.design_pose)];
  const MakeGarmentResult top = make_garment(V_body, scene.avatar.poses.F, parse_garment_spec(scene.top_spec, "top.json"));
  CHECK(top.file.material.grain_angles.empty());  // no grain region: every face on the straight grain
  Json extend_spec = scene.extend_spec;
  extend_spec["grain"] = 45;
  const DesignBody body{V_body, scene.avatar.poses.F};
  const ExtendResult skirt = extend_boundary(top.mesh, top.file, parse_extend_spec(extend_spec, "extend.json"), &body);
  const Eigen::MatrixXd& V = skirt.mesh.V;
  const Eigen::MatrixXi& F = skirt.mesh.F;
  const std::vector<double>& angles = skirt.file.material.grain_angles;
  REQUIRE(static_cast<Eigen::Index>(angles.size()) == F.rows());

  // The waistband's faces (those of the garment before the band: its
  // vertices keep their ids, and come first) stay at 0; the band's are at
  // pi/4, and their warp is 45 degrees from the vertical projected into the face.
  const Eigen::Index top_vertices = top.mesh.V.rows();
  std::vector<char> in_band(static_cast<size_t>(F.rows()), 0);
  int band = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (F.row(f).maxCoeff() < top_vertices) {
      CHECK(angles[static_cast<size_t>(f)] == 0.0);
      continue;
    }
    in_band[static_cast<size_t>(f)] = 1;
    ++band;
    REQUIRE(angles[static_cast<size_t>(f)] == Approx(kPi / 4).epsilon(1e-12));
    Eigen::Matrix3d X;
    for (int k = 0; k < 3; ++k) X.col(k) = V.row(F(f, k)).transpose();
    const Eigen::Vector3d straight = cloth::warp_direction(X);
    const Eigen::Vector3d bias = cloth::warp_direction(X, Eigen::Vector3d::UnitY(), angles[static_cast<size_t>(f)]);
    INFO("band face " << f);
    CHECK(degrees_between(straight, bias) == Approx(45.0).margin(1e-9));
    // The straight warp is the body's vertical in the face (a cone's faces
    // lean, none lies flat): the bias warp is 45 degrees from it.
    const Eigen::Vector3d n = (X.col(1) - X.col(0)).cross(X.col(2) - X.col(0)).normalized();
    const Eigen::Vector3d up = (Eigen::Vector3d::UnitY() - n.y() * n).normalized();
    CHECK(degrees_between(up, bias) == Approx(45.0).margin(1e-6));
  }
  CHECK(F.rows() - band == top.mesh.F.rows());
  REQUIRE(band > 100);

  // A seam where the skirt meets the waistband (the waist loop's old
  // vertices, which keep their ids); the cutter opens both rings itself.
  const GarmentLoop& waist = top.file.loops[static_cast<size_t>(top.file.find_loop("waist"))];
  SeamPath seam{"waist", waist.vertex_ids, true, "test", {}};
  const Pattern pattern = make_pattern(V, F, {seam}, PatternOptions{});
  const Layout layout = layout_pattern(pattern, LayoutOptions{}, angles);
  const Layout straight_layout = layout_pattern(pattern, LayoutOptions{});
  int bias_pieces = 0, straight_pieces = 0;
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const PatternPiece& p = pattern.pieces[i];
    const LaidOutPiece& lp = layout.pieces[i];
    // The cutter smooths the waist seam through the rest triangles, so a
    // piece holds slivers of the faces beyond it: judged by where most of
    // its area lies, and every face's own warp counted.
    double area = 0.0, band_area = 0.0;
    for (int f = 0; f < p.F.rows(); ++f) {
      const Eigen::Vector3d e1 = (p.V.row(p.F(f, 1)) - p.V.row(p.F(f, 0))).transpose();
      const Eigen::Vector3d e2 = (p.V.row(p.F(f, 2)) - p.V.row(p.F(f, 0))).transpose();
      const double a = 0.5 * e1.cross(e2).norm();
      area += a;
      if (in_band[static_cast<size_t>(pattern.mesh.rest_face[static_cast<size_t>(p.face_ids[static_cast<size_t>(f)])])]) band_area += a;
    }
    const bool is_bias = band_area > 0.95 * area;
    INFO("piece " << p.name << ": " << band_area / area * 100 << " % of its area in the skirt");
    CHECK((band_area < 0.05 * area || is_bias));  // no piece straddles the waist seam
    REQUIRE(lp.grain_from_body_vertical);
    const Eigen::Vector2d grain = (lp.grain_to - lp.grain_from).normalized();
    // The grain line drawn is the faces' own warp, within 1 degree.
    CHECK(sheet_degrees(grain, mean_sheet_warp(pattern, p, lp, angles, true)) < 1.0);
    if (is_bias) {
      ++bias_pieces;
      // ... which is 45 degrees from where the straight grain would run:
      // the check would fail for a pattern that ignored the turn.
      CHECK(sheet_degrees(grain, mean_sheet_warp(pattern, p, lp, angles, false)) == Approx(45.0).margin(3.0));
      CHECK(lp.grain_turn * 180.0 / kPi == Approx(45.0).margin(3.0));
      CHECK(piece_label(lp, "skirt", p.name, CutInstruction{}).line2.find("deg to the vertical") != std::string::npos);
    } else {
      ++straight_pieces;
      CHECK(lp.grain_turn * 180.0 / kPi < 3.0);
      CHECK(std::abs(lp.rotation - straight_layout.pieces[i].rotation) * 180.0 / kPi < 3.0);
    }
  }
  CHECK(bias_pieces >= 1);
  CHECK(straight_pieces >= 1);
}
