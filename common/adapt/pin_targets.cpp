#include "adapt/pin_targets.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace gp::adapt {
namespace {

// A target within this distance [m] below the clearance counts as at it, so
// that rounding never moves a target that was put there.
constexpr double kClearanceTolerance = 1e-6;

}  // namespace

void keep_off_body(Eigen::MatrixXd& targets, const collision::BodyCollider& collider, double clearance,
                   std::vector<int>& hints, PinClearanceStats& stats, int max_pushes) {
  if (targets.cols() != 3 || hints.size() != static_cast<size_t>(targets.rows())) {
    throw UsageError("pin targets must be #P by 3 with one hint each, got " + std::to_string(targets.rows()) + " by " +
                     std::to_string(targets.cols()) + " and " + std::to_string(hints.size()) + " hints");
  }
  if (!(clearance >= 0.0) || !std::isfinite(clearance)) {
    throw UsageError("the pin clearance must be finite and non-negative");
  }
  for (Eigen::Index k = 0; k < targets.rows(); ++k) {
    const Eigen::Vector3d start = targets.row(k).transpose();
    Eigen::Vector3d t = start;
    int& hint = hints[static_cast<size_t>(k)];
    for (int push = 0; push < max_pushes; ++push) {
      const collision::Proximity q = collider.query(t, hint);
      hint = q.face;
      if (q.face < 0) break;
      double usable = clearance;
      if (q.signed_distance < clearance - kClearanceTolerance) usable = std::min(clearance, 0.5 * collider.gap(q));
      if (!(q.signed_distance < usable - kClearanceTolerance)) break;
      if (push == 0 && (stats.pushed == 0 || q.signed_distance < stats.closest_before)) {
        stats.closest_before = q.signed_distance;
      }
      t = q.closest + usable * q.outward;
    }
    if (t == start) continue;
    ++stats.pushed;
    stats.largest_push = std::max(stats.largest_push, (t - start).norm());
    targets.row(k) = t.transpose();
  }
}

}  // namespace gp::adapt
