#pragma once
// Small procedural meshes for tests (named families, as in libigl's and pmp's test helpers), closed
// or open as the name says, consistently oriented with normals pointing outward.
#include <vector>

#include <Eigen/Core>

#include "io/mesh.h"

namespace gp::testing {

// Icosahedron subdivided `levels` times and projected to the sphere:
// 10*4^levels + 2 vertices, closed, genus 0, near-equilateral triangles.
Mesh make_icosphere(int levels, double radius = 1.0);

// Latitude-longitude sphere with poles: (rings-1)*segments + 2 vertices.
Mesh make_uv_sphere(int rings, int segments, double radius = 1.0);

// Torus around the y axis: `nu` segments around the ring, `nv` around the tube.
Mesh make_torus(int nu, int nv, double ring_radius = 1.0, double tube_radius = 0.3);

// Open cylinder along +y from y=0 to y=height: `nu` around, `nv` rows of split quads; two loops.
Mesh make_open_cylinder(int nu, int nv, double radius = 1.0, double height = 2.0);

// A closed tube bent like an arm from a torso: up +y from (0, -leg, 0) to the origin, an arc of
// `turn` radians towards +x about (bend_radius, 0, 0), then `leg` metres straight; with
// bend_radius a little above radius its inner side is a saddle like an A-pose armpit. `nu`
// vertices per ring; flat fans close the ends.
Mesh make_bent_tube(int nu, double radius, double leg, double bend_radius, double turn);

// A box-shaped grid patch in the xz-plane (open, one boundary loop),
// (nx+1)*(nz+1) vertices, spanning [0,sx] x [0,sz].
Mesh make_grid(int nx, int nz, double sx = 1.0, double sz = 1.0);

// The faces `face_ids` of m (in that order) as a mesh of their own; its vertices
// are m's in the order of first use, and vertex_ids maps them back to m.
struct SubMesh {
  Mesh mesh;
  std::vector<int> vertex_ids;
};
SubMesh face_subset(const Mesh& m, const std::vector<int>& face_ids);

// Largest edge length in X over its length in V_rest (faces F): a tear shows far above the stretch.
double max_edge_stretch(const Eigen::MatrixXd& X, const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F);

// `count` vertex ids of V around the ring where the plane (`center`, `normal`) cuts it: at each of
// `count` evenly spaced angles the vertex nearest the plane within `reach` [m] of the centre, -1
// where none is (garment loop points clicked on a generated body).
std::vector<int> ring_vertex_ids(const Eigen::MatrixXd& V, const Eigen::Vector3d& center, const Eigen::Vector3d& normal,
                                 double reach, int count = 8);

}  // namespace gp::testing
