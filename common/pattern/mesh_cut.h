#pragma once
// Cutting a triangle mesh open along edge paths (seams): every vertex on a
// cut is split into one copy per fan of faces between cut (or boundary)
// edges, so that each cut edge becomes two boundary edges, and each keeps
// its partner on the other side of the seam.
#include <vector>
#include <Eigen/Core>

namespace gp {

// An edge path to cut along: vertex ids of the uncut mesh; consecutive ids
// must share an edge. Edges already on the boundary, or already cut by an
// earlier path, are skipped.
struct CutPath {
  int seam = -1;                // caller's seam index, copied into CutEdge
  std::vector<int> vertex_ids;
  bool closed = false;          // the last vertex joins the first
};

// One cut edge: the uncut edge (a -> b, in the direction of its path) and its
// two sides in the cut mesh. The "left" face is the one traversing a -> b
// (counter-clockwise faces: the face left of the path), the "right" face
// traverses b -> a. Face ids are the same in the cut and uncut mesh.
struct CutEdge {
  int seam = -1;
  int a = -1, b = -1;               // uncut vertex ids
  int left_face = -1, right_face = -1;
  int left_a = -1, left_b = -1;     // cut vertex ids of a and b in the left face
  int right_a = -1, right_b = -1;   // ... in the right face
  double length = 0.0;              // 3D length, metres
  double arc_start = 0.0;           // 3D arc length along its seam where the edge starts, metres
};

struct CutMesh {
  Eigen::MatrixXd V;        // #Vc by 3: cut vertices
  Eigen::MatrixXi F;        // #F by 3: same faces as the input, re-indexed to cut vertices
  Eigen::VectorXi origin;   // #Vc: uncut vertex id of every cut vertex
  std::vector<CutEdge> edges;  // every edge that was cut, path by path in path order
};

// V #V by 3 and F #F by 3 must be edge-manifold (an edge used by at most two
// faces) and consistently oriented; GeometryError otherwise, or when two
// consecutive path vertices share no edge. Cut vertex ids are assigned in
// order of (uncut id, smallest face id of the fan), so the result is
// deterministic.
CutMesh cut_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<CutPath>& paths);

}  // namespace gp
