#pragma once
// The seam spec (schema "seam-spec/1"; format in README.md): the user's seams
// as clicked points on the rest shape, the garment as designed, or the body,
// joined by shortest edge paths (Dijkstra over the rest shape's edges).
//
// Design points name the rest vertex with the same id, so a spec written
// before the fit holds on the adapted rest shape. A body point within the
// snap tolerance of a bound boundary vertex's body point becomes that vertex;
// any other (x, normal n) the rest vertex closest to x + offset n.
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
// `V_design` (V_rest's connectivity), needed for design points, also takes
// the body points away from the boundary when given (the rest shape may have
// grown centimetres away from the body).
// One end of an open seam may lie inside the surface (a dart). Throws
// SpecError (bad id, point beyond the snap tolerance, missing body or design,
// < 2 points) or GeometryError (points on different components, a path that
// crosses itself or runs only along the boundary, an open seam reaching
// neither the boundary nor another seam), naming the seam.
std::vector<SeamPath> resolve_seams(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const SeamSpec& spec, const GarmentFile* garment,
                                    const DesignBody* body, const Eigen::MatrixXd* V_design = nullptr);

}  // namespace gp
