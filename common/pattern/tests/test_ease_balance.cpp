// A piece over one bound of the one-sided limit and within the other trades
// them (balance_ease, make_pattern.h): a spherical cap cut as one piece, no
// darts and no panel seams, flattened with ease priced at a tenth of
// compression, is within a loose ease bound but over a tight compression
// bound; with ease priced lower it takes the excess as ease and meets both.
#include <catch2/catch.hpp>

#include <vector>

#include "pattern/make_pattern.h"
#include "testing/test_meshes.h"

using namespace gp;

namespace {

// The faces of an icosphere of radius 0.2 m above y = h.
Mesh cap(double h) {
  const Mesh sphere = testing::make_icosphere(4, 0.2);
  std::vector<int> faces;
  for (int f = 0; f < sphere.F.rows(); ++f) {
    bool above = true;
    for (int k = 0; k < 3; ++k) above = above && sphere.V(sphere.F(f, k), 1) > h;
    if (above) faces.push_back(f);
  }
  return testing::face_subset(sphere, faces).mesh;
}

PatternOptions one_piece() {
  PatternOptions o;
  o.darts.max_darts = 0;
  o.panels.max_pieces = 1;
  o.armholes.enabled = false;
  o.panels.mirror = false;
  // The cap's rim free: held at its 3D length, the rim is shorter than the
  // flat disc's and compresses the cap radially whatever ease costs.
  o.flatten.boundary_weight = 0.0;
  // The ease trade alone, on the plain flattening (the limit weighting
  // would move the same figures by its own rounds).
  o.flatten.limit_rounds = 0;
  return o;
}

}  // namespace

TEST_CASE("a piece over the compression bound and within the ease bound is eased into the limit", "[cutter][ease]") {
  const Mesh m = cap(0.17);
  PatternOptions o = one_piece();
  o.panels.ease_balance_steps = 0;
  const Pattern plain = make_pattern(m.V, m.F, {}, o);
  REQUIRE(plain.pieces.size() == 1);
  const DistortionStats& s0 = plain.pieces[0].stats;
  INFO("plain: compression " << s0.worst1_compression << " ease " << s0.worst5_ease);
  // The bounds placed so that the plain flattening is tight but has room for ease.
  o.limit.compression_worst1 = 0.8 * s0.worst1_compression;
  o.limit.ease_worst5 = 1.6 * s0.worst5_ease;
  const Pattern tight = make_pattern(m.V, m.F, {}, o);
  CHECK(!tight.meets_limit);
  o.panels.ease_balance_steps = 4;
  const Pattern eased = make_pattern(m.V, m.F, {}, o);
  REQUIRE(eased.pieces.size() == 1);
  const DistortionStats& s1 = eased.pieces[0].stats;
  INFO("eased: compression " << s1.worst1_compression << " ease " << s1.worst5_ease);
  CHECK(eased.meets_limit);
  CHECK(s1.worst1_compression < o.limit.compression_worst1);
  CHECK(s1.worst5_ease > s0.worst5_ease);
  CHECK(eased.pieces[0].flat.stats.area_2d > plain.pieces[0].flat.stats.area_2d);

  // Over the ease bound and within compression (the rim held at its 3D
  // length, as seams are): ease made dearer.
  PatternOptions held = one_piece();
  held.flatten.boundary_weight = PatternOptions{}.flatten.boundary_weight;
  held.panels.ease_balance_steps = 0;
  const DistortionStats h0 = make_pattern(m.V, m.F, {}, held).pieces[0].stats;
  INFO("held rim: compression " << h0.worst1_compression << " ease " << h0.worst5_ease);
  PatternOptions loose = held;
  loose.panels.ease_balance_steps = 4;
  loose.limit.compression_worst1 = 3.0 * h0.worst1_compression;
  loose.limit.ease_worst5 = 0.8 * h0.worst5_ease;
  const Pattern less = make_pattern(m.V, m.F, {}, loose);
  const DistortionStats& s2 = less.pieces[0].stats;
  INFO("less ease: compression " << s2.worst1_compression << " ease " << s2.worst5_ease);
  CHECK(less.meets_limit);
  CHECK(s2.worst5_ease < loose.limit.ease_worst5);
  // (Here dearer ease takes compression down too, 6.5 -> 5.5 %: held at
  // its rim, the cheap ease of the default weight had not relieved it.)

  // Over both: no trade helps, the piece stays as it was flattened.
  PatternOptions both = one_piece();
  both.panels.ease_balance_steps = 4;
  both.limit.compression_worst1 = 0.5 * s0.worst1_compression;
  both.limit.ease_worst5 = 0.5 * s0.worst5_ease;
  const Pattern neither = make_pattern(m.V, m.F, {}, both);
  CHECK(!neither.meets_limit);
  CHECK(neither.pieces[0].stats.worst5_ease == Approx(s0.worst5_ease).epsilon(1e-9));
  CHECK(neither.pieces[0].stats.worst1_compression == Approx(s0.worst1_compression).epsilon(1e-9));
  // Off by default; the symmetric limit is left alone.
  CHECK(PatternOptions{}.panels.ease_balance_steps == 0);
  PatternOptions symmetric = o;
  symmetric.limit.symmetric = true;
  symmetric.limit.p95_limit = 0.5;
  symmetric.limit.max_limit = 0.9;
  CHECK(make_pattern(m.V, m.F, {}, symmetric).pieces[0].stats.worst5_ease == Approx(s0.worst5_ease).epsilon(1e-9));
}
