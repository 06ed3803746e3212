#include "pattern/cutter_helpers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f %%", 100.0 * x);
  return buf;
}

std::string metres(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3f m", x);
  return buf;
}

// The curve of a piece (local ids) on the pattern mesh.
SurfaceCurve piece_to_mesh(const PatternPiece& p, const SurfaceCurve& c) {
  SurfaceCurve out;
  for (const CurvePoint& q : c) {
    if (q.is_vertex()) out.push_back(CurvePoint::at_vertex(p.mesh_vertex_ids[q.vertex]));
    else if (q.is_edge()) out.push_back(CurvePoint::on_edge(p.mesh_vertex_ids[q.a], p.mesh_vertex_ids[q.b], q.t));
    else out.push_back(CurvePoint::in_face(p.face_ids[static_cast<size_t>(q.face)], q.bary));
  }
  return out;
}

// Cache key of a piece: its triangles as sorted triples of pattern-mesh
// vertex ids (unchanged by insertions elsewhere), then its slits.
std::vector<int> piece_key(const Pattern& pattern, size_t c) {
  const PatternPiece& p = pattern.pieces[c];
  std::vector<std::array<int, 3>> tri;
  for (int f = 0; f < p.F.rows(); ++f) {
    std::array<int, 3> t{p.mesh_vertex_ids[p.F(f, 0)], p.mesh_vertex_ids[p.F(f, 1)], p.mesh_vertex_ids[p.F(f, 2)]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    tri.push_back(t);
  }
  std::sort(tri.begin(), tri.end());
  std::vector<int> key;
  for (const auto& t : tri) key.insert(key.end(), t.begin(), t.end());
  key.push_back(-1);
  for (const CutEdge& e : pattern.cut.edges)
    if (pattern.piece_of_face[static_cast<size_t>(e.left_face)] == static_cast<int>(c) &&
        pattern.piece_of_face[static_cast<size_t>(e.right_face)] == static_cast<int>(c)) {
      key.push_back(std::min(e.a, e.b));
      key.push_back(std::max(e.a, e.b));
    }
  return key;
}

// Whether the two flat sides of every seam have the same length within the
// tolerance; fills the pieces on seams that do not.
bool seam_sides_match(const Pattern& pattern, const PatternOptions& options, double margin, std::set<int>* mismatched) {
  std::vector<double> left(pattern.seams.size(), 0.0), right(pattern.seams.size(), 0.0),
      length(pattern.seams.size(), 0.0);
  for (const CutEdge& e : pattern.cut.edges) {
    length[static_cast<size_t>(e.seam)] += e.length;
    for (int side = 0; side < 2; ++side) {
      const auto& q = pattern.pieces[static_cast<size_t>(pattern.piece_of_face[static_cast<size_t>(side == 0 ? e.left_face : e.right_face)])];
      const int a = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_a : e.right_a)];
      const int b = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_b : e.right_b)];
      (side == 0 ? left : right)[static_cast<size_t>(e.seam)] += (q.flat.UV.row(a) - q.flat.UV.row(b)).norm();
    }
  }
  bool ok = true;
  for (const CutEdge& e : pattern.cut.edges) {
    const size_t i = static_cast<size_t>(e.seam);
    if (std::abs(left[i] - right[i]) <= margin * std::max(options.seams.seam_tolerance, options.seams.seam_tolerance_relative * length[i]))
      continue;
    ok = false;
    if (!mismatched) return false;
    mismatched->insert(pattern.piece_of_face[static_cast<size_t>(e.left_face)]);
    mismatched->insert(pattern.piece_of_face[static_cast<size_t>(e.right_face)]);
  }
  return ok;
}

std::vector<char> boundary_flags(const PatternPiece& p) {
  std::vector<char> b(static_cast<size_t>(p.V.rows()), 0);
  for (const auto& loop : boundary_loops(p.F))
    for (int v : loop) b[static_cast<size_t>(v)] = 1;
  return b;
}

// The rest faces piece c covers, sorted.
std::vector<int> piece_rest_faces(const Pattern& pattern, size_t c) {
  std::vector<int> out;
  for (int f : pattern.pieces[c].face_ids) out.push_back(pattern.mesh.rest_face[static_cast<size_t>(f)]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

int piece_limb(const Pattern& pattern, size_t c) {
  if (pattern.limb_of_rest_face.empty()) return -1;
  const PatternPiece& p = pattern.pieces[c];
  const Eigen::VectorXd w = face_areas(p.V, p.F);
  std::map<int, double> on_limb;
  for (size_t i = 0; i < p.face_ids.size(); ++i) {
    const int rest = pattern.mesh.rest_face[static_cast<size_t>(p.face_ids[i])];
    on_limb[pattern.limb_of_rest_face[static_cast<size_t>(rest)]] += w(static_cast<Eigen::Index>(i));
  }
  for (const auto& [limb, area] : on_limb)
    if (limb >= 0 && area > 0.5 * w.sum()) return limb;
  return -1;
}

}  // namespace gp
