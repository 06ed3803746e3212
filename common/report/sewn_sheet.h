#pragma once
// The garment sewn from the pattern against the drape it was compared with
// (export-rest's sewn-fit check, /sewn_fit/key_poses/*/distance_to_verified):
// at every key pose the check measured, the reference drape (the fit's
// verified drape, or the rest shape's own drape that export-rest simulated)
// above the sewn drape, front, side and back, both coloured by the distance
// between corresponding points, so that a piece that hangs away from the
// designed garment shows where.
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pose/pose_set.h"
#include "render/colour_scale.h"
#include "render/text.h"
#include "report/fit_run.h"
#include "report/picture_sheet.h"

namespace gp::report {

// Distance from the sewn drape to its reference, 0 to 30 mm (the values in
// millimetres): white at 0, marked at the sewn-fit goal's 5 mm (mean) and
// 15 mm (p95) bounds, dark red from 30 mm.
render::ColourScale drape_distance_scale();

// Per-face value of a per-vertex field (#V): the mean of its corners (F #F by 3).
Eigen::VectorXd face_mean_of_vertices(const Eigen::VectorXd& vertex_values, const Eigen::MatrixXi& F);

// Writes renders/sewn_<kk>_<pose>.png into `folder` for every key pose of
// run.keys whose sewn drape export-rest compared with a reference, and
// returns one path per key pose of run.keys (relative to `folder`; empty
// where the pattern's report measured none). F: the garment's faces.
// Throws InputError for a missing mesh, GeometryError for one of other
// triangles or without the distance field.
std::vector<std::string> write_sewn_sheets(const FitRun& run, const PoseSet& poses, const Eigen::MatrixXi& F,
                                           const render::Font& font, const SheetOptions& sheet,
                                           const std::filesystem::path& folder);

}  // namespace gp::report
