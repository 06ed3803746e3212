#pragma once
// Names of the pattern's pieces after the part of the body they cover, in
// the body's frame (+y up, +z the body's front, +x its left; the rest shape's
// coordinates): "front", "back", "left front", "centre back", "left sleeve
// front", ... A piece is a sleeve when most of its area lies on a limb (the
// faces beyond an armhole); it faces front, back or sideways by its
// area-weighted normal; it is left, right or centre by its centroid against
// the garment's; two pieces that would share a name are told apart by
// "front" and "back" or "upper" and "lower" (along the axis on which they
// lie farther apart, chosen alike for a piece and its mirror image), then by
// a number. A sleeve's parts are its front and back by their centroids.
#include <string>

#include "pattern/pattern.h"

namespace gp {

void name_pieces(Pattern& pattern);

// The name of a piece's mirror image: its words "left" and "right" swapped
// (the name itself when it has neither).
std::string mirror_name(const std::string& name);

// Whether the name has the word "left" (a piece on the body's left).
bool is_left(const std::string& name);

}  // namespace gp
