#pragma once
// The pattern sheet as SVG at true scale: width and height in millimetres
// and a viewBox in millimetres, so that printing at 100 % gives a 1:1
// pattern. Per piece (a <g> with the piece's name as id): the cutting line
// (seam allowance), the sewing line, notches, the grain line with arrows, the
// piece's label and the names of its seams.
#include <ostream>
#include <string>

#include "core/text_format.h"  // format_fixed: deterministic text for coordinates
#include "pattern/pattern.h"
#include "pattern/layout.h"

namespace gp {

struct SvgOptions {
  std::string title = "pattern";  // garment name, printed in every label
};

void write_svg(std::ostream& out, const Pattern& pattern, const Layout& layout, const SvgOptions& options);

}  // namespace gp
