#pragma once
// The fallback for a key pose in which the body holds the cloth (a hand
// resting on the thigh over a skirt): the least opening of that pose towards
// another registered pose that gives the cloth room where it was held. The
// pipeline then fits the garment to the opened pose (interp-poses, make fit's
// OPEN_POSE), as a tailor asks the customer to stand a little more open.
#include <vector>

#include <Eigen/Core>

#include "adapt/key_pose.h"
#include "collision/contact_surface.h"
#include "interp/pose_interpolator.h"

namespace gp::adapt {

struct OpeningOptions {
  // Candidate openings, least first: the pose moved 1/n of the way towards
  // another pose, for each n here.
  std::vector<int> steps{40, 20, 10, 5};
  // An opening frees the cloth when the room in front of every held patch
  // (HeldCloth::gap, measured again in the opened pose) is at least this many
  // comfort offsets: the offset on both sides and room to slide [1].
  double clearance = 3.0;
  collision::ContactSurfaceOptions contact_surface;  // the hulls, as the run's
};

struct Opening {
  bool found = false;
  int pose = -1;                  // the held pose (pose-set index)
  int toward = -1;                // the pose it is opened towards
  int steps = 0;                  // opened 1/steps of the way
  double smallest_gap = 0.0;      // m: the least room in front of a held patch once opened (counted up to 2 clearances)
  double largest_displacement = 0.0;  // m: the body vertex that moves most
  // Per candidate pose (pose-set order, the held pose itself 0), the least
  // room at the largest opening tried [m], to say why none was found.
  std::vector<double> gap_at_largest;
};

// The least opening of pose `pose` (a pose-set index of `interpolator`) that
// leaves at least options.clearance * offset [m] in front of every patch of
// `held` (as recorded at that pose: their contact-surface faces and
// barycentric coordinates; the room is BodyCollider::facing_distance); among
// the poses that reach it at the same opening, the one leaving the most room,
// then the one moving the body least. The hulls are taken in `pose`.
// Throws UsageError for a pose out of range or no patch.
Opening choose_opening(PoseInterpolator& interpolator, int pose, const std::vector<HeldCloth>& held, double offset,
                       const OpeningOptions& options = {});

}  // namespace gp::adapt
