#pragma once
// The round trip of a pattern (Wolff et al. 2023, sec. 7: sew the flattened
// pieces back together and compare the drapes): the garment is draped on the
// design pose twice, with the same simulator, pins and body, and settled:
//   1. with the rest shape's own triangles (what the fit designed),
//   2. with the flat pattern pieces' triangles as rest shape (what a tailor
//      sews: every rest face takes its triangle from its piece; pieces join
//      along the seams because their vertices are the rest shape's).
// Reported: the distance between the two drapes per vertex and the stretch of
// the sewn drape against its flat pieces.
#include <string>
#include <vector>
#include <Eigen/Core>

#include "cloth/cloth_energy.h"
#include "garment/garment_file.h"
#include "pattern/pattern.h"
#include "pattern/layout.h"
#include "pose/pose_set.h"

namespace gp {

struct RoundTripOptions {
  // Settling time step [s]. Four times the fit's 0.0025 s: a drape on a
  // still body needs only the settled state. On the shared shirt (3,829
  // vertices, designed) 0.0025 / 0.005 / 0.01 s give drape distances of
  // 4.3 / 4.0 / 3.9 mm max and 1.46 / 1.63 / 1.59 mm p95, the sewn drape
  // settling in 112 / 120 / 56 steps (33 / 47 / 16 s for both drapes).
  double dt = 0.01;
  int settle_max_steps = 1000;   // cap per drape [steps]
  // m/s: largest vertex speed of a settled cloth. Stricter than the fit's
  // 0.05 m/s: a garment that starts at rest passes 0.05 m/s within a few
  // steps, before gravity and the pins have shaped it.
  double settle_speed = 0.005;
};

// The flat rest triangle of every rest face (#F, in rest face order): its
// corners in its laid-out piece (sheet metres), turned so that the sheet's
// y axis (the grain line, the body's vertical) is the warp (the u axis of
// cloth::triangle_rest_flat), as the rest shape's own triangles have +y as warp.
// A rest face that a cut runs through holds cloth of two pieces: its
// triangle has the area-weighted mean metric of its parts (and the warp of
// the largest), the simulation's resolution being the rest shape's.
std::vector<cloth::TriangleRest> sewn_rest_triangles(const Pattern& pattern, const Layout& layout, int face_count);

struct DrapeRun {
  int settle_steps = 0;
  bool settled = false;
  double seconds = 0.0;  // wall time
};

struct StretchFigures {  // principal stretches s1 >= s2 per face against a rest triangle
  double max_s1 = 0.0;   // largest stretch
  double p95_s1 = 0.0;   // 95th percentile of s1 by rest area
  double mean_s1 = 0.0;  // rest-area weighted mean of s1
  double min_s2 = 0.0;   // strongest compression
};

struct RoundTripResult {
  std::string pose;                      // the garment's design pose
  Eigen::MatrixXd V_rest_drape;          // #V by 3, drape with the rest shape's triangles
  Eigen::MatrixXd V_sewn_drape;          // #V by 3, drape with the pattern's flat triangles
  double max_distance = 0.0;             // metres, over vertices
  double mean_distance = 0.0;            // metres
  double p95_distance = 0.0;             // metres, 95th percentile over vertices
  StretchFigures rest_drape_stretch;     // rest drape against the rest shape
  StretchFigures sewn_drape_stretch;     // sewn drape against the flat pieces
  DrapeRun rest_run, sewn_run;
};

// V_rest, F: the rest shape the pattern was made from. `poses` must hold the
// garment's design pose (garment.body.design_pose). Throws SpecError when the
// pose is missing, GeometryError from the simulation, NumericalError naming
// the drape when a simulation step fails (a pattern far from its rest shape
// can start with forces no step survives).
// Both drapes start at V_start (#V by 3; the garment as designed, which lies
// at the comfort offset without the tucks an adapted rest shape may have) or,
// when null, at V_rest.
RoundTripResult round_trip(const PoseSet& poses, const GarmentFile& garment, const Eigen::MatrixXd& V_rest,
                           const Eigen::MatrixXi& F, const Pattern& pattern, const Layout& layout,
                           const RoundTripOptions& options, const Eigen::MatrixXd* V_start = nullptr);

}  // namespace gp
