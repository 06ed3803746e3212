// A short-sleeved top designed on a generated body in the A-pose, as the demo
// customer's: the armpits are pinches narrower than twice the offset, where
// the exact offset surface has a crease. make-garment with default options
// gives a garment without cone points or slivers there, outside the body.
#include <catch2/catch.hpp>

#include <cmath>

#include "avatar/make_avatar.h"
#include "garment/make_garment.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "testing/test_meshes.h"

using gp::Json;

namespace {

const gp::GirthResult& girth(const gp::AvatarResult& a, const std::string& name) {
  for (const auto& g : a.girths)
    if (g.name == name) return g;
  FAIL("no girth landmark " << name);
  return a.girths.front();
}

Json ring_vertices(const Eigen::MatrixXd& V, const gp::GirthResult& g) {
  return Json(gp::testing::ring_vertex_ids(V, g.center, g.normal, 1.5 * g.target / (2 * M_PI)));
}

}  // namespace

TEST_CASE("a top on a generated A-pose body has no cone points and no slivers in its armpits",
          "[garment][avatar][offset]") {
  gp::AvatarOptions options;
  options.poses = {"apose"};
  options.check_self_intersection = false;
  const gp::AvatarResult avatar = gp::make_avatar(gp::default_avatar_spec(), options);
  const Eigen::MatrixXd& V = avatar.poses.V[0];
  const Eigen::MatrixXi& F = avatar.poses.F;

  Json j;
  j["schema"] = "garment-spec/1";
  j["loops"] = Json::array({
      {{"name", "neck"}, {"pinned", true}, {"points", ring_vertices(V, girth(avatar, "neck"))}},
      {{"name", "hem"}, {"points", ring_vertices(V, girth(avatar, "waist"))}},
      {{"name", "sleeve_left"}, {"points", ring_vertices(V, girth(avatar, "upper_arm_left"))}},
      {{"name", "sleeve_right"}, {"points", ring_vertices(V, girth(avatar, "upper_arm_right"))}},
  });
  const gp::GirthResult& chest = girth(avatar, "chest");
  int front = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (std::abs(V(v, 1) - chest.center.y()) < 0.03 && std::abs(V(v, 0) - chest.center.x()) < 0.05 &&
        V(v, 2) > V(front, 2))
      front = static_cast<int>(v);
  j["region"] = front;
  // The demo's resolution and offset: 1,100 vertices, 1 cm.
  j["resolution"] = {{"vertex_count", 1100}};
  const double offset = 0.01;
  j["offset"] = offset;
  const gp::GarmentSpec spec = gp::parse_garment_spec(j, "top.json");
  const gp::MakeGarmentResult r = gp::make_garment(V, F, spec);
  REQUIRE(r.component_count == 1);
  REQUIRE(r.boundary_loop_count == 4);

  // No inner vertex at |angle defect| >= 18 degrees, counted here from the mesh.
  std::vector<char> inner(static_cast<size_t>(r.mesh.V.rows()), 1);
  for (const auto& loop : gp::boundary_loops(r.mesh.F))
    for (int v : loop) inner[static_cast<size_t>(v)] = 0;
  const Eigen::VectorXd K = gp::angle_defects(r.mesh.V, r.mesh.F);
  double largest = 0.0;
  for (Eigen::Index v = 0; v < K.size(); ++v)
    if (inner[static_cast<size_t>(v)]) largest = std::max(largest, std::abs(K[v]) * 180.0 / M_PI);
  CHECK(largest < gp::kConeDefectDeg);
  CHECK(r.quality.cone_vertices == 0);
  // Even triangles: no sliver anywhere, the armpits included.
  CHECK(r.quality.min_angle_deg > 15.0);
  CHECK(r.quality.faces_min_angle_under_5 == 0);
  // The saddles are refined (to 0.6^3 of the edge length at most), but no
  // cluster of tiny triangles is left: 1.4 mm at the least.
  CHECK(r.quality.min_edge_ratio > 0.05);
  // Outside the body, never closer than the offset; lifted off it only in
  // the pinches, by less than the rounding radius.
  CHECK(r.clearance.clear());
  CHECK(r.offset_error.max_below < 1e-4);
  CHECK(r.offset_error.max_above < spec.offset_fillet);
}

