#pragma once
// Small text formatting shared by the writers of SVG, DXF, HTML and reports.
#include <string>

namespace gp {

// x with `digits` decimals ("%.*f"), without the sign of a negative zero.
std::string format_fixed(double x, int digits = 3);

// `s` with &, <, > and " replaced by their XML/HTML entities.
std::string escape_xml(const std::string& s);

}  // namespace gp
