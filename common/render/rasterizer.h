#pragma once
// A z-buffer rasterizer for triangle meshes: orthographic camera, per-pixel
// depth, normals interpolated across each triangle and lit by one directional
// light plus ambient (Lambert), both sides of every triangle lit (garments are
// open surfaces), supersampling resolved by a box filter for anti-aliasing.
// Deterministic: no threads, no GPU, no window; the same input gives the same
// pixels.
#include <vector>

#include <Eigen/Core>

#include "render/image.h"

namespace gp::render {

// An orthographic view. World point p lands at pixel
//   x = width / 2 + pixels_per_metre * (p - center) . right
//   y = height / 2 - pixels_per_metre * (p - center) . up
// and is nearer the viewer the larger (p - center) . (right x up) is.
struct OrthoCamera {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // world point at the image centre [m]
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();  // unit, image +x
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();     // unit, orthogonal to right; image rows go down
  double pixels_per_metre = 100.0;
  int width = 256;                                   // pixels
  int height = 256;
};

struct Shading {
  float ambient = 0.38f;  // light from every side, fraction of the albedo
  float diffuse = 0.62f;  // directional light at normal incidence, fraction of the albedo
  // Light direction (unit after normalization), towards the light, in camera
  // coordinates: x right, y up, z towards the viewer. Default: from the upper
  // left, in front.
  Eigen::Vector3f light = Eigen::Vector3f(-0.35f, 0.5f, 0.79f);
  // Albedo factor where the back of a triangle (its corners clockwise on the
  // screen) faces the viewer: the inside of a garment reads darker.
  float back_factor = 0.8f;
};

struct RenderOptions {
  int supersampling = 3;            // samples per pixel along each axis (1: no anti-aliasing)
  Rgb background{1.0f, 1.0f, 1.0f};
  Shading shading;
};

// One mesh to draw. Colours: per face (#F by 3), else per vertex (#V by 3,
// interpolated), else `colour`. Components in [0, 1].
struct MeshLayer {
  const Eigen::MatrixXd* V = nullptr;  // #V by 3 [m]
  const Eigen::MatrixXi* F = nullptr;  // #F by 3
  const Eigen::MatrixXf* face_colours = nullptr;
  const Eigen::MatrixXf* vertex_colours = nullptr;
  Rgb colour{0.7f, 0.7f, 0.7f};
};

// Where world point p lands in the camera's image [pixels, fractional], by
// the mapping documented on OrthoCamera: marks drawn over a render (a ring
// around a place) line up with the rendered mesh.
Eigen::Vector2d project(const OrthoCamera& camera, const Eigen::Vector3d& p);

// Renders the layers into a camera.width by camera.height image. Throws
// UsageError for sizes that do not match, a non-positive scale or image size,
// or a supersampling factor outside 1..8.
Image render(const std::vector<MeshLayer>& layers, const OrthoCamera& camera, const RenderOptions& options = {});

}  // namespace gp::render
