#pragma once
// Where the pinned garment vertices go in a body frame. A pinned vertex
// follows its binding (garment_file.h), which the contact never corrects;
// where another body part rises beside the bound point (a shoulder lifted
// towards the neckline) the binding alone goes into the body (README.md).
// keep_off_body() pushes such a target out to a clearance away from its
// closest body point, or to the middle of a pinch, repeating in a crease
// (alternating projections onto the two half-spaces). Other targets are left
// bit for bit.
#include <vector>

#include <Eigen/Core>

#include "collision/body_collider.h"

namespace gp::adapt {

struct PinClearanceStats {
  long pushed = 0;              // targets moved (summed over calls)
  double largest_push = 0.0;    // m, the longest move of a target
  double closest_before = 0.0;  // m, smallest signed distance before a move (0: none)
};

// Moves the rows of `targets` (#P by 3, m) nearer to the collider's body
// than `clearance` (m; in a pinch, half the gap) out to it, in up to
// `max_pushes` pushes; `hints` (#P culled face ids or -1) warm-start the
// queries. Throws UsageError for a size mismatch or negative clearance.
void keep_off_body(Eigen::MatrixXd& targets, const collision::BodyCollider& collider, double clearance,
                   std::vector<int>& hints, PinClearanceStats& stats, int max_pushes = 8);

}  // namespace gp::adapt
