#include "registration/correspondence.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

#include "core/math.h"

namespace gp {
namespace {

struct DirectedEdgeHash {
  size_t operator()(const std::pair<int, int>& e) const {
    return std::hash<long long>()((static_cast<long long>(e.first) << 32) ^
                                  static_cast<unsigned>(e.second));
  }
};

// Half-edge lookup for one mesh: directed edge (a, b) -> (face, corner of a).
struct HalfEdges {
  std::unordered_map<std::pair<int, int>, std::pair<int, int>, DirectedEdgeHash> map;
  std::vector<int> valence;
  bool manifold = true;

  HalfEdges(const Eigen::MatrixXi& F, int n_vertices) : valence(static_cast<size_t>(n_vertices), 0) {
    map.reserve(static_cast<size_t>(F.rows()) * 3);
    for (int f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = F(f, k), b = F(f, (k + 1) % 3);
        if (a < 0 || a >= n_vertices || b < 0 || b >= n_vertices) {
          manifold = false;
          continue;
        }
        if (!map.emplace(std::make_pair(a, b), std::make_pair(f, k)).second) manifold = false;
        ++valence[a];
      }
  }
  const std::pair<int, int>* find(int a, int b) const {
    auto it = map.find({a, b});
    return it == map.end() ? nullptr : &it->second;
  }
};

// Grows the map from reference face `seed_ref` (corner 0) onto face
// `seed_other` starting at corner `rot`. Fills vertex and face maps for the
// connected component; returns false on any contradiction.
bool grow(const Eigen::MatrixXi& Fr, const HalfEdges& Hr, const Eigen::MatrixXi& Fo,
          const HalfEdges& Ho, int seed_ref, int seed_other, int rot, std::vector<int>& vmap,
          std::vector<int>& vmap_inverse, std::vector<int>& fmap, std::vector<int>& touched_faces,
          std::vector<int>& touched_vertices) {
  std::vector<std::pair<int, int>> queue;  // (ref face, rotation onto its other face)
  auto assign_vertex = [&](int v, int w) {
    if (vmap[v] == w) return true;
    if (vmap[v] != -1 || vmap_inverse[w] != -1) return false;
    if (Hr.valence[v] != Ho.valence[w]) return false;
    vmap[v] = w;
    vmap_inverse[w] = v;
    touched_vertices.push_back(v);
    return true;
  };
  auto assign_face = [&](int fr, int fo, int r) {
    if (fmap[fr] != -1) return fmap[fr] == fo;
    for (int k = 0; k < 3; ++k)
      if (!assign_vertex(Fr(fr, k), Fo(fo, (k + r) % 3))) return false;
    fmap[fr] = fo;
    touched_faces.push_back(fr);
    queue.push_back({fr, r});
    return true;
  };
  if (!assign_face(seed_ref, seed_other, rot)) return false;
  for (size_t head = 0; head < queue.size(); ++head) {
    const auto [fr, r] = queue[head];
    const int fo = fmap[fr];
    for (int k = 0; k < 3; ++k) {
      const int a = Fr(fr, k), b = Fr(fr, (k + 1) % 3);
      const auto* twin_ref = Hr.find(b, a);
      const int oa = Fo(fo, (k + r) % 3), ob = Fo(fo, (k + 1 + r) % 3);
      const auto* twin_other = Ho.find(ob, oa);
      if (!twin_ref || !twin_other) {
        if (twin_ref || twin_other) return false;  // boundary on one side only
        continue;
      }
      // Corner of b in the twin faces must correspond.
      const int gr = twin_ref->first, jr = twin_ref->second;
      const int go = twin_other->first, jo = twin_other->second;
      if (!assign_face(gr, go, ((jo - jr) % 3 + 3) % 3)) return false;
    }
  }
  return true;
}

}  // namespace

const char* connectivity_name(Connectivity c) {
  switch (c) {
    case Connectivity::identical: return "identical";
    case Connectivity::same_faces_reordered: return "same-faces-reordered";
    case Connectivity::permuted: return "permuted";
    case Connectivity::different: return "different";
  }
  return "different";
}

Connectivity compare_triangle_lists(const Eigen::MatrixXi& F_ref, const Eigen::MatrixXi& F_other) {
  if (F_ref.rows() == F_other.rows() && F_ref == F_other) return Connectivity::identical;
  if (F_ref.rows() != F_other.rows()) return Connectivity::different;
  // The same oriented triangles in another order or starting corner.
  auto canonical = [](const Eigen::MatrixXi& F) {
    std::vector<std::array<int, 3>> out;
    out.reserve(static_cast<size_t>(F.rows()));
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      std::array<int, 3> t = {F(f, 0), F(f, 1), F(f, 2)};
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  return canonical(F_ref) == canonical(F_other) ? Connectivity::same_faces_reordered
                                                : Connectivity::different;
}

std::optional<VertexCorrespondence> find_vertex_correspondence(
    const Eigen::MatrixXd& V_ref, const Eigen::MatrixXi& F_ref, const Eigen::MatrixXd& V_other,
    const Eigen::MatrixXi& F_other, const CorrespondenceOptions& options) {
  const int nv = static_cast<int>(V_ref.rows());
  if (V_other.rows() != nv || F_other.rows() != F_ref.rows() || F_ref.rows() == 0) return std::nullopt;
  const HalfEdges Hr(F_ref, nv), Ho(F_other, nv);
  if (!Hr.manifold || !Ho.manifold) return std::nullopt;
  {
    std::vector<int> a = Hr.valence, b = Ho.valence;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    if (a != b) return std::nullopt;
  }

  // Valence signature of a face read from a given corner.
  auto signature = [](const Eigen::MatrixXi& F, const HalfEdges& H, int f, int r) {
    return std::array<int, 3>{H.valence[F(f, r)], H.valence[F(f, (r + 1) % 3)],
                              H.valence[F(f, (r + 2) % 3)]};
  };
  std::map<std::array<int, 3>, std::vector<std::pair<int, int>>> other_by_signature;
  for (int f = 0; f < F_other.rows(); ++f)
    for (int r = 0; r < 3; ++r) other_by_signature[signature(F_other, Ho, f, r)].push_back({f, r});

  // Edge list of the reference for the distortion score.
  std::vector<std::pair<int, int>> edges;
  for (const auto& [e, fk] : Hr.map)
    if (e.first < e.second) edges.push_back(e);
  std::sort(edges.begin(), edges.end());

  VertexCorrespondence result;
  result.other_of_ref.assign(static_cast<size_t>(nv), -1);
  std::vector<int> vmap_inverse(static_cast<size_t>(nv), -1);
  std::vector<int> fmap(static_cast<size_t>(F_ref.rows()), -1);
  std::vector<bool> other_face_used(static_cast<size_t>(F_other.rows()), false);
  int trials = 0;

  // One connected component of the reference at a time.
  while (true) {
    int seed_ref = -1;
    {
      // Rarest signature among unmapped faces (ties: lowest face id).
      size_t best = SIZE_MAX;
      for (int f = 0; f < F_ref.rows(); ++f) {
        if (fmap[f] != -1) continue;
        auto it = other_by_signature.find(signature(F_ref, Hr, f, 0));
        const size_t n = it == other_by_signature.end() ? 0 : it->second.size();
        if (n < best) {
          best = n;
          seed_ref = f;
        }
        if (best <= 1) break;
      }
    }
    if (seed_ref == -1) break;  // all faces mapped
    auto it = other_by_signature.find(signature(F_ref, Hr, seed_ref, 0));
    if (it == other_by_signature.end()) return std::nullopt;

    struct Solution {
      std::vector<std::pair<int, int>> vertex_pairs;  // (ref, other)
      std::vector<std::pair<int, int>> face_pairs;
      double distortion, displacement;
    };
    std::vector<Solution> solutions;
    for (const auto& [fo, r] : it->second) {
      if (other_face_used[fo]) continue;
      if (++trials > options.max_seed_trials ||
          static_cast<int>(solutions.size()) >= options.max_solutions)
        break;
      std::vector<int> touched_faces, touched_vertices;
      const bool ok = grow(F_ref, Hr, F_other, Ho, seed_ref, fo, r, result.other_of_ref,
                           vmap_inverse, fmap, touched_faces, touched_vertices);
      if (ok) {
        Solution s;
        s.distortion = 0;
        s.displacement = 0;
        std::set<int> component_vertices(touched_vertices.begin(), touched_vertices.end());
        for (const auto& [a, b] : edges) {
          if (!component_vertices.count(a)) continue;
          const double lr = (V_ref.row(a) - V_ref.row(b)).norm();
          const double lo =
              (V_other.row(result.other_of_ref[a]) - V_other.row(result.other_of_ref[b])).norm();
          if (lr > 0 && lo > 0) s.distortion += std::abs(gp::math::log(lo / lr));
        }
        for (int v : touched_vertices) {
          s.vertex_pairs.push_back({v, result.other_of_ref[v]});
          s.displacement += (V_ref.row(v) - V_other.row(result.other_of_ref[v])).squaredNorm();
        }
        for (int f : touched_faces) s.face_pairs.push_back({f, fmap[f]});
        solutions.push_back(std::move(s));
      }
      // Undo, so that the next candidate starts clean.
      for (int v : touched_vertices) {
        vmap_inverse[result.other_of_ref[v]] = -1;
        result.other_of_ref[v] = -1;
      }
      for (int f : touched_faces) fmap[f] = -1;
    }
    if (solutions.empty()) return std::nullopt;

    // Least distortion wins; within a relative 1e-9 of it, least displacement.
    double best_distortion = INFINITY;
    for (const auto& s : solutions) best_distortion = std::min(best_distortion, s.distortion);
    const double slack = 1e-9 * (1.0 + best_distortion) * static_cast<double>(edges.size());
    const Solution* best = nullptr;
    int near_best = 0;
    for (const auto& s : solutions) {
      if (s.distortion > best_distortion + slack) continue;
      ++near_best;
      if (!best || s.displacement < best->displacement) best = &s;
    }
    int ties = 0;
    for (const auto& s : solutions)
      if (s.distortion <= best_distortion + slack &&
          s.displacement <= best->displacement * (1 + 1e-9) + 1e-300)
        ++ties;
    result.ties = std::max(result.ties, ties);
    if (near_best > 1)
      result.note = std::to_string(near_best) +
                    " relabellings fit the connectivity equally well (a symmetric mesh); chose the one "
                    "that moves vertices least";
    for (const auto& [v, w] : best->vertex_pairs) {
      result.other_of_ref[v] = w;
      vmap_inverse[w] = v;
    }
    for (const auto& [fr, fo] : best->face_pairs) {
      fmap[fr] = fo;
      other_face_used[fo] = true;
    }
  }
  result.candidates_tried = trials;

  // Verify: a bijection, and every reference triangle is a triangle of the
  // other mesh with the same orientation.
  for (int v = 0; v < nv; ++v)
    if (result.other_of_ref[v] < 0) return std::nullopt;  // unreferenced vertex
  for (int f = 0; f < F_ref.rows(); ++f) {
    const int a = result.other_of_ref[F_ref(f, 0)], b = result.other_of_ref[F_ref(f, 1)],
              c = result.other_of_ref[F_ref(f, 2)];
    const auto* e = Ho.find(a, b);
    if (!e || F_other(e->first, (e->second + 2) % 3) != c) return std::nullopt;
  }
  return result;
}

Eigen::MatrixXd reorder_vertices(const Eigen::MatrixXd& V_other, const VertexCorrespondence& c) {
  Eigen::MatrixXd V(static_cast<Eigen::Index>(c.other_of_ref.size()), V_other.cols());
  for (size_t v = 0; v < c.other_of_ref.size(); ++v)
    V.row(static_cast<Eigen::Index>(v)) = V_other.row(c.other_of_ref[v]);
  return V;
}

}  // namespace gp
