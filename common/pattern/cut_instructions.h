#pragma once
// What to cut from each piece, as the cutting room reads it off the label:
// how many, whether it is one of a mirrored pair, whether it is cut on the
// fold, and from which fabric layer. The writers put it on every piece
// (SVG and PDF labels, DXF piece text) and the marker places the pieces by it.
#include <string>
#include <vector>

#include "marker/marker_pieces.h"
#include "pattern/pattern.h"

namespace gp {
struct Layout;
}

namespace gp {

struct CutInstruction {
  // Pieces cut from this outline. The cutter lays out a mirrored pair as two
  // pieces (each side of the body is cut from its own flattening, as the
  // sides of a scanned body differ a little), so every outline is cut once.
  int quantity = 1;
  // The piece this one is the mirror image of ("left X" and "right X",
  // piece_names.h), or empty. Cut face up, both are then a mirrored pair.
  std::string mirror_of;
  // Cut on the fold: never, as a piece across the body's middle is cut whole
  // or split by a centre seam (make_pattern.h), never halved to a fold.
  bool on_fold = false;
  // The fabric layer: the garment is one fabric (no lining or interfacing).
  std::string fabric = "self";

  // One line for a label: "cut 1 self, face up, pair of right sleeve front".
  std::string text() const;
};

// One instruction per piece of the pattern, in piece order.
std::vector<CutInstruction> cut_instructions(const Pattern& pattern);

// The pieces as make-marker nests them (marker_pieces.h, "marker-pieces/1",
// metres): each piece's cutting line (its sewing line without allowance)
// turned so that its grain line (+y of the sheet) runs along the fabric's
// length (+x), the quantity of its instruction, orientations 0 and 180.
MarkerPieces marker_pieces(const Pattern& pattern, const Layout& layout, const std::vector<CutInstruction>& cut);

}  // namespace gp
