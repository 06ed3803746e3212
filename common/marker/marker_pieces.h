#pragma once
// The pieces a marker nests, as the small JSON polygon schema
// "marker-pieces/1" that make-marker reads (and export-rest writes beside
// its pattern, marker_pieces.json):
//
//   { "schema": "marker-pieces/1",
//     "units": "m",                 // "m" (metres), or any other word: unitless (benchmarks)
//     "fabric_width": 1.5,          // optional: the width the marker is for, in the units
//     "fabric": "denim-11oz",       // optional: the fabric the pieces are cut from (common/fabric)
//     "pieces": [ { "name": "front",
//                   "outline": [[x, y], ...],   // the cutting line, >= 3 points, any orientation
//                   "quantity": 1,              // copies to cut (>= 1)
//                   "mirrored_pairs": false,    // true: every second copy is the mirror image
//                   "orientations": [0, 180] } ] }  // allowed turns in degrees (multiples of 90)
//
// The frame is the marker's: x along the fabric's length (the warp, the
// selvedge), y across its width. A piece's grain line runs along x, so
// orientations 0 and 180 keep it on the grain.
#include <filesystem>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "spec/json_file.h"

namespace gp {

struct MarkerPiece {
  std::string name;
  std::vector<Eigen::Vector2d> outline;  // units of the file
  int quantity = 1;
  bool mirrored_pairs = false;
  std::vector<int> orientations = {0, 180};  // degrees
};

struct MarkerPieces {
  std::string units = "m";
  double fabric_width = 0.0;  // 0: not given
  std::string fabric;         // empty: not given (export-rest names a fabric a garment spec chose)
  std::vector<MarkerPiece> pieces;
};

// Strict reader: SpecError naming the JSON pointer of a bad field, InputError
// for an unreadable file, GeometryError for an outline of no area.
MarkerPieces read_marker_pieces(const std::filesystem::path& path);

OrderedJson marker_pieces_json(const MarkerPieces& pieces);

// Area of a polygon, positive when counter-clockwise.
double signed_area(const std::vector<Eigen::Vector2d>& outline);

}  // namespace gp
