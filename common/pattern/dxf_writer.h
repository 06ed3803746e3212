#pragma once
// The pattern sheet as an AutoCAD R12 ASCII DXF (AC1009) in millimetres, the
// lowest common denominator of CAD and pattern software: closed POLYLINE
// entities for the sewing lines (layer SEW) and cutting lines (layer CUT),
// LINE entities for notches (NOTCH) and grain lines (GRAIN), TEXT for labels
// (LABEL). Same sheet coordinates as the SVG but with y up (DXF convention).
#include <ostream>
#include <string>

#include "pattern/pattern.h"
#include "pattern/layout.h"

namespace gp {

void write_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const std::string& title);

}  // namespace gp
