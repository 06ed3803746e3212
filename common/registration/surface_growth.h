#pragma once
// Where a registration stretches or shrinks the body's surface between two poses of one mesh, over
// neighbourhoods rather than edges: skin a garment rests on, and which grows by half between two
// captured poses, makes the garment's rest shape grow with it there (the adaptation follows the
// cloth that the body stretched), and cloth grown next to a loop that did not grow is a frill that
// no pattern flattens within its limit (BENCHMARKS.md, "The bulk's ease, and sleeves opened under
// the arm"). An edge's ratio (edge_ratios.h) finds a registration error; this finds the regions.
#include <Eigen/Core>

namespace gp {

// A neighbourhood: the reference's triangles whose centroids lie within the radius of a vertex.
struct SurfacePatch {
  double factor = 1.0;  // its area in the pose over its area in the reference
  int vertex = -1;      // the vertex it is centred on
  Eigen::Vector3d at = Eigen::Vector3d::Zero();  // that vertex in the reference [m]
};

struct SurfaceGrowth {
  double radius = 0.0;  // of the neighbourhoods [m]
  SurfacePatch largest, smallest;
  // Over the vertices, weighted by their share of the reference's area: the factor that 99 % of the
  // surface stays below, and the share of the surface whose neighbourhood grows by more than a
  // quarter.
  double p99 = 1.0;
  double share_above_1_25 = 0.0;
};

// The neighbourhoods of every vertex of V_ref (#V by 3, metres) against V_pose (#V by 3) over the
// triangles F (#F by 3) with the given radius [m] (> 0). Vertices whose neighbourhood has no
// reference area, or a pose area that is not finite (a NaN vertex), are skipped (factor 1 where
// none is left). Ties go to the lower vertex id. Throws UsageError on a bad radius or sizes.
SurfaceGrowth surface_growth(const Eigen::MatrixXd& V_ref, const Eigen::MatrixXd& V_pose, const Eigen::MatrixXi& F,
                             double radius);

}  // namespace gp
