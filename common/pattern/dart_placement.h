#pragma once
// Darts, else a panel seam, for a piece over the limit (make_pattern.h
// phase 5). Dart tips sit at the modes (mean shift) of a kernel density of
// positive curvature: angle defects, or the log conformal factor u
// (L u = -K, u = 0 on the boundary; Sawhney and Crane 2017). Curves are in
// piece-local ids (surface_curve.h).
#include <optional>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "pattern/make_pattern.h"
#include "pattern/pattern.h"

namespace gp {

struct DartTip {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // on the piece, metres
  CurvePoint at;                                    // the same point, piece-local
  double curvature = 0.0;                           // kernel-weighted angle defect around it, radians
};

// Up to `count` strongest tips in piece c (left to right), each with
// min_dart_angle around it, tip_margin inside, two kernel radii apart.
std::vector<DartTip> dart_tips(const Pattern& pattern, size_t c, const PatternOptions& options, int count);

// The piece's LSCM chart (#Vp by 2), unique up to a similarity.
Eigen::MatrixXd conformal_chart(const PatternPiece& piece);

// A dart, mouth first, straight in `chart` from the nearest outline point at
// least min_dart_length away that crosses none of `avoid` (other darts) to
// the tip; nullopt when no wedge stays inside the piece.
std::optional<SurfaceCurve> dart_curve(const PatternPiece& piece, const Eigen::MatrixXd& chart, const DartTip& tip,
                                       const PatternOptions& options, const std::vector<Eigen::MatrixXd>& avoid = {});

// Whether two 2D polylines (#points by 2) cross or touch, shared ends aside.
bool polylines_cross(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

// A tip in piece c at its point nearest to x (a mirrored tip); nullopt within
// tip_margin of the outline or under `min_curvature` (radians), where a dart
// would be a slit.
std::optional<DartTip> dart_tip_near(const Pattern& pattern, size_t c, const Eigen::Vector3d& x,
                                     double min_curvature, const PatternOptions& options);

// Where piece p's panel seam runs through: the centroid of its conformal
// flattening's one-sided energy (metres, maybe off the piece); nullopt
// without such energy.
std::optional<Eigen::Vector3d> panel_centre(const PatternPiece& p, const PatternOptions& options);

// Where a centre seam runs through: the point of piece p on the plane
// x = plane_x nearest to the piece's point nearest to `from` (`from` itself
// where no edge crosses the plane).
Eigen::Vector3d centre_seam_point(const PatternPiece& p, double plane_x, const Eigen::Vector3d& from);

// A centre seam in piece p: the section of the piece by the plane x =
// plane_x (the body's middle), the open chain of it (outline to outline)
// passing nearest to `near`, leaving no part under min_piece_area; nullopt
// when no chain fits (none, or one ending on a dart's leg). A tailor's
// centre front or back follows the body's middle (common/export/README.md, "Centre seams").
std::optional<SurfaceCurve> centre_seam_curve(const Pattern& pattern, size_t c, double plane_x,
                                              const Eigen::Vector3d& near, const PatternOptions& options);

// A panel seam in piece c along the grain through the piece's point nearest
// to `centre`, leaving no part under min_piece_area (`where` describes it);
// nullopt when none fits.
std::optional<SurfaceCurve> panel_curve(const Pattern& pattern, size_t c, const Eigen::MatrixXd& chart,
                                        const Eigen::Vector3d& centre, const PatternOptions& options,
                                        std::string* where = nullptr);

}  // namespace gp
