// An armhole that runs within a hair of a user seam crosses it back and forth
// and leaves slivers between the two: merge_armhole_slivers joins each
// sliver to the piece across the armhole and leaves the user seam whole.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "mesh/measures.h"
#include "pattern/make_pattern.h"
#include "pattern/pattern.h"
#include "testing/test_meshes.h"

using namespace gp;

namespace {

double piece_area(const PatternPiece& p) { return face_areas(p.V, p.F).sum(); }

}  // namespace

TEST_CASE("slivers between an armhole and a user seam join the piece across the armhole", "[cutter][armholes]") {
  // A 20 cm square of 1 cm cells in the xz-plane; grid vertex (i, j) is at
  // (i, 0, j) cm, and the cells' diagonals run from (i, j) to (i+1, j+1).
  const int n = 20;
  const Mesh grid = testing::make_grid(n, n, 0.2, 0.2);
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  // The user seam: column i = 10, top to bottom.
  SurfaceCurve user;
  for (int j = 0; j <= n; ++j) user.push_back(CurvePoint::at_vertex(id(10, j)));
  // The armhole: down column 9 from the top, across the user seam at (10, 3)
  // to column 11, back across it at (10, 5) and along row 5 to the left
  // edge. It cuts off a "sleeve" (the top left corner) and leaves two
  // slivers beside the user seam: 2.5 cm^2 left of it (rows 0-3) and
  // 1.5 cm^2 right of it (rows 3-5).
  SurfaceCurve armhole;
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{9, 0}, {9, 1}, {9, 2}, {10, 3}, {11, 4}, {11, 5}})
    armhole.push_back(CurvePoint::at_vertex(id(i, j)));
  for (int i = 10; i >= 0; --i) armhole.push_back(CurvePoint::at_vertex(id(i, 5)));

  const std::vector<PatternSeam> seams{{"side", "user", "", {}, false, false, {}},
                                       {"armhole1", "armhole", "", {}, false, true, {}}};
  Pattern pattern;
  pattern.mesh = pattern_mesh_of_rest(grid.V, grid.F);
  insert_cuts(pattern, seams, {user, armhole});
  REQUIRE(pattern.pieces.size() == 5);
  std::vector<double> before;
  for (const PatternPiece& p : pattern.pieces) before.push_back(piece_area(p));
  std::sort(before.begin(), before.end());
  CHECK(before[0] == Approx(1.5e-4).epsilon(1e-9));
  CHECK(before[1] == Approx(2.5e-4).epsilon(1e-9));
  const std::vector<int> user_path = pattern.seams[0].vertex_ids;

  PatternOptions options;
  options.armholes.sliver_area = 3e-4;  // both slivers, not the 47.5 cm^2 "sleeve"
  merge_armhole_slivers(pattern, options);

  // Three pieces: the sleeve with the left sliver, the lower left, the right
  // with the right sliver; every piece a disk, the area unchanged.
  REQUIRE(pattern.pieces.size() == 3);
  std::vector<double> after;
  for (const PatternPiece& p : pattern.pieces) {
    CHECK(is_disk(p));
    after.push_back(piece_area(p));
  }
  std::sort(after.begin(), after.end());
  CHECK(after[0] == Approx(47.5e-4 + 2.5e-4).epsilon(1e-9));  // rows 0-5 left of the seam, sliver included
  CHECK(after[1] == Approx(150e-4).epsilon(1e-9));             // rows 5-20 left of the seam
  CHECK(after[2] == Approx(200e-4).epsilon(1e-9));             // the right half, sliver included
  // The user seam is whole; what is left of the armhole runs from where it
  // last crosses the user seam to the left edge: 10 cm.
  REQUIRE(pattern.seams.size() == 2);
  CHECK(pattern.seams[0].name == "side");
  CHECK(pattern.seams[0].vertex_ids == user_path);
  CHECK(pattern.seams[1].kind == "armhole");
  CHECK_FALSE(pattern.seams[1].closed);
  CHECK(pattern.seams[1].vertex_ids.front() == id(10, 5));
  CHECK(pattern.seams[1].vertex_ids.back() == id(0, 5));
  // One note per sliver, saying how much armhole was not cut.
  int notes = 0;
  for (const std::string& note : pattern.notes) notes += note.find("a sliver of") != std::string::npos ? 1 : 0;
  CHECK(notes == 2);

  SECTION("below sliver_area nothing merges") {
    Pattern again;
    again.mesh = pattern_mesh_of_rest(grid.V, grid.F);
    insert_cuts(again, seams, {user, armhole});
    options.armholes.sliver_area = 1e-4;  // both slivers are larger
    merge_armhole_slivers(again, options);
    CHECK(again.pieces.size() == 5);
    CHECK(again.notes.empty());
  }
}
