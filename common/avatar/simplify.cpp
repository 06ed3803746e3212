#include "avatar/simplify.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "core/math.h"

namespace gp {
namespace {

// Quadric as the symmetric 4x4 matrix of (n, d) plane outer products.
using Quadric = Eigen::Matrix4d;

struct Candidate {
  double cost;
  int a, b;
  unsigned stamp_a, stamp_b;
  bool operator>(const Candidate& o) const { return std::tie(cost, a, b) > std::tie(o.cost, o.a, o.b); }
};

// Garland and Heckbert's quadric edge collapse on the mesh's own arrays: a
// face's plane quadric per vertex, a heap of edges by cost, and a stamp per
// vertex that marks its older heap entries stale.
class EdgeCollapser {
 public:
  EdgeCollapser(const Mesh& mesh, const SimplifyOptions& opt) : opt_(opt) {
    const int nv = static_cast<int>(mesh.V.rows());
    P_.resize(nv);
    for (int i = 0; i < nv; ++i) P_[i] = mesh.V.row(i).transpose();
    F_.resize(mesh.F.rows());
    for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) F_[f] = mesh.F.row(f).transpose();
    face_alive_.assign(F_.size(), true);
    vert_alive_.assign(nv, true);
    vf_.resize(nv);
    for (size_t f = 0; f < F_.size(); ++f)
      for (int k = 0; k < 3; ++k) vf_[F_[f](k)].push_back(static_cast<int>(f));
    Q_.assign(nv, Quadric::Zero());
    for (size_t f = 0; f < F_.size(); ++f) {
      const Eigen::Vector3d& a = P_[F_[f](0)];
      const Eigen::Vector3d n2 = (P_[F_[f](1)] - a).cross(P_[F_[f](2)] - a);
      const double area2 = n2.norm();
      if (area2 <= 0) continue;
      const Eigen::Vector3d n = n2 / area2;
      Eigen::Vector4d pl(n.x(), n.y(), n.z(), -n.dot(a));
      const Quadric q = 0.5 * area2 * pl * pl.transpose();
      for (int k = 0; k < 3; ++k) Q_[F_[f](k)] += q;
    }
    stamp_.assign(nv, 0);
    alive_ = nv;
  }

  int alive() const { return alive_; }

