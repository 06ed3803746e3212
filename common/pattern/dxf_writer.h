#pragma once
// The pattern sheet as an ASCII DXF in millimetres (the SVG's sheet
// coordinates with y up, the DXF convention), in one of three profiles; the
// layers, entities and text of each are in common/pattern/README.md ("DXF
// profiles"):
// - astm (default): the garment industry's interchange format, ASTM D6673-10
//   (the successor of AAMA-DXF), DXF R12 entities, one BLOCK per piece
//   inserted once, numbered layers, piece and style text in 7-bit ASCII, no
//   other blocks (Gerber AccuMark refuses extra ones);
// - aama: the same with notches as AAMA-DXF's slits, for older importers;
// - plain: the drawing before these profiles, for general CAD and cutters.
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
