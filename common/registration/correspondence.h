#pragma once
// Correspondence between two poses' connectivity: identical, the same mesh
// with its vertices (and faces) in another order, or different. For the second
// case the common vertex order is recovered from the connectivity alone, since
// the poses differ in shape and positions cannot be matched directly.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gp {

enum class Connectivity {
  identical,        // same triangle list, row by row
  same_faces_reordered,  // same triangles (as vertex cycles), listed in another order
  permuted,         // isomorphic: a vertex relabelling maps one onto the other
  different,        // not the same mesh
};

const char* connectivity_name(Connectivity c);

struct VertexCorrespondence {
  // other_of_ref[v] = vertex of the other mesh that is vertex v of the reference.
  std::vector<int> other_of_ref;
  // How many distinct relabellings fit the connectivity and tied on the tie
  // breakers (1 = unique; more means a symmetric mesh, see `note`).
  int ties = 1;
  int candidates_tried = 0;
  std::string note;
};

struct CorrespondenceOptions {
  // Upper bound on complete relabellings examined before choosing; a body mesh
  // has one, symmetric test meshes (spheres) many.
  int max_solutions = 256;
  // Upper bound on seed trials (each costs at most one sweep of the mesh).
  int max_seed_trials = 20000;
};

// Compares triangle lists only (no search).
Connectivity compare_triangle_lists(const Eigen::MatrixXi& F_ref, const Eigen::MatrixXi& F_other);

// Finds the vertex relabelling that maps the reference connectivity onto the
// other mesh's, orientation preserving, by growing a face-to-face map from a
// seed triangle across shared edges (every step is forced on an oriented
// manifold, so a wrong seed fails quickly). Seeds are tried in order of rarity
// of their vertex valences. Among several complete solutions (symmetric
// meshes) the one with the least edge-length distortion wins, then the one
// with the smallest vertex displacement. Returns nothing if the meshes are not
// isomorphic or not manifold. Verified: every reference triangle maps onto a
// triangle of the other mesh.
std::optional<VertexCorrespondence> find_vertex_correspondence(
    const Eigen::MatrixXd& V_ref, const Eigen::MatrixXi& F_ref, const Eigen::MatrixXd& V_other,
    const Eigen::MatrixXi& F_other, const CorrespondenceOptions& options = {});

// V_other re-indexed into the reference's vertex order.
Eigen::MatrixXd reorder_vertices(const Eigen::MatrixXd& V_other, const VertexCorrespondence& c);

}  // namespace gp
