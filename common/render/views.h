#pragma once
// The standard views of a body: front, side (the body's left) and back, as
// orthographic cameras that frame a box, all at one scale so that pictures of
// different poses compare at a glance.
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "render/rasterizer.h"

namespace gp::render {

enum class View { front, side, back };

const char* view_name(View view);  // "front", "side", "back"

// Camera axes for `view` of a body standing along +y whose front faces
// `front` (a unit vector orthogonal to +y): right and up of the image.
OrthoCamera view_axes(View view, const Eigen::Vector3d& front);

// Half extents of `box` along the camera's right and up axes [m].
Eigen::Vector2d projected_half_extents(const Eigen::AlignedBox3d& box, const OrthoCamera& axes);

}  // namespace gp::render