  // One pass over every live edge with the normal bound cos_max, until
  // `target_vertices` are left or the heap is empty.
  void pass(int target_vertices, double cos_max) {
    heap_ = decltype(heap_)();
    for (size_t f = 0; f < F_.size(); ++f) {
      if (!face_alive_[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const int a = F_[f](k), b = F_[f]((k + 1) % 3);
        if (a < b) push_edge(a, b);
      }
    }
    while (alive_ > target_vertices && !heap_.empty()) {
      const Candidate c = heap_.top();
      heap_.pop();
      const int a = c.a, b = c.b;
      if (!vert_alive_[a] || !vert_alive_[b] || stamp_[a] != c.stamp_a || stamp_[b] != c.stamp_b) continue;
      if (!link_condition(a, b)) continue;
      double cost;
      const Eigen::Vector3d p = best_position(a, b, cost);
      if (!keeps_normals(a, b, p, cos_max)) continue;
      collapse(a, b, p);
    }
  }

  // The live vertices and faces, renumbered in their order.
  Mesh result() const {
    const int nv = static_cast<int>(P_.size());
    Mesh out;
    std::vector<int> remap(nv, -1);
    int n = 0;
    for (int i = 0; i < nv; ++i)
      if (vert_alive_[i]) remap[i] = n++;
    out.V.resize(n, 3);
    for (int i = 0; i < nv; ++i)
      if (vert_alive_[i]) out.V.row(remap[i]) = P_[i].transpose();
    int nf = 0;
    for (size_t f = 0; f < F_.size(); ++f) nf += face_alive_[f];
    out.F.resize(nf, 3);
    int k = 0;
    for (size_t f = 0; f < F_.size(); ++f)
      if (face_alive_[f]) out.F.row(k++) << remap[F_[f](0)], remap[F_[f](1)], remap[F_[f](2)];
    return out;
  }

 private:
  Eigen::Vector3d best_position(int a, int b, double& cost) const {
    const Quadric q = Q_[a] + Q_[b];
    const Eigen::Vector3d mid = 0.5 * (P_[a] + P_[b]);
    const Eigen::Matrix3d A = q.topLeftCorner<3, 3>();
    const Eigen::Vector3d bb = q.topRightCorner<3, 1>();
    // Regularized toward the midpoint so flat regions stay well posed.
    const double eps = 1e-6 * A.trace() + 1e-30;
    const Eigen::Vector3d p = (A + eps * Eigen::Matrix3d::Identity()).ldlt().solve(-bb + eps * mid);
    const Eigen::Vector4d h(p.x(), p.y(), p.z(), 1.0);
    const double len2 = (P_[a] - P_[b]).squaredNorm();
    cost = std::max(h.dot(q * h), 0.0) + opt_.length_weight * len2 * len2;
    return p;
  }

  void push_edge(int a, int b) {
    if (a > b) std::swap(a, b);
    double c;
    best_position(a, b, c);
    heap_.push({c, a, b, stamp_[a], stamp_[b]});
  }

  void neighbors(int v, std::vector<int>& out) const {
    out.clear();
    for (int f : vf_[v])
      for (int k = 0; k < 3; ++k)
        if (F_[f](k) != v) out.push_back(F_[f](k));
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  // The link condition (a and b share exactly two neighbours, into common_),
  // and the two opposite vertices, which lose an edge each, keep valence >= 3.
  bool link_condition(int a, int b) {
    neighbors(a, na_);
    neighbors(b, nb_);
    if (!std::binary_search(na_.begin(), na_.end(), b)) return false;
    common_.clear();
    std::set_intersection(na_.begin(), na_.end(), nb_.begin(), nb_.end(), std::back_inserter(common_));
    if (common_.size() != 2) return false;
    bool thin = false;
    for (int o : common_) {
      neighbors(o, nc_);
      thin |= nc_.size() <= 3;
    }
    return !thin;
  }

  // No triangle may flip or turn too far when a and b move to p.
  bool keeps_normals(int a, int b, const Eigen::Vector3d& p, double cos_max) const {
    for (int v : {a, b}) {
      for (int f : vf_[v]) {
        const Eigen::Vector3i t = F_[f];
        if ((t.array() == a).any() && (t.array() == b).any()) continue;
        Eigen::Vector3d q[3];
        for (int k = 0; k < 3; ++k) q[k] = P_[t(k)];
        const Eigen::Vector3d n0 = (q[1] - q[0]).cross(q[2] - q[0]);
        for (int k = 0; k < 3; ++k)
          if (t(k) == v) q[k] = p;
        const Eigen::Vector3d n1 = (q[1] - q[0]).cross(q[2] - q[0]);
        const double l0 = n0.norm(), l1 = n1.norm();
        if (l1 <= 1e-18 || n0.dot(n1) < cos_max * l0 * l1) return false;
      }
    }
    return true;
  }

  // Collapses b into a at p (common_ holds their two shared neighbours).
  void collapse(int a, int b, const Eigen::Vector3d& p) {
    std::vector<int> merged;
    for (int f : vf_[b]) {
      Eigen::Vector3i& t = F_[f];
      if ((t.array() == a).any()) {
        face_alive_[f] = false;
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (t(k) == b) t(k) = a;
      merged.push_back(f);
    }
    std::vector<int> fa;
    for (int f : vf_[a])
      if (face_alive_[f]) fa.push_back(f);
    fa.insert(fa.end(), merged.begin(), merged.end());
    std::sort(fa.begin(), fa.end());
    vf_[a] = fa;
    vf_[b].clear();
    for (int o : common_) {
      auto& l = vf_[o];
      l.erase(std::remove_if(l.begin(), l.end(), [&](int f) { return !face_alive_[f]; }), l.end());
    }
    vert_alive_[b] = false;
    P_[a] = p;
    Q_[a] += Q_[b];
    // Only edges at a changed (its quadric and position); older heap
    // entries of a are invalidated by its stamp, those of b by its death.
    ++stamp_[a];
    --alive_;
    neighbors(a, na_);
    for (int u : na_) push_edge(a, u);
  }

  const SimplifyOptions& opt_;
  std::vector<Eigen::Vector3d> P_;
  std::vector<Eigen::Vector3i> F_;
  std::vector<bool> face_alive_, vert_alive_;
  std::vector<std::vector<int>> vf_;
  std::vector<Quadric> Q_;
  std::vector<unsigned> stamp_;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap_;
  std::vector<int> na_, nb_, nc_, common_;
  int alive_ = 0;
};

}  // namespace

Mesh simplify_mesh(const Mesh& mesh, int target_vertices, const SimplifyOptions& opt) {
  const int nv = static_cast<int>(mesh.V.rows());
  if (nv <= target_vertices) return mesh;
  EdgeCollapser collapser(mesh, opt);
  // Strict normal bound first; where it leaves the budget unmet (strongly
  // curved small parts at coarse budgets) later passes relax it.
  // Edges refused in a pass get another chance in the next one, after their
  // neighbourhood changed.
  for (int pass = 0; pass < 40 && collapser.alive() > target_vertices; ++pass) {
    const int alive_before = collapser.alive();
    const double turn = opt.max_normal_turn * (pass < 8 ? 1.0 : pass < 16 ? 1.5 : 2.5);
    const double cos_max = gp::math::cos(std::min(turn, 150.0) * M_PI / 180.0);
    collapser.pass(target_vertices, cos_max);
    if (collapser.alive() == alive_before && pass >= 16) break;
  }
  return collapser.result();
}

}  // namespace gp
