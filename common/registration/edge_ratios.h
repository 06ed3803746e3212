#pragma once
// Registration quality between two poses of one mesh: how much every edge
// changes length. Skin stretches locally (shoulders, armpits), so some change
// is expected; a vertex thrown far away by a registration error shows as a
// handful of edges with extreme ratios.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pose/pose_set.h"

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

// register-check's default limit on the edge-length factor between poses.
constexpr double kDefaultMaxEdgeRatio = 8.0;

// register-check's registration-error test for stages that take a pose set
// without it (a hand-written manifest): throws GeometryError, naming the pose,
// its worst edge and `where`, when an edge of one of the poses `pose_ids`
// changes length against the reference pose by more than max_factor: spikes
// left undetected would be fitted into the rest shape by simulate-adapt.
void check_pose_edge_ratios(const PoseSet& poses, const std::vector<int>& pose_ids, double max_factor,
                            const std::string& where);

}  // namespace gp
