#pragma once
// Combinatorial structure of a triangle mesh (F #F by 3 indices into [0, n_vertices)): edges,
// adjacency, boundary loops, connected components.
#include <vector>

#include <Eigen/Core>

namespace gp {

// Unique undirected edges as #E by 2 rows (a, b) with a < b, sorted.
Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F);

// #F by 3: TT(f,k) the face across the directed edge F(f,k) -> F(f,(k+1)%3), or -1 where the edge
// is a boundary or shared by more than two faces (non-manifold).
Eigen::MatrixXi triangle_adjacency(const Eigen::MatrixXi& F);

// Boundary loops: closed chains of edges used by exactly one face (an edge of three or more faces is
// none), as vertex ids in the direction the faces traverse them (the surface on the left for a
// counter-clockwise mesh); sorted by, and starting at, their smallest id: deterministic.
std::vector<std::vector<int>> boundary_loops(const Eigen::MatrixXi& F);

// Connected components of faces joined by shared edges: component id per face
// (numbered by first face), returns the number of components.
int face_components(const Eigen::MatrixXi& F, Eigen::VectorXi& component);

// Faces around each vertex (vertex -> list of face ids, ascending).
std::vector<std::vector<int>> vertex_faces(const Eigen::MatrixXi& F, int n_vertices);

// Vertex neighbours (one ring, ascending ids).
std::vector<std::vector<int>> vertex_neighbors(const Eigen::MatrixXi& F, int n_vertices);

// Euler characteristic V - E + F counting only referenced vertices.
int euler_characteristic(const Eigen::MatrixXi& F);

}  // namespace gp
