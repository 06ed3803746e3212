#include "interp/rotation_log.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>
#include <tuple>

#include "core/math.h"
#include "mesh/topology.h"

namespace gp {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d vee_antisymmetric(const Eigen::Matrix3d& R) {
  // vee(R - R^T) = 2 sin(theta) a.
  return Eigen::Vector3d(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
}

}  // namespace

Eigen::Vector3d rotation_log(const Eigen::Matrix3d& R) {
  const Eigen::Vector3d w = vee_antisymmetric(R);
  const double s = 0.5 * w.norm();                  // sin(theta)
  const double c = 0.5 * (R.trace() - 1.0);         // cos(theta)
  const double theta = gp::math::atan2(s, c);            // accurate at both ends, unlike acos
  if (theta < 1e-6) {
    // theta / sin(theta) = 1 + theta^2/6 + ...
    return 0.5 * (1.0 + theta * theta / 6.0) * w;
  }
  if (theta < 0.5 * kPi) return (theta / (2.0 * s)) * w;
  // Near pi, sin(theta) loses the axis; (R + R^T)/2 = cos I + (1 - cos) a a^T does not.
  const Eigen::Matrix3d B = (0.5 * (R + R.transpose()) - c * Eigen::Matrix3d::Identity()) / (1.0 - c);
  int k = 0;
  B.diagonal().maxCoeff(&k);
  Eigen::Vector3d a = B.col(k) / std::sqrt(std::max(B(k, k), 1e-300));
  a.normalize();
  if (a.dot(w) < 0.0) a = -a;
  return theta * a;
}

Eigen::Matrix3d rotation_exp(const Eigen::Vector3d& omega) {
  const double theta2 = omega.squaredNorm();
  Eigen::Matrix3d K;
  K << 0.0, -omega.z(), omega.y(), omega.z(), 0.0, -omega.x(), -omega.y(), omega.x(), 0.0;
  double a, b;  // sin(theta)/theta and (1 - cos(theta))/theta^2
  if (theta2 < 1e-12) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    const double theta = std::sqrt(theta2);
    a = gp::math::sin(theta) / theta;
    b = (1.0 - gp::math::cos(theta)) / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * K + b * (K * K);
}

Eigen::Vector3d closest_log_branch(const Eigen::Vector3d& omega, const Eigen::Vector3d& reference) {
  const double theta = omega.norm();
  Eigen::Vector3d axis;
  if (theta > 1e-9) {
    axis = omega / theta;
  } else if (reference.norm() > 1e-9) {
    axis = reference.normalized();
  } else {
    return omega;
  }
  // The branches (theta + 2 pi k) axis lie on one line; take the one nearest to
  // the reference's projection on that line.
  const double s = axis.dot(reference);
  const double k = std::round((s - theta) / (2.0 * kPi));
  return omega + (2.0 * kPi * k) * axis;
}

Eigen::MatrixXd consistent_rotation_logs(const std::vector<Eigen::Matrix3d>& R,
                                         const std::vector<bool>& valid, const Eigen::MatrixXi& F) {
  const int nf = static_cast<int>(F.rows());
  Eigen::MatrixXd principal(nf, 3);
  std::vector<double> angle(static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    principal.row(f) = rotation_log(R[static_cast<size_t>(f)]).transpose();
    angle[static_cast<size_t>(f)] = valid[static_cast<size_t>(f)] ? principal.row(f).norm() : 1e300;
  }
  std::vector<int> order(static_cast<size_t>(nf));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return angle[static_cast<size_t>(x)] < angle[static_cast<size_t>(y)]; });

  const Eigen::MatrixXi TT = triangle_adjacency(F);
  const int nv = F.size() > 0 ? F.maxCoeff() + 1 : 0;
  const std::vector<std::vector<int>> VF = vertex_faces(F, nv);
  Eigen::VectorXi edge_component;
  face_components(F, edge_component);

  // Prim's order over the face graph (a minimum spanning tree): the face taken
  // next is the one whose rotation differs least from an already placed
  // neighbour's (angle of R_f^T R_g, branch-free). The branch thus travels
  // along the smoothest paths and never through a noisy patch (folds, near-
  // degenerate triangles) when a smoother way round exists: on a body, plain
  // breadth-first order can wind up a full turn through such a patch.
  // Faces sharing only a vertex are joined at a penalty, so that parts touching
  // at one vertex are reached but edges are preferred.
  constexpr double kVertexOnlyPenalty = 2.0 * kPi;
  Eigen::MatrixXd omega = Eigen::MatrixXd::Zero(nf, 3);
  std::vector<char> placed(static_cast<size_t>(nf), 0);
  using Item = std::tuple<double, int, int>;  // (weight, face, parent)
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  auto relative_angle = [&](int f, int g) {
    return rotation_log(R[static_cast<size_t>(f)].transpose() * R[static_cast<size_t>(g)]).norm();
  };
  auto push_neighbours = [&](int f) {
    for (int k = 0; k < 3; ++k) {
      const int g = TT(f, k);
      if (g >= 0 && !placed[static_cast<size_t>(g)]) heap.emplace(relative_angle(f, g), g, f);
    }
    for (int k = 0; k < 3; ++k)
      for (int g : VF[static_cast<size_t>(F(f, k))]) {
        // Within an edge-connected part the edges reach every face already.
        if (placed[static_cast<size_t>(g)] || edge_component(g) == edge_component(f)) continue;
        heap.emplace(relative_angle(f, g) + kVertexOnlyPenalty, g, f);
      }
  };
  for (int seed : order) {
    if (placed[static_cast<size_t>(seed)]) continue;
    placed[static_cast<size_t>(seed)] = 1;
    if (valid[static_cast<size_t>(seed)]) omega.row(seed) = principal.row(seed);
    push_neighbours(seed);
    while (!heap.empty()) {
      const auto [weight, g, f] = heap.top();
      heap.pop();
      if (placed[static_cast<size_t>(g)]) continue;
      placed[static_cast<size_t>(g)] = 1;
      const Eigen::Vector3d parent = omega.row(f).transpose();
      const Eigen::Vector3d w = valid[static_cast<size_t>(g)]
                                    ? closest_log_branch(principal.row(g).transpose(), parent)
                                    : parent;
      omega.row(g) = w.transpose();
      push_neighbours(g);
    }
  }
  return omega;
}

}  // namespace gp
