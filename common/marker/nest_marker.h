#pragma once
// Nests the pieces of a marker on a strip of fabric: the fabric's width is
// fixed (y), its length (x, along the grain) is what the nesting shortens.
//
// Method (own implementation): pieces are rasterised conservatively on a
// grid of `resolution` (a cell is taken wherever the piece's outline or
// inside touches it, so pieces whose cells are apart cannot overlap, and
// a piece inside its cells stays inside the width), then placed one after
// another by bottom-left fill: each copy, in each allowed orientation, goes
// where its right end is leftmost (ties: its left end, then lowest y),
// found row by row by jumping past occupied runs. The order of the copies
// is improved by a local search (swap two copies or move one; keep a move
// that does not lengthen the marker), from largest-first, with a seeded
// generator and a budget of work: the search stops after
// `budget_s * kWorkPerSecond` interval tests (kWorkPerSecond measured on
// the project's build machine), never by the clock, so that a seed and a
// budget give the same marker on any machine (in about budget_s seconds on
// the build machine). Evaluations that cannot beat the best order stop early.
//
// Compare: Dowsland, Vaid and Dowsland (2002), "An algorithm for polygon
// placement using a bottom-left strategy" (EJOR 141); Jakobs (1996) for
// bottom-left fill driven by a search over the order.
#include <vector>
#include <Eigen/Core>

#include "marker/marker_pieces.h"

namespace gp {

struct NestOptions {
  double width = 1.5;       // fabric width, units of the pieces (metres for a pattern)
  double resolution = 0.0;  // raster cell, units; 0: width / 300 (5 mm on 1.5 m)
  unsigned seed = 1;        // the local search's generator
  double budget_s = 10.0;   // the search's work budget, seconds on the build machine (0: largest-first only)
};

// Interval tests per CPU second of the build machine (2-core AMD EPYC, Release;
// measured on the ESICUP shirts instance: 1.0e9 tests in 6.3 s of CPU).
constexpr double kWorkPerSecond = 1.5e8;

struct Placement {
  int piece = -1;      // index in MarkerPieces::pieces
  int copy = 0;        // 0 .. quantity - 1
  bool mirrored = false;  // mirrored across the grain (y -> -y) before turning
  int rotation = 0;    // degrees, counter-clockwise
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // added after mirroring and turning
  std::vector<Eigen::Vector2d> outline;  // placed, units of the pieces
};

struct MarkerResult {
  std::vector<Placement> placements;  // one per copy, in placement order
  double width = 0.0, length = 0.0;   // units
  double piece_area = 0.0;            // sum of the copies' areas
  double utilisation = 0.0;           // piece_area / (width * length)
  double resolution = 0.0;
  double first_length = 0.0;          // largest-first, before the search
  long long work = 0;                 // interval tests spent
  int evaluations = 0;                // orders tried
};

// Throws GeometryError when a piece is wider than the fabric in every
// allowed orientation.
MarkerResult nest_marker(const MarkerPieces& pieces, const NestOptions& options);

// The piece's outline mirrored (y -> -y) if asked, then turned by `rotation` degrees.
std::vector<Eigen::Vector2d> oriented_outline(const std::vector<Eigen::Vector2d>& outline, bool mirrored, int rotation);

// Whether two simple polygons overlap (share interior): edges that cross
// properly, or a vertex of one strictly inside the other. Touching is not overlap.
bool polygons_overlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b, double tolerance);

}  // namespace gp
