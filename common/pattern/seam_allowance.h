#pragma once
// Seam allowance: the cutting line around a piece's sewing line, a true
// polygon offset with mitred corners (the offset of the straight skeleton,
// CGAL create_exterior_skeleton_and_offset_polygons_2), as a tailor draws it.
#include <vector>
#include <Eigen/Core>

namespace gp {

using Polygon2 = std::vector<Eigen::Vector2d>;

// Douglas-Peucker simplification of a closed polygon: drops vertices closer
// than `tolerance` (metres) to the simplified outline. Keeps at least 3.
Polygon2 simplify_polygon(const Polygon2& polygon, double tolerance);

// The outward offset by `distance` (metres, > 0) of a simple counter-clockwise
// polygon simplified by `simplify_tolerance`; outlines counter-clockwise. A
// self-touching outline (meeting dart sides) loses the smaller loop at each
// crossing; mitres longer than twice the allowance are bevelled. Throws
// GeometryError naming `what` when the skeleton cannot be built.
std::vector<Polygon2> offset_polygon(const Polygon2& polygon, double distance, double simplify_tolerance,
                                     const std::string& what);

// Signed area (positive when counter-clockwise) and perimeter.
double polygon_area(const Polygon2& polygon);
double polygon_perimeter(const Polygon2& polygon);

}  // namespace gp
