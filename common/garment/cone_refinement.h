#pragma once
// Local refinement where a garment's curvature is too concentrated for its
// resolution. A vertex's angle defect is the Gaussian curvature integrated
// over its area (Meyer, Desbrun, Schroeder and Barr 2003, "Discrete
// differential-geometry operators for triangulated 2-manifolds", eq. 9), so
// on a smooth saddle (the rounded armpit of an A-pose, a crotch) it shrinks
// with the square of the edge length: halving the edges there divides the
// largest defects by about four, where a coarser uniform mesh leaves cone
// points that no flat pattern piece reproduces.
#include <Eigen/Core>

#include "garment/remesh.h"

namespace gp {

struct ConeRefinementOptions {
  // Degrees: inner vertices whose |angle defect| reaches this are refined
  // around. Below kConeDefectDeg (18), so that the refined mesh keeps a margin.
  double cone_angle_deg = 14.0;
  int rings = 2;                 // faces within this many vertex rings of a cone are remeshed
  double length_factor = 0.6;    // each round's target edge length: this times the previous one's
  int max_rounds = 3;            // rounds; each remeshes around the cones left by the one before
  int remesh_iterations = 4;     // split/collapse/flip/relax rounds of each local remesh
};

struct ConeRefinementResult {
  int rounds = 0;             // rounds that remeshed something
  int cones_before = 0;       // inner vertices at or above cone_angle_deg before
  int cones_after = 0;        // ... after
  int added_vertices = 0;     // vertex count after minus before
  double finest_edge_length = 0.0;  // metres: the finest target edge length used (0 if none)
};

// V #V by 3 (metres), F #F by 3: an open garment patch whose inner vertices
// lie on the target surface; replaced by the refined mesh. Around inner
// vertices with large |angle defect| the faces are remeshed
// (remesh_selected_faces: the border of the patch and of each selection is
// kept) at a shorter edge length, starting from `target_edge_length`, and
// the new and moved vertices are put on the surface by `project`. Boundary
// vertices keep their positions. Throws GeometryError as remesh_selected_faces.
ConeRefinementResult refine_cones(Eigen::MatrixXd& V, Eigen::MatrixXi& F, double target_edge_length,
                                  const PointProjection& project, const ConeRefinementOptions& options = {});

}  // namespace gp
