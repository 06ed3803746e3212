#pragma once
// The pattern sheet as an ASCII DXF in millimetres, in one of three profiles:
//
// - astm (default): the garment industry's interchange format, ASTM D6673-10
//   ("Standard Practice for Sewn Products Pattern Data Interchange - Data
//   Exchange Format"), the successor of the AAMA-DXF of 1997. DXF R12
//   (AC1009) entities only; every piece is one BLOCK, inserted once in the
//   ENTITIES section at its place on the sheet; layers are numbers:
//     1  the cutting line (closed POLYLINE) and the piece text (TEXT),
//     2  turn points (POINT at every vertex of the cutting line where it
//        turns by more than kTurnPointDegrees),
//     3  curve points (POINT at every other vertex of the cutting line),
//     4  notches: POINT on the cutting line, group 50 the notch's angle in
//        degrees (the direction it cuts into the piece, counter-clockwise
//        from +x),
//     6  fold lines (none: every piece is cut whole, cut_instructions.h),
//     7  the grain line (LINE, arrow towards +y of the sheet),
//     8  internal lines: the darts as drawn (their two legs, LINE),
//     13 drill holes: a POINT a centimetre short of each dart's tip,
//     14 the sewing line (closed POLYLINE).
//   Piece text, one TEXT per line on layer 1 in 7-bit ASCII: "Piece Name:",
//   "Quantity:", "Size:", "Category:", "Fabric:", "Annotation:". Style text
//   once, in ENTITIES outside any block: "Style Name:", "Creation Date:",
//   "Author:", "Sample Size:", "Units: METRIC". No other blocks (Gerber
//   AccuMark refuses extra ones).
// - aama: the same, but notches as the AAMA-DXF of 1997 draws them, a slit:
//   a LINE on layer 4 from the cutting line into the piece, with no angle
//   code, for importers that predate ASTM D6673's notch points.
// - plain: the drawing as before these profiles, for general CAD and laser
//   cutters: closed POLYLINE entities for the sewing lines (layer SEW) and
//   cutting lines (layer CUT), LINE entities for notches (NOTCH), grain lines
//   (GRAIN) and darts (DART), TEXT for labels (LABEL), all in ENTITIES.
//
// Same sheet coordinates as the SVG but with y up (DXF convention).
#include <ostream>
#include <string>
#include <vector>

#include "pattern/cut_instructions.h"
#include "pattern/layout.h"
#include "pattern/pattern.h"

namespace gp {

enum class DxfProfile { astm, aama, plain };

// "astm", "aama", "plain"; throws UsageError for another name.
DxfProfile dxf_profile_from_name(const std::string& name);
std::string dxf_profile_name(DxfProfile profile);

struct DxfOptions {
  DxfProfile profile = DxfProfile::astm;
  std::string style = "pattern";  // Style Name: the garment's name
  std::string size;               // Size / Sample Size: the customer (empty: the style name)
  std::string author = "export-rest";
  std::string date;               // Creation Date, YYYY-MM-DD (empty: "unknown")
};

// A vertex of the cutting line whose outline turns by more than this is a
// turn point (layer 2), any other a curve point (layer 3): a cutting room's
// CAD keeps turn points as corners and fits curves through curve points.
constexpr double kTurnPointDegrees = 25.0;

// Writes the pattern in the options' profile; `cut` holds one instruction
// per piece (cut_instructions.h; unused by the plain profile).
void write_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const DxfOptions& options,
               const std::vector<CutInstruction>& cut);

// The plain profile (the drawing before the profiles existed).
void write_dxf(std::ostream& out, const Pattern& pattern, const Layout& layout, const std::string& title);

// The default Creation Date (YYYY-MM-DD, UTC): that of $SOURCE_DATE_EPOCH
// where set (the reproducible-builds convention), else the modification
// date of `input` (the rest shape the pattern is cut from), so that the same
// input file gives the same DXF; empty where neither can be read.
std::string default_creation_date(const std::string& input);

// `s` in 7-bit ASCII, as the ASTM text wants it: every byte above 0x7e or
// below 0x20 replaced by '?', a UTF-8 sequence by one '?'.
std::string ascii_text(const std::string& s);

}  // namespace gp
