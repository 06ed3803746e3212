#pragma once
// Names of the pattern's pieces after the part of the body they cover, in
// the body's frame (+y up, +z the body's front, +x its left; the rest shape's
// coordinates): "front", "back", "left front", "centre back", "left sleeve
// front", ... A piece is a sleeve when most of its area lies on a limb (the
// faces beyond an armhole); it faces front, back or sideways by its
// area-weighted normal; it is left, right or centre by its centroid against
// the garment's; two pieces that would share a name are told apart by
// "upper" and "lower", then by a number.
#include "pattern/pattern.h"

namespace gp {

void name_pieces(Pattern& pattern);

}  // namespace gp
