#include <catch2/catch.hpp>

#include <cmath>

#include <Eigen/Geometry>

#include "avatar/make_avatar.h"
#include "garment/make_garment.h"
#include "mesh/topology.h"
#include "testing/test_meshes.h"

using gp::Json;

namespace {

// Eight body vertices around the slice of `landmark` (plane through its
// center with its normal), chosen by angle around the center.
Json ring_vertices(const Eigen::MatrixXd& V, const gp::GirthResult& g) {
  return Json(gp::testing::ring_vertex_ids(V, g.center, g.normal, 1.5 * g.target / (2 * M_PI)));
}

const gp::GirthResult& girth(const gp::AvatarResult& a, const std::string& name) {
  for (const auto& g : a.girths)
    if (g.name == name) return g;
  FAIL("no girth landmark " << name);
  return a.girths.front();
}

}  // namespace

TEST_CASE("a shirt on a generated body: four loops, one manifold piece, binding valid in the T-pose",
          "[garment][avatar]") {
  gp::AvatarOptions options;
  options.target_vertices = gp::kAvatarDefaultVertices;
  options.poses = {"apose", "tpose"};
  // Whether the hands touch the hips does not matter for a shirt.
  options.check_self_intersection = false;
  const gp::AvatarResult avatar = gp::make_avatar(gp::default_avatar_spec(), options);
  const Eigen::MatrixXd& V = avatar.poses.V[0];
  const Eigen::MatrixXi& F = avatar.poses.F;

  Json j;
  j["schema"] = "garment-spec/1";
  j["loops"] = Json::array({
      {{"name", "neck"}, {"pinned", true}, {"points", ring_vertices(V, girth(avatar, "neck"))}},
      {{"name", "waist"}, {"points", ring_vertices(V, girth(avatar, "hip"))}},
      {{"name", "cuff_left"}, {"pinned", true}, {"points", ring_vertices(V, girth(avatar, "wrist_left"))}},
      {{"name", "cuff_right"}, {"pinned", true}, {"points", ring_vertices(V, girth(avatar, "wrist_right"))}},
  });
  // Region: the front-most vertex at chest height.
  const gp::GirthResult& chest = girth(avatar, "chest");
  int front = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (std::abs(V(v, 1) - chest.center.y()) < 0.03 && std::abs(V(v, 0) - chest.center.x()) < 0.05 &&
        V(v, 2) > V(front, 2))
      front = static_cast<int>(v);
  j["region"] = front;
  j["resolution"] = {{"edge_length", 0.02}};
  j["offset"] = 0.015;
  const gp::MakeGarmentResult r = gp::make_garment(V, F, gp::parse_garment_spec(j, "shirt.json"));
  CHECK(r.component_count == 1);
  CHECK(r.boundary_loop_count == 4);
  CHECK(r.euler_characteristic == -2);
  CHECK(r.quality.fraction_min_angle_over_20 >= 0.99);
  CHECK(r.boundary_curve_error < 1e-3);
  CHECK(r.offset_error.max_error < 1e-3);
  // The binding evaluated in the T-pose lies on the loop's curve there.
  const Eigen::MatrixXd& V_t = avatar.poses.V[1];
  for (size_t k = 0; k < r.file.loops.size(); ++k) {
    const Eigen::MatrixXd P = gp::evaluate_curve(V_t, F, r.cut.curves[k]);
    double worst = 0.0;
    for (const auto& b : r.file.loops[k].binding) {
      const Eigen::Vector3d x = gp::evaluate(V_t, F, b);
      double d = 1e300;
      for (Eigen::Index i = 0; i < P.rows(); ++i) {
        const Eigen::Vector3d a = P.row(i), c = P.row((i + 1) % P.rows());
        const double t = std::clamp((x - a).dot(c - a) / std::max((c - a).squaredNorm(), 1e-300), 0.0, 1.0);
        d = std::min(d, (a + t * (c - a) - x).norm());
      }
      worst = std::max(worst, d);
    }
    CHECK(worst < 1e-6);
  }
}
