#pragma once
// A designed garment that starts outside the body: where the garment passes
// through the body (a skirt cone through the hips or a hand, a band through a
// thigh), it is pushed out until it is clear, at the comfort offset where
// there is room.
//
// Where the surfaces meet is found exactly (collision/crossings.h): garment
// vertices inside the body or closer than the offset, and the points where a
// body edge passes through a garment triangle or a garment edge through a body
// triangle. Each of these points belongs to the body part it meets: points
// whose nearest body vertices lie within `part_radius` of each other along
// the body's edges are one part (the fingers and palm of a hand; a hand and
// the hip beside it are far apart along the body, so they are two). Every
// part ends on one side of the garment: the side where most of it lies (by
// the garment's winding number at its body vertices: the hips inside a
// skirt, a hand beside it outside), or where that is undecided the side
// that needs the smaller pushes; it keeps that side in later rounds. A skirt
// through a hand thus ends with the hand on one side of it, never wrapped
// half around it. Each point then asks for a displacement along the
// garment's normal, on its part's side, into its free stretch: at least the
// offset from the body, or the middle of a narrower gap, never through a
// second body part. The garment moves as a membrane that meets all these
// asks and fades out over `spread` around them (a smooth dent or bulge that
// keeps the triangles' shape). Rounds repeat until the garment is clear or
// `max_rounds`, and the best round's garment (fewest crossings and vertices
// inside) is kept. Fixed vertices (loops bound to the body) never move.
#include <vector>

#include <Eigen/Core>

#include "collision/crossings.h"
#include "spec/json_file.h"

namespace gp {

struct BodyClearanceOptions {
  double offset = 0.0;        // m: clearance wanted where there is room (the comfort offset)
  // m: clearance below which a vertex counts as touching, also the target of
  // a garment with offset 0 (a surface on the body would touch it everywhere).
  double min_clearance = 1e-3;
  double tolerance = 1e-4;    // m: a vertex this much closer than the offset is left alone (rounding of the offset)
  // m: longest push searched for: through a hand or a wrist, not through a
  // thigh or the torso.
  double search = 0.05;
  double search_step = 1e-3;  // m: step of that search
  // m: length over which a push fades into the garment around it (the
  // membrane's decay length, see clear_body).
  double spread = 0.04;
  int membrane_iterations = 300;  // Jacobi steps of the displacement per round
  double part_radius = 0.06;  // m: places this close along the body are one body part
  int max_rounds = 8;
  // false: a garment that nothing passes through is returned as it is, even
  // where vertices lie closer than the offset (make-garment, whose offset
  // already put every vertex as far out as there is room).
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
