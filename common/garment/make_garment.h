#pragma once
// make-garment's algorithm: from a body pose and a garment spec to the initial
// garment (tools T1 boundary, T3 paint, T4 comfort offset, T5 pins).
#include <Eigen/Core>

#include "garment/body_clearance.h"
#include "garment/comfort_offset.h"
#include "garment/garment_file.h"
#include "garment/garment_spec.h"
#include "garment/region_cut.h"
#include "garment/remesh.h"
#include "io/mesh.h"
#include "spec/json_file.h"

namespace gp {

struct MakeGarmentResult {
  // The garment in the design pose, offset from the body (paint factors are
  // in `file`).
  Mesh mesh;
  // Everything but the fields about input and output files (mesh, body, spec
  // checksums), which the caller fills in.
  GarmentFile file;
  // The cut before remeshing (curves on the body, region area).
  RegionCut cut;
  double target_edge_length = 0.0;    // metres
  MeshQuality quality;                // of the final garment
  double boundary_curve_error = 0.0;  // max distance of remeshed boundary vertices to their offset curve, m
  ComfortOffsetStats offset_error;    // distance to the body minus offset, all vertices
  // Largest distance between a boundary vertex and the position its binding
  // rule gives (garment_file.h); non-zero only in concave places.
  double binding_max_deviation = 0.0;
  // The garment against the body: found clear, or pushed clear where a
  // triangle passed through it (body_clearance.h).
  BodyClearanceResult clearance;
  int boundary_loop_count = 0;
  int euler_characteristic = 0;
  int component_count = 0;
  // Seconds per phase.
  OrderedJson timing;
};

// V_body #V by 3 (metres) and F_body #F by 3: the body in the design pose.
// Throws SpecError for bad ids, far-away points and paint fields, and
// GeometryError (see cut_region and closed_edge_path) for loops and regions
// that cannot make a garment; every error names the spec field.
MakeGarmentResult make_garment(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                               const GarmentSpec& spec);

}  // namespace gp
