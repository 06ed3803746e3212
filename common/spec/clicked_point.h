#pragma once
// A point the user "clicks" in a spec: either a vertex id of some mesh or a
// 3D point (metres) that the caller snaps to that mesh. Garment loops, paint
// centres and seam paths all take them.
#include <string>

#include <Eigen/Core>

#include "spec/json_file.h"

namespace gp {

struct ClickedPoint {
  bool is_vertex = true;
  long long vertex_id = -1;                         // when is_vertex
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // metres, when !is_vertex
  std::string where;                                // "file: /json/pointer" for errors
};

// Reads a non-negative integer (vertex id) or [x, y, z] (finite numbers).
// `noun` names the vertex in messages ("body vertex", "vertex"). Throws
// SpecError at `where` otherwise.
ClickedPoint read_clicked_point(const Json& j, const std::string& where, const std::string& noun);

// The point back as JSON (an id or [x, y, z]), for reports.
OrderedJson to_json(const ClickedPoint& p);

}  // namespace gp
