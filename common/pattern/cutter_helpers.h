#pragma once
// What the cutter's phases share (make_pattern.h): number formats for the
// reasons they record, curves and keys of pieces, and the seam check.
// Internal to pattern/: the phases' own files and make_pattern.cpp.
#include <set>
#include <string>
#include <vector>

#include "pattern/pattern.h"
#include "pattern/pattern_options.h"
#include "pattern/surface_curve.h"

namespace gp {

// x as a percentage ("12.34 %") and as metres ("0.123 m"), for reasons.
std::string percent(double x);
std::string metres(double x);

// The curve of a piece (local ids) on the pattern mesh.
SurfaceCurve piece_to_mesh(const PatternPiece& p, const SurfaceCurve& c);

// Cache key of a piece: its triangles as sorted triples of pattern-mesh
// vertex ids (unchanged by insertions elsewhere), then its slits.
std::vector<int> piece_key(const Pattern& pattern, size_t c);

// Whether the two flat sides of every seam have the same length within the
// tolerance; fills the pieces on seams that do not.
bool seam_sides_match(const Pattern& pattern, const PatternOptions& options, double margin, std::set<int>* mismatched);

// Per vertex of piece p (local ids): on its boundary.
std::vector<char> boundary_flags(const PatternPiece& p);

// The rest faces piece c covers, sorted.
std::vector<int> piece_rest_faces(const Pattern& pattern, size_t c);

// The limb (sleeve) piece c belongs to: the one holding more than half of
// its area (cut_armholes), or -1 (the body's, or no limbs found).
int piece_limb(const Pattern& pattern, size_t c);

}  // namespace gp
