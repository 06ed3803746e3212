#pragma once
// Where the pinned garment vertices go in a body frame.
//
// A pinned vertex (a garment loop bound to the body, garment_file.h) follows
// its binding: the bound body point plus the comfort offset along the body's
// vertex normal there. The continuous contact never moves a pinned vertex,
// so a target must itself stay clear of the body. The binding alone does not
// keep it clear where another body part rises beside the bound point: a
// shoulder lifted towards the neck comes within millimetres of the neckline's
// targets, and the body can then pass through the cloth between the pins and
// their free neighbours (figures in README.md).
//
// keep_off_body() moves a target nearer than a clearance (a part of the
// comfort offset) out to it, from the contact surface along the direction
// away from its closest point, as the collider does with free cloth vertices
// (body_collider.h), and in a pinch to the middle of the gap. A target that
// keeps the clearance is not touched, so that where no body part comes near,
// the pins follow their binding exactly as designed. In a crease (two body
// parts at an angle) one push can bring the target within the clearance of
// the other side, so it repeats; the pushes are alternating projections onto
// the two clearance half-spaces, which meet, and converge to a point outside
// both.
#include <vector>

#include <Eigen/Core>

#include "collision/body_collider.h"

namespace gp::adapt {

struct PinClearanceStats {
  long pushed = 0;              // targets moved (summed over calls)
  double largest_push = 0.0;    // m, the longest move of a target
  double closest_before = 0.0;  // m, smallest signed distance of a target before
                                // its move (0 until one moved)
};

// Moves the rows of `targets` (#P by 3, metres) nearer to the collider's
// current body than `clearance` [m] (or half the gap in front of their
// closest point, in a pinch) out to it, in up to `max_pushes` pushes each.
// `hints` (#P, culled face ids or -1) warm-start the closest-point queries
// and are updated. The other targets are left bit for bit as they are.
// Throws UsageError for a size mismatch or a negative clearance.
void keep_off_body(Eigen::MatrixXd& targets, const collision::BodyCollider& collider, double clearance,
                   std::vector<int>& hints, PinClearanceStats& stats, int max_pushes = 8);

}  // namespace gp::adapt
