#pragma once
// Where a piece over the distortion limit gets its darts and, failing
// those, its panel seam (phase 5 of make_pattern.h).
//
// Dart tips sit at the modes of a kernel density of positive curvature:
// either the angle defects of the rest shape's vertices inside the piece
// (Gaussian curvature integrated over their areas), or the log conformal
// factor u of the piece's flattening that keeps its boundary's length
// (L u = -K inside, u = 0 on the boundary: the Yamabe equation with which
// boundary-first flattening places its cone points, Sawhney and Crane 2017;
// a dart is a cone whose wedge is cut away). Densities use 3D distances and
// modes are reached by mean shift, so tips move continuously with the shape.
// A dart runs straight, in the piece's conformal chart, from the tip to the
// outline vertex nearest to it.
//
// A panel seam runs straight along the grain (the body's vertical) through
// the centroid of the piece's distortion energy, from outline to outline.
// The energy is that of the conformal flattening keeping the boundary's
// length (one-sided: u^2 where u < 0, ease_weight u^2 where u > 0): a linear
// solve, so that the seam moves continuously with the shape.
//
// All curves are returned in the piece's local ids (surface_curve.h).
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

// Up to `count` tips in piece c (the strongest, listed from the body's left
// to its right), each with at least
// options.min_dart_angle of curvature around it, at least tip_margin inside
// the piece and two kernel radii from each other.
std::vector<DartTip> dart_tips(const Pattern& pattern, size_t c, const PatternOptions& options, int count);

// The piece's least-squares conformal chart (#Vp by 2): unique up to a
// similarity, which maps straight lines to straight lines, so that a curve
// drawn straight in it does not depend on how the chart was pinned.
Eigen::MatrixXd conformal_chart(const PatternPiece& piece);

// A dart from the nearest outline point (at least min_dart_length away)
// to the tip, straight in `chart`; the mouth is first. Where that wedge
// would cross one of the chart polylines `avoid` (the piece's other darts),
// from the next nearest outline segment that does not. nullopt when no
// straight wedge stays inside the piece.
std::optional<SurfaceCurve> dart_curve(const PatternPiece& piece, const Eigen::MatrixXd& chart, const DartTip& tip,
                                       const PatternOptions& options, const std::vector<Eigen::MatrixXd>& avoid = {});

// Whether two 2D polylines (#points by 2) cross or touch, shared end points
// aside.
bool polylines_cross(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

// A panel seam (see above) in piece c, leaving no part smaller than
// min_piece_area;
// `where` describes it. nullopt when none fits.
std::optional<SurfaceCurve> panel_curve(const Pattern& pattern, size_t c, const Eigen::MatrixXd& chart,
                                        const PatternOptions& options, std::string* where = nullptr);

}  // namespace gp
