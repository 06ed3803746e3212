#pragma once
// Pieces named after the body part they cover, in the body's frame (+y up,
// +z front, +x the body's left): "front", "left sleeve front", ... A sleeve
// has most of its area beyond an armhole; a piece faces front, back or
// sideways by its area-weighted normal, and is left or right by where most
// of its area lies, unless a quarter of it or more lies on each side of the
// body's axis. Equal names are told apart by centre/side, front/back or
// upper/lower (the axis on which they lie farther apart, alike for mirror
// images), then a number.
#include <string>

#include "pattern/pattern.h"
#include "pattern/piece_mirror.h"

namespace gp {

// With `mirror` (piece_mirror.h; by default no pairs), a mirrored pair is
// named from the average of the two, so that each name is the other's mirror
// image.
void name_pieces(Pattern& pattern, const PieceMirror& mirror = {});

// The name of a piece's mirror image: its words "left" and "right" swapped
// (the name itself when it has neither).
std::string mirror_name(const std::string& name);

// Whether the name has the word "left" (a piece on the body's left).
bool is_left(const std::string& name);

}  // namespace gp
