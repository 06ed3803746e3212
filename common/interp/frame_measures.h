#pragma once
// How well in-between frames keep the body's shape: edge lengths and enclosed
// volume against the two key poses of their transition, and the deviation of
// one method's frame from another's (linear baseline against nonlinear).
// Lengths are relative (dimensionless); volumes in cubic metres.
#include <vector>

#include <Eigen/Core>

namespace gp {

struct FrameMeasures {
  double volume = 0.0;           // signed enclosed volume [m^3]
  // Relative distance of the volume outside [min, max] of the two key poses'
  // volumes, divided by the larger key volume magnitude; 0 inside the range.
  double volume_excess = 0.0;
  double edge_ratio_min = 1.0;   // min over edges of length / reference-pose length
  double edge_ratio_max = 1.0;   // max over edges of the same
  // Per edge, the relative excursion outside the lengths in the two key poses,
  // max(l / max(l_a, l_b) - 1, 1 - l / min(l_a, l_b), 0); its max and mean.
  double edge_excess_max = 0.0;
  double edge_excess_mean = 0.0;
};

struct FrameDeviation {
  double edge_deviation_max = 0.0;   // max over edges of |l_x / l_y - 1|
  double edge_deviation_mean = 0.0;  // mean of the same
  double volume_error = 0.0;         // (vol_x - vol_y) / |vol_y|
  double vertex_distance_max = 0.0;  // max |x_v - y_v| [m]
};

class MotionMeasurer {
 public:
  // poses: #V by 3 each over the shared F; `reference` is the pose whose edge
  // lengths define edge ratios.
  MotionMeasurer(const std::vector<Eigen::MatrixXd>& poses, const Eigen::MatrixXi& F, int reference);

  // Frame V between key poses a and b.
  FrameMeasures measure(const Eigen::MatrixXd& V, int a, int b) const;
  // Deviation of frame V_x from frame V_y (same connectivity).
  FrameDeviation compare(const Eigen::MatrixXd& V_x, const Eigen::MatrixXd& V_y) const;

  double key_volume(int pose) const { return volumes_.at(static_cast<size_t>(pose)); }
  const Eigen::VectorXd& key_edge_lengths(int pose) const { return lengths_.at(static_cast<size_t>(pose)); }

 private:
  Eigen::MatrixXi F_;
  Eigen::MatrixXi E_;
  int reference_;
  std::vector<Eigen::VectorXd> lengths_;
  std::vector<double> volumes_;
};

}  // namespace gp
