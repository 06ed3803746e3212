// The case that was missed: a generated body with its arms hanging beside
// the hips and a flared skirt whose cone passes through the hands and the
// seat. extend-boundary with the body leaves no vertex inside and no
// crossing, each hand on one side of the skirt, and the band's triangles
// about as good as without the push.
#include <catch2/catch.hpp>

#include <cmath>

#include "avatar/make_avatar.h"
#include "garment/extend_boundary.h"
#include "garment/make_garment.h"
#include "geometry/winding_number.h"
#include "mesh/measures.h"
#include "testing/skirt_scene.h"

TEST_CASE("a skirt through the hands and the seat of a generated body starts outside it", "[garment][avatar][clearance]") {
  const gp::testing::SkirtScene scene = gp::testing::make_skirt_scene();
  const Eigen::MatrixXd& V = scene.avatar.poses.V[scene.design_pose];
  const Eigen::MatrixXi& F = scene.avatar.poses.F;
  const gp::MakeGarmentResult top = gp::make_garment(V, F, gp::parse_garment_spec(scene.top_spec, "top.json"));
  const gp::ExtendSpec extend = gp::parse_extend_spec(scene.extend_spec, "extend.json");
  const gp::DesignBody body{V, F};
  const gp::ExtendResult with_body = gp::extend_boundary(top.mesh, top.file, extend, &body);
  const gp::ExtendResult without = gp::extend_boundary(top.mesh, top.file, extend);

  // As designed, the cone passes through the body: the seat and both hands.
  const gp::BodyClearanceResult& c = with_body.clearance;
  CHECK(c.before.cloth_vertices_inside > 0);
  CHECK(c.before.crossings() > 0);
  CHECK(c.places.size() >= 3);
  // Pushed out: nothing inside, no crossing.
  CHECK(c.clear());
  CHECK(c.after.cloth_vertices_inside == 0);
  CHECK(c.after.crossings() == 0);
  CHECK(c.min_distance > 0.0);
  // Each hand lies on one side of the skirt (not wrapped half around).
  for (const Eigen::Vector3d& hand : scene.hands) {
    double lowest = 1e9, highest = -1e9;
    for (int v = 0; v < V.rows(); ++v) {
      if ((V.row(v).transpose() - hand).norm() > 0.05) continue;
      const double w = gp::winding_number(with_body.mesh.V, with_body.mesh.F, V.row(v).transpose());
      lowest = std::min(lowest, w);
      highest = std::max(highest, w);
    }
    INFO("hand at " << hand.transpose());
    CHECK((highest < 0.5 || lowest > 0.5));
  }
  // The same connectivity as without the body; triangles nearly as good.
  CHECK(with_body.mesh.F == without.mesh.F);
  const double L = top.file.target_edge_length;
  const gp::MeshQuality q_with = gp::measure_quality(with_body.mesh.V, with_body.mesh.F, L);
  const gp::MeshQuality q_without = gp::measure_quality(without.mesh.V, without.mesh.F, L);
  CHECK(q_with.fraction_min_angle_over_20 >= q_without.fraction_min_angle_over_20 - 0.03);
  CHECK(q_with.fraction_edges_within_30 >= q_without.fraction_edges_within_30 - 0.05);
}
