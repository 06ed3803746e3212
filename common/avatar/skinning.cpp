#include "avatar/skinning.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "mesh/topology.h"

namespace gp {

Eigen::MatrixXd skinning_weights(const BodyShape& shape, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const SkinningOptions& o) {
  const Eigen::Index n = V.rows();
  const double falloff = o.falloff * shape.scale;
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(n, kJointCount);
  std::array<double, kPartCount> d;
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d p = V.row(v).transpose();
    body_part_distances(shape, p, d);
    int nearest = 0;
    for (int i = 1; i < kPartCount; ++i)
      if (d[i] < d[nearest]) nearest = i;
    const int chain = body_part_chain(nearest);
    for (int i = 0; i < kPartCount; ++i) {
      const int c = body_part_chain(i);
      // Torso vertices may take any limb root; limb vertices only their own
      // limb and the torso group.
      const bool limb_root = i == kLUpperArm || i == kRUpperArm || i == kLThigh || i == kRThigh;
      const bool allowed = c == chain || c == 0 || (chain == 0 && limb_root);
      if (!allowed) continue;
      const bool hip_pair = (i == kLThigh || i == kRThigh || nearest == kLThigh || nearest == kRThigh) &&
                            (i == kTorso || nearest == kTorso);
      const double t = 1.0 - (d[i] - d[nearest]) / (hip_pair ? o.hip_falloff_scale * falloff : falloff);
      if (t <= 0) continue;
      const double w = t * t;
      if (i == kTorso) {
        const Eigen::Vector3d tw = torso_bone_weights(shape, p.y());
        W(v, kPelvis) += w * tw(0);
        W(v, kSpine) += w * tw(1);
        W(v, kChest) += w * tw(2);
      } else {
        W(v, body_part_bone(i)) += w;
      }
    }
  }
  const auto nb = vertex_neighbors(F, static_cast<int>(n));
  double edge_sum = 0.0;
  long long edge_count = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    for (int u : nb[v]) {
      edge_sum += (V.row(u) - V.row(v)).norm();
      ++edge_count;
    }
  const double mean_edge = edge_count ? edge_sum / edge_count : o.reference_edge * shape.scale;
  const double ratio = o.reference_edge * shape.scale / mean_edge;
  const int iterations =
      o.smoothing_iterations == 0
          ? 0
          : std::clamp(static_cast<int>(std::lround(o.smoothing_iterations * ratio * ratio)), 1, 40);
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixXd S = W;
    for (Eigen::Index v = 0; v < n; ++v) {
      if (nb[v].empty()) continue;
      Eigen::RowVectorXd avg = Eigen::RowVectorXd::Zero(kJointCount);
      for (int u : nb[v]) avg += W.row(u);
      S.row(v) = 0.5 * W.row(v) + 0.5 * avg / static_cast<double>(nb[v].size());
    }
    W.swap(S);
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    const double s = W.row(v).sum();
    if (s > 0)
      W.row(v) /= s;
    else
      W(v, kPelvis) = 1.0;
  }
  return W;
}

Eigen::MatrixXd dual_quaternion_skinning(const Eigen::MatrixXd& V, const Eigen::MatrixXd& W,
                                         const std::vector<RigidTransform>& bones) {
  const int nb = static_cast<int>(bones.size());
  // Unit dual quaternion per bone: real part q, dual part 0.5 (0, t) q.
  std::vector<Eigen::Vector4d> real(nb), dual(nb);  // (w, x, y, z)
  for (int b = 0; b < nb; ++b) {
    const Eigen::Quaterniond& q = bones[b].q;
    const Eigen::Quaterniond t(0.0, bones[b].t.x(), bones[b].t.y(), bones[b].t.z());
    const Eigen::Quaterniond e = t * q;
    real[b] = Eigen::Vector4d(q.w(), q.x(), q.y(), q.z());
    dual[b] = 0.5 * Eigen::Vector4d(e.w(), e.x(), e.y(), e.z());
  }
  Eigen::MatrixXd out(V.rows(), 3);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    Eigen::Index pivot;
    W.row(v).maxCoeff(&pivot);
    Eigen::Vector4d b0 = Eigen::Vector4d::Zero(), be = Eigen::Vector4d::Zero();
    for (int b = 0; b < nb; ++b) {
      const double w = W(v, b);
      if (w == 0.0) continue;
      // Antipodal quaternions describe the same rotation; blend on the
      // pivot's hemisphere so that the shortest path is taken.
      const double s = real[b].dot(real[pivot]) < 0 ? -w : w;
      b0 += s * real[b];
      be += s * dual[b];
    }
    const double len = b0.norm();
    b0 /= len;
    be /= len;
    const Eigen::Quaterniond q(b0(0), b0(1), b0(2), b0(3));
    const Eigen::Quaterniond e(be(0), be(1), be(2), be(3));
    // Translation 2 e q* (the dual part's component orthogonal to q does not matter).
    const Eigen::Quaterniond tq = e * q.conjugate();
    const Eigen::Vector3d t = 2.0 * Eigen::Vector3d(tq.x(), tq.y(), tq.z());
    out.row(v) = (q * V.row(v).transpose() + t).transpose();
  }
  return out;
}

}  // namespace gp
