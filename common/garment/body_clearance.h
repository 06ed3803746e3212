#pragma once
// A designed garment that starts outside the body: where it passes through
// the body (a skirt through a hand, a band through a thigh) it is pushed out,
// to the comfort offset where there is room.
//
// The meeting points are found exactly (collision/crossings.h) and grouped
// into body parts (points whose nearest body vertices lie within
// `part_radius` along the body's edges: a hand, not a hand and the hip
// beside it). Each part stays on one side of the garment: where most of it
// lies by the garment's winding number, else the side of the smaller pushes;
// so a skirt never wraps half around a hand. Each point asks for a push along
// the garment's normal to the offset, or the middle of a narrower gap, never
// through a second part; the garment moves as a membrane meeting all asks
// and fading out over `spread`. Rounds repeat up to `max_rounds`; the best
// round is kept. Fixed vertices (bound loops) never move.
#include <vector>

#include <Eigen/Core>

#include "collision/crossings.h"
#include "spec/json_file.h"

namespace gp {

struct BodyClearanceOptions {
  double offset = 0.0;        // m: clearance wanted where there is room (the comfort offset)
  double min_clearance = 1e-3;  // m: touching below this; the target of a garment with offset 0
  double tolerance = 1e-4;    // m: a vertex this much closer than the offset is left alone (rounding of the offset)
  double search = 0.05;       // m: longest push searched (through a hand, not a thigh)
  double search_step = 1e-3;  // m: step of that search
  double spread = 0.04;       // m: the membrane's decay length around a push
  int membrane_iterations = 300;  // Jacobi steps of the displacement per round
  double part_radius = 0.06;  // m: places this close along the body are one body part
  int max_rounds = 8;
  // false: a garment that nothing passes through is returned as it is
  // (make-garment, whose offset already placed every vertex).
  bool improve_clear = true;
};

// One body part the garment met.
struct ClearancePlace {
  int body_vertex = -1;        // a body vertex of the part (names the place)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // m, centroid of the part's body vertices met
  int side = 0;                // +1 pushed along the garment normals, -1 against them
  double largest_push = 0.0;   // m
  bool room = true;            // every point found a position at the clearance
};

struct BodyClearanceResult {
  collision::CrossingReport before, after;  // of the garment as given and as returned
  int moved_vertices = 0;
  double largest_move = 0.0;   // m
  int rounds = 0;
  std::vector<ClearancePlace> places;  // every body part met, in the order found
  int tight_vertices = 0;      // after: vertices closer to the body than offset - tolerance (no room there)
  double min_distance = 0.0;   // after: smallest signed distance of a garment vertex to the body [m]
  bool clear() const { return after.intersection_free(); }
};

// V #V by 3 (moved in place), F #F by 3: the garment; V_body, F_body: the body
// in the design pose (closed, outward oriented). fixed (#V or empty): vertices
// that must not move. Throws as collision::find_crossings.
BodyClearanceResult clear_body(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& V_body,
                               const Eigen::MatrixXi& F_body, const std::vector<char>& fixed,
                               const BodyClearanceOptions& options);

// The result as a JSON object for stage reports: "clear", the crossing
// reports before and after, moves [m] and the places met.
OrderedJson to_json(const BodyClearanceResult& result);

}  // namespace gp
