#pragma once
// A sewing pattern as the cutter builds it: the rest shape refined along
// every cut (cuts run through the rest shape's triangles along smooth curves,
// so the pattern's mesh is the rest shape with the cut curves inserted), the
// cuts (user seams, topology cuts, darts, panel seams), the pieces with their
// flattenings. assemble_pieces() rebuilds the pieces from the mesh and cuts.
#include <map>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "garment/surface_point.h"
#include "pattern/flatten.h"
#include "pattern/mesh_cut.h"
#include "pattern/surface_curve.h"

namespace gp {

// The rest shape with the cut curves inserted (curve_insertion.h): its
// vertices [0, rest_vertex_count) are the rest shape's own, the others lie on
// rest edges or inside rest faces.
struct PatternMesh {
  Eigen::MatrixXd rest_V;               // the rest shape, #V by 3
  Eigen::MatrixXi rest_F;               // #F by 3
  Eigen::MatrixXd V;                    // #Vm by 3, metres
  Eigen::MatrixXi F;                    // #Fm by 3
  std::vector<int> rest_face;           // #Fm: the rest face each face lies in
  std::vector<SurfacePoint> rest_point; // #Vm: each vertex as a point of the rest shape
  int rest_vertex_count = 0;
};

// The rest shape itself as a PatternMesh (nothing inserted yet).
PatternMesh pattern_mesh_of_rest(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

struct PatternSeam {
  std::string name;
  // "user" (the seam spec), "armhole" (around a sleeve where it meets the
  // body), "topology" (a piece had to be opened into a disk), "dart" (from
  // the piece's edge to a tip inside it) or "panel" (a seam added where darts
  // did not suffice).
  std::string kind;
  std::string reason;           // why it was added (empty for user seams)
  std::vector<int> vertex_ids;  // path in the pattern mesh (a dart: mouth first, tip last)
  bool closed = false;
  bool smoothed = false;        // runs through triangles along a smooth curve (else along rest edges)
  std::string mirror;           // an added cut: the one cut as its mirror image (make_pattern.h), else empty
};

struct PatternPiece {
  std::string name;             // body region: "front", "back", "left sleeve front", ... (unique; piece_names.h)
  std::vector<int> face_ids;    // pattern-mesh faces, ascending
  Eigen::MatrixXd V;            // #Vp by 3, metres
  Eigen::MatrixXi F;            // #Fp by 3, local ids, same order as face_ids
  Eigen::VectorXi cut_vertex_ids;   // #Vp: vertex of the cut mesh
  Eigen::VectorXi mesh_vertex_ids;  // #Vp: vertex of the pattern mesh (the material point)
  std::vector<int> boundary;    // local ids of the boundary loop, counter-clockwise
  std::vector<int> dart_seams;  // indices of the darts in this piece
  FlattenResult flat;           // UV in metres; flat.stats over the pattern mesh's triangles
  // Distortion of the rest faces the piece covers (material_distortion):
  // what the sewn garment's cloth sees, and what the limit is judged on.
  DistortionStats stats;
  bool meets_limit = false;
};

// A limb found by its armhole (make_pattern.h, cut_armholes).
struct Limb {
  std::string loop;   // the boundary loop that ends it (a sleeve's hem)
  bool left = false;  // on the body's left (+x)
};

struct Pattern {
  PatternMesh mesh;
  std::vector<Limb> limbs;
  std::vector<int> limb_of_rest_face;  // per rest face: its limb, or -1 (the body); empty without limbs
  CutMesh cut;                     // the pattern mesh cut along every seam
  std::vector<PatternPiece> pieces;
  std::vector<PatternSeam> seams;  // user seams first, then added cuts in the order added
  std::vector<int> piece_of_face;  // #Fm: piece index per pattern-mesh face
  std::vector<int> local_vertex;   // per cut vertex: its local id in its piece
  bool meets_limit = false;
  bool seams_within_tolerance = false;
  int rounds = 0;                  // flatten rounds
  int flattenings = 0;             // pieces flattened (a piece unchanged by a round is reused)
  std::vector<std::string> merged_cuts;  // added cuts removed again to merge small pieces
  std::vector<std::string> notes;        // decisions worth reporting (a dart not placed, a split refused)
  std::map<std::string, double> seconds; // wall time per phase (for timing.json only)
};

// Cuts the pattern mesh along every seam and extracts the pieces (faces,
// vertices, local ids, darts), in order of their smallest face, and names
// them by body region (piece_names.h); flattenings are left empty.
void assemble_pieces(Pattern& pattern);

// Inserts the curves (on the pattern mesh, surface_curve.h) into the
// pattern mesh, appends `seams` (their vertex_ids are set from the curves),
// carries the earlier seams' paths over and reassembles the pieces.
void insert_cuts(Pattern& pattern, std::vector<PatternSeam> seams, const std::vector<SurfaceCurve>& curves);

// Distortion of piece `c` on the rest faces it covers: a rest face that cuts
// split is cloth of several triangles of the pattern mesh; its metric is the
// area-weighted mean of their metrics A^T A (A the affine map of a part from
// the face's plane to the flat piece), its principal stretches that metric's,
// its weight the area of its parts in the piece. Unlike the figures of the
// pattern mesh's own triangles, these change continuously when a cut moves
// past a vertex of the rest shape.
DistortionStats material_distortion(const Pattern& pattern, size_t c);

// The per-rest-face figures behind material_distortion.
struct MaterialFace {
  int rest_face = -1;
  double area = 0.0;                                  // area of its parts in the piece, m^2
  Eigen::Vector2d stretch = Eigen::Vector2d::Ones();  // principal stretches s1 >= s2 of its mean metric
  double flat_area = 0.0;                             // signed flat area of its parts, m^2
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(); // of its parts, metres
};
std::vector<MaterialFace> material_faces(const Pattern& pattern, size_t c);

// Whether the piece is one disk (one boundary loop, Euler characteristic 1).
bool is_disk(const PatternPiece& piece);

}  // namespace gp
