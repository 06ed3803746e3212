#include "interp/frame_measures.h"

#include <algorithm>
#include <cmath>

#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {

MotionMeasurer::MotionMeasurer(const std::vector<Eigen::MatrixXd>& poses, const Eigen::MatrixXi& F,
                               int reference)
    : F_(F), E_(unique_edges(F)), reference_(reference) {
  for (const Eigen::MatrixXd& V : poses) {
    lengths_.push_back(edge_lengths(V, E_));
    volumes_.push_back(signed_volume(V, F_));
  }
}

FrameMeasures MotionMeasurer::measure(const Eigen::MatrixXd& V, int a, int b) const {
  FrameMeasures m;
  m.volume = signed_volume(V, F_);
  const double va = volumes_.at(static_cast<size_t>(a)), vb = volumes_.at(static_cast<size_t>(b));
  const double vscale = std::max(std::abs(va), std::abs(vb));
  if (vscale > 0.0)
    m.volume_excess = std::max({0.0, m.volume - std::max(va, vb), std::min(va, vb) - m.volume}) / vscale;

  const Eigen::VectorXd l = edge_lengths(V, E_);
  const Eigen::VectorXd& l_ref = lengths_.at(static_cast<size_t>(reference_));
  const Eigen::VectorXd& l_a = lengths_.at(static_cast<size_t>(a));
  const Eigen::VectorXd& l_b = lengths_.at(static_cast<size_t>(b));
  m.edge_ratio_min = 1e300;
  m.edge_ratio_max = 0.0;
  double sum = 0.0;
  int counted = 0;
  for (Eigen::Index e = 0; e < l.size(); ++e) {
    if (l_ref(e) > 0.0) {
      const double r = l(e) / l_ref(e);
      m.edge_ratio_min = std::min(m.edge_ratio_min, r);
      m.edge_ratio_max = std::max(m.edge_ratio_max, r);
    }
    const double lo = std::min(l_a(e), l_b(e)), hi = std::max(l_a(e), l_b(e));
    if (lo <= 0.0) continue;
    const double excess = std::max({0.0, l(e) / hi - 1.0, 1.0 - l(e) / lo});
    m.edge_excess_max = std::max(m.edge_excess_max, excess);
    sum += excess;
    ++counted;
  }
  if (m.edge_ratio_max == 0.0) m.edge_ratio_min = 0.0;
  m.edge_excess_mean = counted > 0 ? sum / counted : 0.0;
  return m;
}

FrameDeviation MotionMeasurer::compare(const Eigen::MatrixXd& V_x, const Eigen::MatrixXd& V_y) const {
  FrameDeviation d;
  const Eigen::VectorXd lx = edge_lengths(V_x, E_), ly = edge_lengths(V_y, E_);
  double sum = 0.0;
  int counted = 0;
  for (Eigen::Index e = 0; e < lx.size(); ++e) {
    if (ly(e) <= 0.0) continue;
    const double dev = std::abs(lx(e) / ly(e) - 1.0);
    d.edge_deviation_max = std::max(d.edge_deviation_max, dev);
    sum += dev;
    ++counted;
  }
  d.edge_deviation_mean = counted > 0 ? sum / counted : 0.0;
  const double vy = signed_volume(V_y, F_);
  if (vy != 0.0) d.volume_error = (signed_volume(V_x, F_) - vy) / std::abs(vy);
  d.vertex_distance_max = (V_x - V_y).rowwise().norm().maxCoeff();
  return d;
}

}  // namespace gp
