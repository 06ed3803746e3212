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

// The outward offset of a simple counter-clockwise polygon by `distance`
// (metres, > 0), simplified first by `simplify_tolerance`. Returns the offset
// outline(s), counter-clockwise. An outline that touches or crosses itself
// (dart sides that meet) is offset without its loops (each crossing cuts off
// the part with less area). Corners whose mitre would reach farther than
// twice the allowance from the outline are bevelled. Throws GeometryError naming `what` if the
// skeleton cannot be built.
std::vector<Polygon2> offset_polygon(const Polygon2& polygon, double distance, double simplify_tolerance,
                                     const std::string& what);

// Signed area (positive when counter-clockwise) and perimeter.
double polygon_area(const Polygon2& polygon);
double polygon_perimeter(const Polygon2& polygon);

}  // namespace gp
