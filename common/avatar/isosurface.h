#pragma once
// Polygonization of an implicit surface (inside f < 0) by marching tetrahedra on a grid split into
// Kuhn (Freudenthal) tetrahedra, six per cube around its main diagonal, so neighbouring cubes agree
// on every face diagonal and the zero set is a closed 2-manifold whatever the field values
// (Bloomenthal, "Polygonization of implicit surfaces", 1988; Doi and Koide 1991).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>

#include "io/mesh.h"

namespace gp {

struct IsosurfaceOptions {
  double cell = 0.01;  // grid spacing [m]
  // Octree culling: a block of cells is filled with the sign of the field at
  // its centre when |f(centre)| > lipschitz * (half the block diagonal). The
  // field must not change faster than `lipschitz` times the distance.
  double lipschitz = 2.0;
  // Cut points stay this fraction of an edge away from its ends (no needles or caps near grid
  // points); the surface may deviate by that fraction of a cell but, each patch inside its own
  // tetrahedron, never self-intersects.
  double min_edge_fraction = 0.2;
};

struct IsosurfaceStats {
  long long field_evaluations = 0;
  long long grid_points = 0;
};

// Triangle mesh of {f = 0} inside the box [lo, hi], oriented with normals
// pointing to f > 0 (outside). Vertices are numbered in scan order (z, y, x)
// of the grid, so the output is deterministic.
Mesh marching_tetrahedra(const std::function<double(const Eigen::Vector3d&)>& f, const Eigen::Vector3d& lo,
                         const Eigen::Vector3d& hi, const IsosurfaceOptions& options = {},
                         IsosurfaceStats* stats = nullptr);

}  // namespace gp
