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

}  // namespace

Mesh simplify_mesh(const Mesh& mesh, int target_vertices, const SimplifyOptions& opt) {
  const int nv = static_cast<int>(mesh.V.rows());
  if (nv <= target_vertices) return mesh;
  std::vector<Eigen::Vector3d> P(nv);
  for (int i = 0; i < nv; ++i) P[i] = mesh.V.row(i).transpose();
  std::vector<Eigen::Vector3i> F(mesh.F.rows());
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) F[f] = mesh.F.row(f).transpose();
  std::vector<bool> face_alive(F.size(), true), vert_alive(nv, true);
  std::vector<std::vector<int>> vf(nv);
  for (size_t f = 0; f < F.size(); ++f)
    for (int k = 0; k < 3; ++k) vf[F[f](k)].push_back(static_cast<int>(f));

  std::vector<Quadric> Q(nv, Quadric::Zero());
  for (size_t f = 0; f < F.size(); ++f) {
    const Eigen::Vector3d& a = P[F[f](0)];
    const Eigen::Vector3d n2 = (P[F[f](1)] - a).cross(P[F[f](2)] - a);
    const double area2 = n2.norm();
    if (area2 <= 0) continue;
    const Eigen::Vector3d n = n2 / area2;
    Eigen::Vector4d pl(n.x(), n.y(), n.z(), -n.dot(a));
    const Quadric q = 0.5 * area2 * pl * pl.transpose();
    for (int k = 0; k < 3; ++k) Q[F[f](k)] += q;
  }
  std::vector<unsigned> stamp(nv, 0);

  auto best_position = [&](int a, int b, double& cost) {
    const Quadric q = Q[a] + Q[b];
    const Eigen::Vector3d mid = 0.5 * (P[a] + P[b]);
    const Eigen::Matrix3d A = q.topLeftCorner<3, 3>();
    const Eigen::Vector3d bb = q.topRightCorner<3, 1>();
    // Regularized toward the midpoint so flat regions stay well posed.
    const double eps = 1e-6 * A.trace() + 1e-30;
    const Eigen::Vector3d p = (A + eps * Eigen::Matrix3d::Identity()).ldlt().solve(-bb + eps * mid);
    const Eigen::Vector4d h(p.x(), p.y(), p.z(), 1.0);
    const double len2 = (P[a] - P[b]).squaredNorm();
    cost = std::max(h.dot(q * h), 0.0) + opt.length_weight * len2 * len2;
    return p;
  };
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap;
  auto push_edge = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    double c;
    best_position(a, b, c);
    heap.push({c, a, b, stamp[a], stamp[b]});
  };

  auto neighbors = [&](int v, std::vector<int>& out) {
    out.clear();
    for (int f : vf[v])
      for (int k = 0; k < 3; ++k)
        if (F[f](k) != v) out.push_back(F[f](k));
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  };
  std::vector<int> na, nb, nc, common;
  int alive = nv;
  // Strict normal bound first; where it leaves the budget unmet (strongly
  // curved small parts at coarse budgets) later passes relax it.
  // Edges refused in a pass get another chance in the next one, after their
  // neighbourhood changed.
  for (int pass = 0; pass < 40 && alive > target_vertices; ++pass) {
    const int alive_before = alive;
    const double turn = opt.max_normal_turn * (pass < 8 ? 1.0 : pass < 16 ? 1.5 : 2.5);
    const double cos_max = gp::math::cos(std::min(turn, 150.0) * M_PI / 180.0);
    heap = decltype(heap)();
    for (size_t f = 0; f < F.size(); ++f) {
      if (!face_alive[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const int a = F[f](k), b = F[f]((k + 1) % 3);
        if (a < b) push_edge(a, b);
      }
    }
    while (alive > target_vertices && !heap.empty()) {
      const Candidate c = heap.top();
      heap.pop();
      const int a = c.a, b = c.b;
      if (!vert_alive[a] || !vert_alive[b] || stamp[a] != c.stamp_a || stamp[b] != c.stamp_b) continue;
      // Link condition.
      neighbors(a, na);
      neighbors(b, nb);
      if (!std::binary_search(na.begin(), na.end(), b)) continue;
      common.clear();
      std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
      if (common.size() != 2) continue;
      // The two opposite vertices lose an edge each; keep them at valence >= 3.
      bool thin = false;
      for (int o : common) {
        neighbors(o, nc);
        thin |= nc.size() <= 3;
      }
      if (thin) continue;
      double cost;
      const Eigen::Vector3d p = best_position(a, b, cost);
      // No triangle may flip or turn too far.
      bool ok = true;
      for (int v : {a, b}) {
        for (int f : vf[v]) {
          const Eigen::Vector3i t = F[f];
          if ((t.array() == a).any() && (t.array() == b).any()) continue;
          Eigen::Vector3d q[3];
          for (int k = 0; k < 3; ++k) q[k] = P[t(k)];
          const Eigen::Vector3d n0 = (q[1] - q[0]).cross(q[2] - q[0]);
          for (int k = 0; k < 3; ++k)
            if (t(k) == v) q[k] = p;
          const Eigen::Vector3d n1 = (q[1] - q[0]).cross(q[2] - q[0]);
          const double l0 = n0.norm(), l1 = n1.norm();
          if (l1 <= 1e-18 || n0.dot(n1) < cos_max * l0 * l1) {
            ok = false;
            break;
          }
        }
        if (!ok) break;
      }
      if (!ok) continue;
      // Collapse b into a.
      std::vector<int> merged;
      for (int f : vf[b]) {
        Eigen::Vector3i& t = F[f];
        if ((t.array() == a).any()) {
          face_alive[f] = false;
          continue;
        }
        for (int k = 0; k < 3; ++k)
          if (t(k) == b) t(k) = a;
        merged.push_back(f);
      }
      std::vector<int> fa;
      for (int f : vf[a])
        if (face_alive[f]) fa.push_back(f);
      fa.insert(fa.end(), merged.begin(), merged.end());
      std::sort(fa.begin(), fa.end());
      vf[a] = fa;
      vf[b].clear();
      for (int o : common) {
        auto& l = vf[o];
        l.erase(std::remove_if(l.begin(), l.end(), [&](int f) { return !face_alive[f]; }), l.end());
      }
      vert_alive[b] = false;
      P[a] = p;
      Q[a] += Q[b];
      // Only edges at a changed (its quadric and position); older heap
      // entries of a are invalidated by its stamp, those of b by its death.
      ++stamp[a];
      --alive;
      neighbors(a, na);
      for (int u : na) push_edge(a, u);
    }
    if (alive == alive_before && pass >= 16) break;
  }
  Mesh out;
  std::vector<int> remap(nv, -1);
  int n = 0;
  for (int i = 0; i < nv; ++i)
    if (vert_alive[i]) remap[i] = n++;
  out.V.resize(n, 3);
  for (int i = 0; i < nv; ++i)
    if (vert_alive[i]) out.V.row(remap[i]) = P[i].transpose();
  int nf = 0;
  for (size_t f = 0; f < F.size(); ++f) nf += face_alive[f];
  out.F.resize(nf, 3);
  int k = 0;
  for (size_t f = 0; f < F.size(); ++f)
    if (face_alive[f]) out.F.row(k++) << remap[F[f](0)], remap[F[f](1)], remap[F[f](2)];
  return out;
}

}  // namespace gp
