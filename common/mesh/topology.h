#pragma once
// Combinatorial structure of a triangle mesh: edges, adjacency, boundary loops,
// connected components. Inputs: F is #F by 3 vertex indices into [0, n_vertices).
#include <vector>

#include <Eigen/Core>

namespace gp {

// Unique undirected edges as #E by 2 rows (a, b) with a < b, sorted.
Eigen::MatrixXi unique_edges(const Eigen::MatrixXi& F);

// For every directed face edge (F(f,k) -> F(f,(k+1)%3)) the face across it:
// #F by 3, TT(f,k) = neighbour face or -1 where the edge is a boundary or is
// shared by more than two faces (non-manifold).
Eigen::MatrixXi triangle_adjacency(const Eigen::MatrixXi& F);

// Boundary loops: closed chains of edges used by exactly one face, each listed
// as vertex ids in the direction the faces traverse them (so that the surface
// lies on the left for a counter-clockwise oriented mesh). Loops are sorted by
// their smallest vertex id and start there, so the result is deterministic.
// Edges used by more than two faces are not boundary edges.
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
