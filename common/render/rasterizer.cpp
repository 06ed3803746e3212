#include "render/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>

#include "core/error.h"
#include "mesh/measures.h"

namespace gp::render {
namespace {

constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
constexpr int kLayerBits = 4;  // up to 16 layers; faces below 2^28

void check_layer(const MeshLayer& layer, size_t index) {
  const std::string where = "layer " + std::to_string(index);
  if (!layer.V || !layer.F) throw UsageError("a render layer needs vertices and faces", where);
  if (layer.V->cols() != 3 || layer.F->cols() != 3) throw UsageError("vertices and faces must have 3 columns", where);
  if (layer.F->size() > 0 && (layer.F->minCoeff() < 0 || layer.F->maxCoeff() >= layer.V->rows()))
    throw UsageError("a face index is out of range", where);
  if (layer.F->rows() >= (Eigen::Index{1} << (32 - kLayerBits)) - 1) throw UsageError("too many faces", where);
  if (layer.face_colours && (layer.face_colours->rows() != layer.F->rows() || layer.face_colours->cols() != 3))
    throw UsageError("face colours must be #F by 3", where);
  if (layer.vertex_colours && (layer.vertex_colours->rows() != layer.V->rows() || layer.vertex_colours->cols() != 3))
    throw UsageError("vertex colours must be #V by 3", where);
}

// A layer in sample coordinates: x right, y down, depth towards the viewer,
// and its vertex normals in camera coordinates (x right, y up, z towards the viewer).
struct ScreenLayer {
  std::vector<float> x, y, z;
  std::vector<float> nx, ny, nz;
};

}  // namespace

Eigen::Vector2d project(const OrthoCamera& camera, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - camera.center;
  return {0.5 * camera.width + camera.pixels_per_metre * d.dot(camera.right.normalized()),
          0.5 * camera.height - camera.pixels_per_metre * d.dot(camera.up.normalized())};
}

Image render(const std::vector<MeshLayer>& layers, const OrthoCamera& camera, const RenderOptions& options) {
  if (camera.width <= 0 || camera.height <= 0 || !(camera.pixels_per_metre > 0.0))
    throw UsageError("the camera needs a positive image size and scale");
  if (options.supersampling < 1 || options.supersampling > 8)
    throw UsageError("supersampling must be 1 to 8, got " + std::to_string(options.supersampling));
  if (layers.size() > (1u << kLayerBits)) throw UsageError("at most 16 layers");
  for (size_t i = 0; i < layers.size(); ++i) check_layer(layers[i], i);

  const int k = options.supersampling;
  const int W = camera.width * k, H = camera.height * k;
  const double s = camera.pixels_per_metre * k;
  const Eigen::Vector3d right = camera.right.normalized();
  const Eigen::Vector3d up = camera.up.normalized();
  const Eigen::Vector3d toward = right.cross(up);

  std::vector<ScreenLayer> screen(layers.size());
  for (size_t l = 0; l < layers.size(); ++l) {
    const Eigen::MatrixXd& V = *layers[l].V;
    const Eigen::MatrixXd N = vertex_normals(V, *layers[l].F);
    ScreenLayer& P = screen[l];
    const size_t n = static_cast<size_t>(V.rows());
    for (auto* a : {&P.x, &P.y, &P.z, &P.nx, &P.ny, &P.nz}) a->resize(n);
    for (size_t v = 0; v < n; ++v) {
      const Eigen::Index i = static_cast<Eigen::Index>(v);
      const Eigen::Vector3d d = V.row(i).transpose() - camera.center;
      P.x[v] = static_cast<float>(0.5 * W + s * d.dot(right));
      P.y[v] = static_cast<float>(0.5 * H - s * d.dot(up));
      P.z[v] = static_cast<float>(d.dot(toward));
      const Eigen::Vector3d nv = N.row(i).transpose();
      P.nx[v] = static_cast<float>(nv.dot(right));
      P.ny[v] = static_cast<float>(nv.dot(up));
      P.nz[v] = static_cast<float>(nv.dot(toward));
    }
  }

  // Visibility: depth test per sample, keeping the face (and its layer).
  const size_t samples = static_cast<size_t>(W) * static_cast<size_t>(H);
  std::vector<float> depth(samples, -std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> id(samples, kEmpty);
  for (size_t l = 0; l < layers.size(); ++l) {
    const Eigen::MatrixXi& F = *layers[l].F;
    const ScreenLayer& P = screen[l];
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const int i0 = F(f, 0), i1 = F(f, 1), i2 = F(f, 2);
      const float x0 = P.x[i0], y0 = P.y[i0], x1 = P.x[i1], y1 = P.y[i1], x2 = P.x[i2], y2 = P.y[i2];
      if (!std::isfinite(x0 + y0 + x1 + y1 + x2 + y2 + P.z[i0] + P.z[i1] + P.z[i2])) continue;
      const float area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
      if (!(std::abs(area) > 1e-12f)) continue;
      const int xmin = std::max(0, static_cast<int>(std::floor(std::min({x0, x1, x2}))));
      const int xmax = std::min(W - 1, static_cast<int>(std::ceil(std::max({x0, x1, x2}))));
      const int ymin = std::max(0, static_cast<int>(std::floor(std::min({y0, y1, y2}))));
      const int ymax = std::min(H - 1, static_cast<int>(std::ceil(std::max({y0, y1, y2}))));
      if (xmin > xmax || ymin > ymax) continue;
      const float inv = 1.0f / area;
      const float z0 = P.z[i0], dz1 = P.z[i1] - z0, dz2 = P.z[i2] - z0;
      const std::uint32_t face_id = (static_cast<std::uint32_t>(f) << kLayerBits) | static_cast<std::uint32_t>(l);
      // Barycentric weights of corners 1 and 2 are affine in the sample
      // position: stepped along x.
      const float b1_dx = (y2 - y0) * inv, b2_dx = -(y1 - y0) * inv;
      for (int y = ymin; y <= ymax; ++y) {
        const float py = static_cast<float>(y) + 0.5f;
        const float px = static_cast<float>(xmin) + 0.5f;
        float b1 = ((px - x0) * (y2 - y0) - (x2 - x0) * (py - y0)) * inv;
        float b2 = ((x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)) * inv;
        size_t at = static_cast<size_t>(y) * static_cast<size_t>(W) + static_cast<size_t>(xmin);
        for (int x = xmin; x <= xmax; ++x, ++at, b1 += b1_dx, b2 += b2_dx) {
          if (b1 < 0.0f || b2 < 0.0f || b1 + b2 > 1.0f) continue;
          const float z = z0 + b1 * dz1 + b2 * dz2;
          if (z <= depth[at]) continue;
          depth[at] = z;
          id[at] = face_id;
        }
      }
    }
  }

  // Deferred shading: each sample is lit once, whatever was drawn over it.
  const Shading& sh = options.shading;
  const Eigen::Vector3f light = sh.light.normalized();
  Image full(W, H, options.background);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const std::uint32_t code = id[static_cast<size_t>(y) * static_cast<size_t>(W) + static_cast<size_t>(x)];
      if (code == kEmpty) continue;
      const size_t l = code & ((1u << kLayerBits) - 1);
      const Eigen::Index f = static_cast<Eigen::Index>(code >> kLayerBits);
      const MeshLayer& layer = layers[l];
      const ScreenLayer& P = screen[l];
      const int i0 = (*layer.F)(f, 0), i1 = (*layer.F)(f, 1), i2 = (*layer.F)(f, 2);
      const float x0 = P.x[i0], y0 = P.y[i0], x1 = P.x[i1], y1 = P.y[i1], x2 = P.x[i2], y2 = P.y[i2];
      // Twice the signed area in sample coordinates (y down): negative for
      // corners counter-clockwise as the viewer sees them (the front side).
      const float area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
      const float inv = 1.0f / area;
      const float px = static_cast<float>(x) + 0.5f, py = static_cast<float>(y) + 0.5f;
      const float b1 = ((px - x0) * (y2 - y0) - (x2 - x0) * (py - y0)) * inv;
      const float b2 = ((x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)) * inv;
      const float b0 = 1.0f - b1 - b2;
      Eigen::Vector3f nc(b0 * P.nx[i0] + b1 * P.nx[i1] + b2 * P.nx[i2], b0 * P.ny[i0] + b1 * P.ny[i1] + b2 * P.ny[i2],
                         b0 * P.nz[i0] + b1 * P.nz[i1] + b2 * P.nz[i2]);
      const float length = nc.norm();
      nc = length > 0.0f ? Eigen::Vector3f(nc / length) : Eigen::Vector3f(0.0f, 0.0f, 1.0f);
      if (nc.z() < 0.0f) nc = -nc;  // both sides lit: the side the viewer sees
      float shade = sh.ambient + sh.diffuse * std::max(0.0f, nc.dot(light));
      if (area > 0.0f) shade *= sh.back_factor;
      float r = layer.colour.r, g = layer.colour.g, b = layer.colour.b;
      if (layer.face_colours) {
        const Eigen::MatrixXf& C = *layer.face_colours;
        r = C(f, 0), g = C(f, 1), b = C(f, 2);
      } else if (layer.vertex_colours) {
        const Eigen::MatrixXf& C = *layer.vertex_colours;
        r = b0 * C(i0, 0) + b1 * C(i1, 0) + b2 * C(i2, 0);
        g = b0 * C(i0, 1) + b1 * C(i1, 1) + b2 * C(i2, 1);
        b = b0 * C(i0, 2) + b1 * C(i1, 2) + b2 * C(i2, 2);
      }
      std::uint8_t* p = full.at(x, y);
      p[0] = to_byte(r * shade);
      p[1] = to_byte(g * shade);
      p[2] = to_byte(b * shade);
    }
  }
  return downsample(full, k);
}

}  // namespace gp::render
