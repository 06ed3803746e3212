#pragma once
// The garment spec (schema "garment-spec/1"): the design tools T1 to T5 as
// JSON instead of mouse clicks.
//
//   {
//     "schema": "garment-spec/1",
//     "name": "shirt",
//     "design_pose": "tpose",            // optional; else --pose or the reference pose
//     "loops": [                          // T1 boundary loops, closed automatically
//       { "name": "neck", "pinned": true, // T5 (default false)
//         "points": [ 1234, [0.01, 1.45, 0.05], ... ] },  // body vertex ids or
//       ...                               //   3D points snapped to the body
//     ],
//     "region": 5678,                     // one point inside the garment (id or [x,y,z])
//     "resolution": { "edge_length": 0.015 }   // metres, or { "vertex_count": 4000 }
//     "offset": 0.015,                    // T4 comfort offset, metres (default 0)
//     "offset_fillet": 0.02,              // metres: creases of the offset surface are rounded
//                                         //   to this radius (comfort_offset.h; default 0: sharp)
//     "paint": [                          // T3, optional; factors multiply where regions overlap
//       { "name": "back", "factor": 1.2, "disc": { "center": 4321, "radius": 0.1 } },
//       { "name": "elbow", "factor": 1.1, "vertices": [ 11, 12, 13 ] } ],
//     "fabric": "cotton-poplin",          // optional: a fabric of common/fabric (default "paper"),
//                                         //   or in full with units: { "name": "my-twill",
//                                         //   "areal_density": "210 g/m^2", "k_warp": "4000 N/m", ... }
//     "material": { "k_stretch": 800, ... },  // optional instead of "fabric": raw cloth parameters
//     "grain": [                          // optional: the warp turned per region (a bias cut), in
//       { "name": "skirt", "angle": 45,   //   degrees within [-90, 90], counter-clockwise about the
//         "disc": { "center": 4321, "radius": 0.3 } } ],  // outward normal from the body's vertical;
//                                         //   regions as paint's ("disc" or "vertices"); the last wins
//     "ease": -0.08,                      // optional, knits only: start 8 % smaller than the design
//     "smoothing": { "iterations": 12, "band_rings": 5 },   // optional
//     "remesh": { "iterations": 8, "relaxation_steps": 2 },  // optional
//     "snap_tolerance": 0.05              // metres: how far a 3D point may be from the body
//   }
#include <filesystem>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "garment/garment_file.h"
#include "garment/region_cut.h"
#include "garment/remesh.h"
#include "spec/clicked_point.h"
#include "spec/json_file.h"

namespace gp {

// A clicked point: a body vertex id, or a 3D point (metres) snapped to the body.
using SpecPoint = ClickedPoint;

struct SpecLoop {
  std::string name;
  bool pinned = false;
  std::vector<SpecPoint> points;
  std::string where;
};

struct PaintRegion {
  std::string name;
  double factor = 1.0;     // area factor (> 0): > 1 enlarges the rest shape
  bool is_disc = true;
  SpecPoint center;        // disc: geodesic disc around this point
  double radius = 0.0;     // disc radius along the body surface, metres
  std::vector<long long> vertex_ids;  // or: a set of body vertices
  std::string where;
};

// A region whose warp is turned (common/garment/README.md, "Grain"): the
// faces over the body region `on` (its factor unused) lay the warp `angle`
// radians counter-clockwise about their outward normal from the body's
// vertical (pi/4: a bias cut).
struct GrainRegion {
  std::string name;
  double angle = 0.0;  // radians; the spec gives degrees
  PaintRegion on;
  std::string where;
};

struct GarmentSpec {
  std::string file;
  std::string name;
  std::string design_pose;  // empty: not given
  std::vector<SpecLoop> loops;
  SpecPoint region;
  double edge_length = 0.0;    // metres; 0 when vertex_count is given
  long long vertex_count = 0;  // 0 when edge_length is given
  double offset = 0.0;
  // Radius (metres) to which the comfort-offset surface's creases are rounded
  // (OffsetSurface, comfort_offset.h); 0: the exact offset surface, which
  // folds where two body parts come closer than twice the offset (an A-pose
  // armpit). 0.02 suits garments of 1-1.5 cm edges (common/garment/README.md).
  double offset_fillet = 0.0;
  std::vector<PaintRegion> paint;
  std::vector<GrainRegion> grain;  // in spec order; a face in several takes the last one's angle
  // Negative ease of a knit (common/garment/README.md, "Negative ease"): the
  // rest shape starts this fraction smaller than the design in every
  // direction (-0.08: 8 % smaller), at most as small as the knit's smaller
  // stretch limit allows (1 + ease >= 1 / min(limit_warp, limit_weft)); 0: none.
  double ease = 0.0;
  Material material;
  RegionCutOptions smoothing;
  RemeshOptions remesh;  // target_edge_length is filled in by make_garment
  double snap_tolerance = 0.05;
  // Width (metres) of the fabric the garment is cut from; 0: not given.
  // make-garment only records it; make fit nests the pattern on it
  // (make-marker) where customer.mk sets no FABRIC_WIDTH of its own.
  double fabric_width = 0.0;
};

// Strict reader; SpecError naming the file and JSON pointer of any wrong,
// unknown, missing or out-of-range field.
GarmentSpec read_garment_spec(const std::filesystem::path& path);
GarmentSpec parse_garment_spec(const Json& j, const std::string& file);
// The effective spec with defaults filled in, for reports.
OrderedJson to_json(const GarmentSpec& spec);

}  // namespace gp
