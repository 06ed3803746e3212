#pragma once
// The seam spec (schema "seam-spec/1"): tool T6 of the paper, the user's seams
// as clicked points instead of mouse clicks.
//
//   {
//     "schema": "seam-spec/1",
//     "snap_tolerance": 0.03,        // metres: how far a 3D point may be from the surface
//     "seams": [
//       { "name": "side_left",       // unique, names the seam in reports and on the pattern
//         "on": "rest",              // "rest": points on the rest shape (default);
//                                    // "design": on the garment as designed (the mesh
//                                    //   beside the garment file; same vertices);
//                                    // "body": points on the body in the design pose
//         "points": [ 12, [0.1, 1.2, 0.05], 845 ],  // vertex ids or 3D points (metres)
//         "closed": false }          // true: the last point joins the first
//     ]
//   }
//
// Consecutive points are joined by shortest edge paths on the rest shape
// (Dijkstra over its edges). Seams are cut along these mesh edge paths as they
// are (no smoothing): on a remeshed garment with even triangles the path
// follows the clicked line within about one edge length.
//
// Design points are found on the garment as designed and name the rest-shape
// vertex with the same id: a seam spec written before the fit stays valid on
// the adapted rest shape, which may have grown centimetres away from the design.
//
// Body points are mapped to the rest shape through the garment's binding: a
// body point within the snap tolerance of a bound boundary vertex's body
// point becomes that garment vertex (exact, as the garment file binds it);
// any other body point x (with body normal n) becomes the rest-shape vertex
// closest to x + offset n, which must lie within the snap tolerance.
#include <filesystem>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "garment/design_body.h"
#include "garment/garment_file.h"
#include "io/mesh.h"
#include "spec/clicked_point.h"
#include "spec/json_file.h"

namespace gp {

using SeamSpecPoint = ClickedPoint;  // a rest-shape or body vertex id, or a 3D point

// The surface a seam's points were clicked on.
enum class SeamSurface { rest, design, body };

struct SeamSpecSeam {
  std::string name;
  SeamSurface on = SeamSurface::rest;
  bool closed = false;
  std::vector<SeamSpecPoint> points;
  std::string where;
};

struct SeamSpec {
  std::string file;
  double snap_tolerance = 0.03;  // metres
  std::vector<SeamSpecSeam> seams;
};

// Strict reader: SpecError naming the file and JSON pointer of any wrong,
// unknown, missing or out-of-range field.
SeamSpec read_seam_spec(const std::filesystem::path& path);
SeamSpec parse_seam_spec(const Json& j, const std::string& file);
OrderedJson to_json(const SeamSpec& spec);

// Seams "on": "body" need the body in the design pose: DesignBody and
// load_design_body (garment/design_body.h).

// A seam resolved to an edge path on the rest shape.
struct SeamPath {
  std::string name;
  std::vector<int> vertex_ids;  // rest-shape vertex ids along the path (closed: first not repeated)
  bool closed = false;
  std::string where;            // spec location, for messages
  std::vector<int> click_ids;   // the rest vertices the seam's points snapped to, in order
};

// Resolves every seam of `spec` on the rest shape (V_rest #V by 3, F #F by 3).
// `garment` and `body` are needed only for body points (nullptr otherwise).
// `V_design` (same connectivity as V_rest) is the garment as designed, needed
// for design points; body points away from the bound boundary are snapped to
// it too when it is given, rather than to the rest shape, which adaptation may
// have grown centimetres away from the body.
// Throws SpecError (bad vertex id, point beyond the snap tolerance, body or
// design points without a body or design shape, fewer than two points) and GeometryError (points on
// different components: the path would leave the mesh; a path crossing
// itself; a seam running only along the boundary; an open seam whose two ends
// reach neither the boundary nor another seam). Every message names the seam.
// One end of an open seam may lie inside the surface: the seam is then a dart.
std::vector<SeamPath> resolve_seams(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const SeamSpec& spec, const GarmentFile* garment,
                                    const DesignBody* body, const Eigen::MatrixXd* V_design = nullptr);

}  // namespace gp
