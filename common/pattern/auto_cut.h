#pragma once
// From a rest shape and the user's seams to flat pattern pieces meeting a
// distortion limit: cut along the seams, make every piece a disk (cuts that
// join its boundary loops), flatten, and cut more where the flattening
// distorts too much, until every piece meets the limit.
//
// Extra cuts (a greedy cut-graph growth in the spirit of Gu, Gortler and
// Hoppe 2002, "Geometry images", section 3.2): in a failing piece take the
// vertex where the distortion concentrates (largest area-weighted error of
// its triangles, or a vertex where the flat boundary overlaps itself). If it
// lies inside the piece, cut the shortest edge path from it to the boundary.
// If it lies on the boundary (where ARAP pushes the distortion of a curved
// piece), cut inward from it to the vertex that maximizes
//   depth(v) - tip_weight * distance(vertex, v),
// depth being the distance to the boundary: a dart reaching into the part of
// the piece farthest from any edge, where the unrelieved curvature sits, while
// staying short. Repeat, one cut per failing piece per round.
#include <map>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "pattern/flatten.h"
#include "pattern/mesh_cut.h"
#include "pattern/seam_spec.h"

namespace gp {

struct PatternOptions {
  // Distortion limit: the error max(|s1-1|, |s2-1|) of the principal
  // stretches s1, s2 must be within p95_limit on 95 % of the area and within
  // max_limit everywhere (fractions: 0.02 = 2 %).
  double p95_limit = 0.02;
  double max_limit = 0.05;
  // Stop adding distortion cuts after this many. The adapted shared-body shirt
  // (3,829 vertices, rest grown x1.47 with the body's curvature in its
  // armpits) meets the default limit after 555 cuts (63 pieces, 23 s); the
  // garments as designed need at most 115 at this limit and 269 at 1 % / 3 %.
  int max_added_cuts = 1000;
  double tip_weight = 0.5;   // weight of the distance from the worst vertex when placing a dart's tip
  // Cone points: in a piece over the limit, every inner vertex whose angle
  // defect |2 pi - sum of its angles| reaches cone_angle (radians) is cut
  // through to the boundary before any other cut (0: never).
  double cone_angle = 0.0;
  // Scraps: an added cut bordering a piece of less than merge_area (m^2 of
  // 3D area) is removed again when the joined piece meets the limit (0: never).
  double merge_area = 0.01;
  // Seam tolerance: the two flat sides of a seam may differ by
  // max(seam_tolerance, seam_tolerance_relative * 3D length). Pieces on a
  // seam beyond it are flattened again with 4 times the boundary weight, up to
  // max_boundary_weight.
  double seam_tolerance = 0.002;           // metres
  double seam_tolerance_relative = 0.005;  // fraction
  double max_boundary_weight = 160.0;
  FlattenOptions flatten;
};

struct PatternSeam {
  std::string name;
  std::string kind;    // "user", "topology", "distortion" or "overlap"
  std::string reason;  // why it was added (empty for user seams)
  std::vector<int> vertex_ids;  // rest-shape vertex path
  bool closed = false;
};

struct PatternPiece {
  std::string name;             // "P1", "P2", ... in order of their smallest rest face id
  std::vector<int> face_ids;    // rest-shape faces, ascending
  Eigen::MatrixXd V;            // #Vp by 3, metres
  Eigen::MatrixXi F;            // #Fp by 3, local ids, same order as face_ids
  Eigen::VectorXi cut_vertex_ids;   // #Vp: vertex of the cut mesh
  Eigen::VectorXi rest_vertex_ids;  // #Vp: vertex of the rest shape
  std::vector<int> boundary;    // local ids of the boundary loop, counter-clockwise
  FlattenResult flat;           // UV in metres
  bool meets_limit = false;
};

struct Pattern {
  CutMesh cut;
  std::vector<PatternPiece> pieces;
  std::vector<PatternSeam> seams;  // user seams first, then added cuts in the order added
  std::vector<int> piece_of_face;  // #F: piece index per rest face
  std::vector<int> local_vertex;   // per cut vertex: its local id in its piece
  bool meets_limit = false;
  bool seams_within_tolerance = false;
  int rounds = 0;                  // flatten rounds
  int flattenings = 0;             // pieces flattened (a piece unchanged by a round is reused)
  std::vector<std::string> merged_cuts;  // added cuts removed again to merge scraps, in order
  // Why cutting stopped short of the limit: the cap max_added_cuts was
  // reached, or no cut rule placed a new cut in these failing pieces.
  bool cut_cap_reached = false;
  std::vector<std::string> stuck_pieces;
};

// V #V by 3 (metres), F #F by 3: the rest shape, edge-manifold and
// consistently oriented. `boundary_names` names rest vertices on named
// boundary loops (for the reasons of topological cuts; may be empty).
// Throws GeometryError for a piece of genus > 0 (seams must cut its handles).
Pattern make_pattern(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<SeamPath>& seams,
                     const PatternOptions& options, const std::map<int, std::string>& boundary_names = {});

// Whether a flattening meets the limit of `options`.
bool meets_limit(const FlattenResult& flat, const PatternOptions& options);

}  // namespace gp
