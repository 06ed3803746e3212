#pragma once
// Registration quality between two poses of one mesh: how much every edge
// changes length. Skin stretches locally (shoulders, armpits), so some change
// is expected; a vertex thrown far away by a registration error shows as a
// handful of edges with extreme ratios.
#include <vector>

#include <Eigen/Core>

namespace gp {

struct EdgeRatioEdge {
  int v0 = 0, v1 = 0;
  double reference_length = 0, length = 0, ratio = 0;
};

struct EdgeRatioStats {
  long long edge_count = 0;
  double min = 0, p01 = 0, p05 = 0, median = 0, p95 = 0, p99 = 0, max = 0;
  // Largest |log ratio| (the larger of ratio and 1/ratio), 1 for a rigid motion.
  double worst_factor = 1;
  std::vector<EdgeRatioEdge> worst;  // sorted by |log ratio|, largest first
};

// Ratios length_in_pose / length_in_reference over the unique edges E
// (#E by 2). Edges of zero reference length are skipped.
EdgeRatioStats edge_ratio_stats(const Eigen::MatrixXd& V_ref, const Eigen::MatrixXd& V_pose,
                                const Eigen::MatrixXi& E, int worst_count = 10);

}  // namespace gp
