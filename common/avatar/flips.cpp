#include "avatar/flips.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "core/math.h"

namespace gp {
namespace {

double min_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  auto ang = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
    const Eigen::Vector3d u = q - p, v = r - p;
    return gp::math::atan2(u.cross(v).norm(), u.dot(v));
  };
  return std::min({ang(a, b, c), ang(b, c, a), ang(c, a, b)});
}

Eigen::Vector3d normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return (b - a).cross(c - a);
}

uint64_t key(int a, int b) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

}  // namespace

int flip_for_angles(const Eigen::MatrixXd& V, Eigen::MatrixXi& F, const FlipOptions& o) {
  const double cos_max = gp::math::cos(o.max_dihedral * M_PI / 180.0);
  const double cos_needle = gp::math::cos(2.0 * o.max_dihedral * M_PI / 180.0);
  auto P = [&](int i) -> Eigen::Vector3d { return V.row(i).transpose(); };
  std::vector<int> valence(V.rows(), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++valence[F(f, k)];  // each vertex: #faces = valence on a closed mesh
  int total = 0;
  for (int pass = 0; pass < o.max_passes; ++pass) {
    // Directed edge -> face.
    std::unordered_map<uint64_t, int> face_of;
    face_of.reserve(static_cast<size_t>(F.rows()) * 3);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) face_of[key(F(f, k), F(f, (k + 1) % 3))] = static_cast<int>(f);
    int flips = 0;
    for (Eigen::Index f1 = 0; f1 < F.rows(); ++f1) {
      for (int k = 0; k < 3; ++k) {
        const int a = F(f1, k), b = F(f1, (k + 1) % 3), c = F(f1, (k + 2) % 3);
        if (a > b) continue;  // each undirected edge once, from one side
        const auto it = face_of.find(key(b, a));
        if (it == face_of.end()) continue;
        const int f2 = it->second;
        int d = -1;
        for (int m = 0; m < 3; ++m)
          if (F(f2, m) != a && F(f2, m) != b) d = F(f2, m);
        if (d < 0 || d == c) continue;
        if (valence[a] <= 3 || valence[b] <= 3) continue;
        if (face_of.count(key(c, d)) || face_of.count(key(d, c))) continue;
        const Eigen::Vector3d pa = P(a), pb = P(b), pc = P(c), pd = P(d);
        const double before = std::min(min_angle(pa, pb, pc), min_angle(pb, pa, pd));
        const double after = std::min(min_angle(pc, pa, pd), min_angle(pd, pb, pc));
        if (after <= before + 1e-3) continue;
        const Eigen::Vector3d n1 = normal(pa, pb, pc), n2 = normal(pb, pa, pd);
        const Eigen::Vector3d m1 = normal(pc, pa, pd), m2 = normal(pd, pb, pc);
        const double l1 = n1.norm(), l2 = n2.norm(), k1 = m1.norm(), k2 = m2.norm();
        if (k1 <= 0 || k2 <= 0) continue;
        // Nearly flat before and after, and the new triangles face the same
        // way. A needle's own normal is noise, so pairs with one are judged
        // by the new triangles alone, with twice the allowed bend.
        const bool needle = before < o.needle_angle * M_PI / 180.0;
        if (!needle && l1 > 0 && l2 > 0 && n1.dot(n2) < cos_max * l1 * l2) continue;
        if (m1.dot(m2) < (needle ? cos_needle : cos_max) * k1 * k2) continue;
        const Eigen::Vector3d avg = n1 + n2;
        if (m1.dot(avg) <= 0 || m2.dot(avg) <= 0) continue;
        // Flip: (a, b, c) + (b, a, d) -> (c, a, d) + (d, b, c).
        for (int m = 0; m < 3; ++m) {
          face_of.erase(key(F(f1, m), F(f1, (m + 1) % 3)));
          face_of.erase(key(F(f2, m), F(f2, (m + 1) % 3)));
        }
        F.row(f1) << c, a, d;
        F.row(f2) << d, b, c;
        for (int m = 0; m < 3; ++m) {
          face_of[key(F(f1, m), F(f1, (m + 1) % 3))] = static_cast<int>(f1);
          face_of[key(F(f2, m), F(f2, (m + 1) % 3))] = f2;
        }
        --valence[a];
        --valence[b];
        ++valence[c];
        ++valence[d];
        ++flips;
        break;  // f1 changed; its other edges are visited in the next pass
      }
    }
    total += flips;
    if (flips == 0) break;
  }
  return total;
}

}  // namespace gp
