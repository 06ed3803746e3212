#include "registration/edge_ratios.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/math.h"
#include "mesh/topology.h"

namespace gp {

EdgeRatioStats edge_ratio_stats(const Eigen::MatrixXd& V_ref, const Eigen::MatrixXd& V_pose,
                                const Eigen::MatrixXi& E, int worst_count) {
  EdgeRatioStats s;
  std::vector<double> ratios;
  std::vector<EdgeRatioEdge> edges;
  ratios.reserve(static_cast<size_t>(E.rows()));
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    EdgeRatioEdge x;
    x.v0 = E(e, 0);
    x.v1 = E(e, 1);
    x.reference_length = (V_ref.row(x.v0) - V_ref.row(x.v1)).norm();
    x.length = (V_pose.row(x.v0) - V_pose.row(x.v1)).norm();
    if (!(x.reference_length > 0) || !std::isfinite(x.length)) continue;
    x.ratio = x.length / x.reference_length;
    ratios.push_back(x.ratio);
    edges.push_back(x);
  }
  s.edge_count = static_cast<long long>(ratios.size());
  if (ratios.empty()) return s;
  std::vector<double> sorted = ratios;
  std::sort(sorted.begin(), sorted.end());
  // Nearest-rank percentiles: deterministic and exact on small sets.
  auto pct = [&](double p) {
    const size_t i = static_cast<size_t>(std::ceil(p * static_cast<double>(sorted.size()))) ;
    return sorted[std::min(sorted.size() - 1, i == 0 ? 0 : i - 1)];
  };
  s.min = sorted.front();
  s.max = sorted.back();
  s.p01 = pct(0.01);
  s.p05 = pct(0.05);
  s.median = pct(0.5);
  s.p95 = pct(0.95);
  s.p99 = pct(0.99);
  const double worst_log = std::max(std::abs(gp::math::log(s.min)), std::abs(gp::math::log(s.max)));
  s.worst_factor = gp::math::exp(worst_log);

  const size_t k = std::min(edges.size(), static_cast<size_t>(std::max(0, worst_count)));
  std::partial_sort(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(k), edges.end(),
                    [](const EdgeRatioEdge& a, const EdgeRatioEdge& b) {
                      const double la = std::abs(gp::math::log(a.ratio)), lb = std::abs(gp::math::log(b.ratio));
                      if (la != lb) return la > lb;
                      return std::make_pair(a.v0, a.v1) < std::make_pair(b.v0, b.v1);
                    });
  s.worst.assign(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(k));
  return s;
}

void check_pose_edge_ratios(const PoseSet& poses, const std::vector<int>& pose_ids, double max_factor,
                            const std::string& where) {
  const Eigen::MatrixXi E = unique_edges(poses.F);
  const int ref = poses.index_of(poses.reference, where);
  std::vector<char> checked(poses.V.size(), 0);
  for (int id : pose_ids) {
    if (id < 0 || id >= static_cast<int>(poses.V.size())) throw UsageError("pose index out of range");
    if (id == ref || checked[id]) continue;
    checked[id] = 1;
    const EdgeRatioStats s = edge_ratio_stats(poses.V[ref], poses.V[id], E, 1);
    if (s.worst_factor > max_factor && !s.worst.empty()) {
      const EdgeRatioEdge& w = s.worst.front();
      throw GeometryError("pose '" + poses.names[id] + "': edge " + std::to_string(w.v0) + "-" +
                              std::to_string(w.v1) + " changes length by a factor of " +
                              std::to_string(s.worst_factor) + " against '" + poses.reference +
                              "' (a registration error? run register-check)",
                          where);
    }
  }
}

}  // namespace gp
