#include "render/views.h"

#include <cmath>

#include "core/error.h"

namespace gp::render {

const char* view_name(View view) {
  switch (view) {
    case View::front: return "front";
    case View::side: return "side";
    case View::back: return "back";
  }
  return "?";
}

OrthoCamera view_axes(View view, const Eigen::Vector3d& front) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  Eigen::Vector3d f = front - front.dot(up) * up;
  if (!(f.norm() > 1e-9)) throw UsageError("the body's front direction must not be vertical", "front");
  f.normalize();
  // The viewer stands at `toward` from the body and looks back at it; the
  // image's right is up x toward. The body's left is up x front seen from the front.
  Eigen::Vector3d toward = f;
  if (view == View::back) toward = -f;
  if (view == View::side) toward = up.cross(f);  // the body's left side
  OrthoCamera camera;
  camera.up = up;
  camera.right = up.cross(toward);
  return camera;
}

Eigen::Vector2d projected_half_extents(const Eigen::AlignedBox3d& box, const OrthoCamera& axes) {
  const Eigen::Vector3d h = 0.5 * box.sizes();
  return {std::abs(axes.right.x()) * h.x() + std::abs(axes.right.y()) * h.y() + std::abs(axes.right.z()) * h.z(),
          std::abs(axes.up.x()) * h.x() + std::abs(axes.up.y()) * h.y() + std::abs(axes.up.z()) * h.z()};
}

}  // namespace gp::render
