#pragma once
// Tool T2, extension (paper section on design tools): a boundary loop is
// duplicated, moved along its axis (from the loop's centroid and vector area)
// to a target, scaled, connected to the garment by a band tessellated at the
// garment's edge length, and the band is remeshed without moving the other
// boundaries. Skirts from a waist loop, wide sleeves from a cuff.
//
// Extension spec (schema "extend-spec/1"):
//   { "schema": "extend-spec/1",
//     "loop": "waist",
//     "target": { "point": [x, y, z] }  or  { "distance": 0.45 },   // metres
//     "scale": 1.3  or  "girth": 1.6,   // factor (> 0) or new loop length in metres; default scale 1
//     "grain": 45,                      // optional: the band's warp, degrees from the body's vertical
//                                       //   within [-90, 90] (garment_spec.h, "grain"); default 0
//     "remesh": { "iterations": 6 } }   // optional
#include <filesystem>
#include <string>
#include <Eigen/Core>

#include "garment/body_clearance.h"
#include "garment/design_body.h"
#include "garment/garment_file.h"
#include "io/mesh.h"
#include "spec/json_file.h"

namespace gp {

struct ExtendSpec {
  std::string file;
  std::string loop;
  bool has_point = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // target point (projected on the axis)
  double distance = 0.0;                            // or distance along the axis, metres
  double scale = 1.0;                               // scale of the new loop about its centroid
  double girth = 0.0;                               // or its length in metres (> 0 wins over scale)
  int remesh_iterations = 6;
  double grain_angle = 0.0;  // radians: the band's grain (the spec gives degrees)
};
ExtendSpec parse_extend_spec(const Json& j, const std::string& file);
ExtendSpec read_extend_spec(const std::filesystem::path& path);
OrderedJson to_json(const ExtendSpec& spec);

struct ExtendResult {
  Mesh mesh;          // garment with the band (paint factors are in `file`)
  GarmentFile file;   // updated (mesh checksum left to the caller)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the old loop
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();      // unit, pointing away from the garment
  double distance = 0.0;     // moved along the axis, metres
  double scale = 1.0;        // applied to the loop
  double old_girth = 0.0;    // metres
  double new_girth = 0.0;    // length of the new loop, metres
  int band_faces = 0;
  int band_flipped_faces = 0;  // band triangles whose normal faces the axis
  bool unpinned = false;       // the loop was pinned; the new loop is not on the body
  // With a body: the extended garment pushed clear of it (body_clearance.h),
  // at the garment's comfort offset where there is room.
  bool body_checked = false;
  BodyClearanceResult clearance;
};

// `garment` is the garment mesh, `file` its garment file; `body`, when given,
// the body in the design pose, which the extended garment is then cleared of
// (vertices of loops bound to the body stay where they are). Throws SpecError
// naming the spec field for an unknown loop, a target behind the loop or a
// zero scale, GeometryError for a degenerate loop.
ExtendResult extend_boundary(const Mesh& garment, const GarmentFile& file, const ExtendSpec& spec,
                             const DesignBody* body = nullptr);

}  // namespace gp
