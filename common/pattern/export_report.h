#pragma once
// What export-rest writes besides the sheets: the pieces as meshes and the
// report's figures (schema "export-rest-report/1", assembled by the tool).
#include <filesystem>
#include <ostream>

#include "io/mesh.h"
#include "pattern/make_pattern.h"
#include "pattern/layout.h"
#include "spec/json_file.h"

namespace gp {

// Seam mismatch tolerance: the two sides' flat lengths may differ by at most
// max(absolute, relative * the seam's length); export-rest sets it from
// PatternOptions (1 mm, 0).
struct SeamTolerance {
  double absolute = 0.001;   // metres
  double relative = 0.0;     // fraction of the 3D length
};

struct SeamToleranceFields {
  template <class Fields>
  void operator()(SeamTolerance& t, Fields& f) const {
    f.number("absolute_m", t.absolute, Range::non_negative());
    f.number("relative", t.relative, Range::non_negative());
  }
};

// Sewn edges that match: a seam's two flat sides sewn together should agree
// within 1 mm (a sewer eases in less without a mark); the cutter adds no
// deliberate ease (the flattening keeps both sides at the seam's 3D length),
// so the report names every seam beyond it as a mismatch, not as ease.
constexpr double kSeamMatch = 0.001;  // metres

struct SeamMeasure {
  double length_3d = 0.0;                   // metres, cut edges of the seam
  double left_2d = 0.0, right_2d = 0.0;     // flat lengths of its two sides, metres
  double mismatch = 0.0;                    // |left_2d - right_2d|, metres
  bool ok = true;
  std::vector<std::string> left_pieces, right_pieces;
};
std::vector<SeamMeasure> measure_seams(const Pattern& pattern, const Layout& layout, const SeamTolerance& tol);

// All pieces as one 2D mesh in sheet coordinates (z = 0, metres), one
// connected component per piece, with vertex fields "piece" (index) and
// "rest_vertex" (vertex of the rest shape).
Mesh flat_pieces_mesh(const Pattern& pattern, const Layout& layout);

// All pieces in 3D (rest positions, cut along the seams) with texture
// coordinates = sheet positions in metres, one OBJ group per piece.
void write_pieces_obj(std::ostream& out, const Pattern& pattern, const Layout& layout);

// Every seam as a polyline on the rest shape (metres), one OBJ object per
// seam named after it, in the pattern's seam order: where the cuts run.
void write_seams_obj(std::ostream& out, const Pattern& pattern);

// Where the limit's figure of a piece comes from: the worst `fraction` of
// the faces' area, by compression 1 - s2 or by ease s1 - 1 (the last face
// taken in part, as the limit takes it), and of it the densest spot: the
// area-weighted centroid of its faces within `radius` (metres) of its face
// with the most of it within that radius (rest shape, metres). The centroid
// of the whole region lay between its parts: the demo front's worst
// compression, at its two shoulder points, was reported at the centre front
// (issue 49).
Eigen::Vector3d worst_region_centroid(const std::vector<MaterialFace>& faces, double fraction, bool compression,
                                      double radius = 0.06);

// The report body: pieces, seams, added cuts, totals (without options and timing).
OrderedJson pattern_report(const Pattern& pattern, const Layout& layout, const PatternOptions& options,
                           const SeamTolerance& tol);

}  // namespace gp
