#pragma once
// The marker as a drawing and a report: SVG and PDF (cairo) at true scale
// for pieces in metres (1 unit = 10 mm drawn for unitless benchmark pieces),
// the fabric's width across the page and its length along it; and the
// report's placements ("make-marker-report/1").
#include <ostream>
#include <string>

#include "marker/marker_pieces.h"
#include "marker/nest_marker.h"
#include "spec/json_file.h"

namespace gp {

// Millimetres drawn per unit of the pieces: 1000 for metres, else 10.
double marker_mm_per_unit(const MarkerPieces& pieces);

void write_marker_svg(std::ostream& out, const MarkerPieces& pieces, const MarkerResult& marker, const std::string& title);

// One page as long as the marker (scaled down to PDF's largest page, 5.08 m,
// where longer: the page then says its scale). Throws OutputError.
void write_marker_pdf(std::ostream& out, const MarkerPieces& pieces, const MarkerResult& marker, const std::string& title);

// Placements and figures; `check_overlap` runs polygons_overlap over every pair.
OrderedJson marker_report(const MarkerPieces& pieces, const MarkerResult& marker, const NestOptions& options);

}  // namespace gp
