#pragma once
// The garment's left-right symmetry, so that the cutter cuts both sides of
// the body alike, as a tailor does. The rest shape is in the body's frame
// (+y up, +z front, +x the body's left) and is mirrored across the plane
// x = its area centroid's x (the axis piece_names.h names sides by). A
// scanned body and the cloth adapted to it are symmetric only roughly, so
// pieces are paired by how much of their mirrored area they share, not by
// an exact correspondence of vertices.
#include <vector>

#include <Eigen/Core>

#include "pattern/pattern.h"

namespace gp {

struct PieceMirror {
  double plane_x = 0.0;       // metres
  std::vector<int> partner;   // per piece: the piece of its mirror image (itself across the plane), or -1

  Eigen::Vector3d reflect(const Eigen::Vector3d& x) const { return {2.0 * plane_x - x.x(), x.y(), x.z()}; }
};

// Pairs the pattern's pieces: the partner of piece c is the piece d that
// holds the largest share of c's mirrored area (each pattern-mesh face
// counted at the piece of the face nearest to its mirrored centroid), where
// that share is at least `min_overlap` of c's area and c is likewise d's.
// A piece paired with itself straddles the plane (a whole front).
PieceMirror mirror_pieces(const Pattern& pattern, double min_overlap);

}  // namespace gp
