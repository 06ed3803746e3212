#include "adapt/key_pose.h"

#include <cmath>
#include <cstdio>

#include "mesh/measures.h"

namespace gp::adapt {

void stretch_figures(const Eigen::VectorXd& s, const Eigen::VectorXd& area, double limit, KeyPoseResult& k) {
  const double total = area.sum();
  k.p99_stretch = area_weighted_percentile(s, area, 0.99);
  k.max_stretch = s.size() ? s.maxCoeff() : 0.0;
  k.mean_stretch = total > 0.0 ? s.dot(area) / total : 0.0;
  double above = 0.0;
  for (Eigen::Index f = 0; f < s.size(); ++f) {
    if (s(f) > limit) above += area(f);
  }
  k.area_fraction_above = total > 0.0 ? above / total : 0.0;
  k.face_max_stretch = s;
  k.face_rest_area = area;
}

double area_fraction_above(const KeyPoseResult& k, double stretch) {
  const double total = k.face_rest_area.sum();
  double above = 0.0;
  for (Eigen::Index f = 0; f < k.face_max_stretch.size() && f < k.face_rest_area.size(); ++f)
    if (k.face_max_stretch(f) > stretch) above += k.face_rest_area(f);
  return total > 0.0 ? above / total : 0.0;
}

std::vector<std::string> stretch_failures(const KeyPoseResult& k, double delta, const FitCriteria& criteria) {
  std::vector<std::string> failures;
  char line[200];
  const double limit = 1.0 + delta;
  if (k.area_fraction_above >= criteria.max_area_above) {
    std::snprintf(line, sizeof(line), "%.2f %% of the area stretched above %.3f (at most %.2f %%)",
                  100.0 * k.area_fraction_above, limit, 100.0 * criteria.max_area_above);
    failures.push_back(line);
  }
  if (k.p99_stretch > limit + criteria.p99_margin) {
    std::snprintf(line, sizeof(line), "p99 stretch %.4f above %.4f", k.p99_stretch, limit + criteria.p99_margin);
    failures.push_back(line);
  }
  return failures;
}

std::vector<std::string> check_pose(const KeyPoseResult& k, double delta, const FitCriteria& criteria) {
  std::vector<std::string> failures = stretch_failures(k, delta, criteria);
  char line[400];
  const double torn = area_fraction_above(k, criteria.tear_stretch);
  if (torn > criteria.max_torn_area) {
    std::snprintf(line, sizeof(line), "%.2f %% of the area stretched beyond %.2f, where cloth tears (at most %.2f %%)",
                  100.0 * torn, criteria.tear_stretch, 100.0 * criteria.max_torn_area);
    failures.push_back(line);
  }
  if (k.deepest_penetration > criteria.max_penetration) {
    std::snprintf(line, sizeof(line), "a cloth vertex %.1f mm inside the body (at most %.1f mm)",
                  1e3 * k.deepest_penetration, 1e3 * criteria.max_penetration);
    failures.push_back(line);
  }
  if (k.crossings.crossings() > criteria.max_crossings) {
    std::snprintf(line, sizeof(line), "the body passes through the cloth (%ld edge/triangle crossings, at most %ld)",
                  k.crossings.crossings(), criteria.max_crossings);
    failures.push_back(line);
  }
  if (k.held && !k.held_cloth.empty()) {
    const HeldCloth& h = k.held_cloth.front();
    char gap[64] = "no other body part in front of it";
    if (std::isfinite(h.gap)) std::snprintf(gap, sizeof(gap), "a gap of %.1f mm", 1e3 * h.gap);
    std::snprintf(line, sizeof(line),
                  "the body holds the cloth at %s (%.3f, %.3f, %.3f) m, %s: %zu faces stretched up to %.2f, no "
                  "better after %d settling steps",
                  h.region.c_str(), h.position.x(), h.position.y(), h.position.z(), gap, h.faces.size(),
                  h.max_stretch, k.settle_steps);
    failures.push_back(line);
  }
  if (criteria.require_settled && !k.settled) {
    std::snprintf(line, sizeof(line),
                  "the cloth did not settle within %d steps (largest net vertex speed %.3f m/s over the last check)",
                  k.settle_steps, k.max_net_speed);
    failures.push_back(line);
  }
  return failures;
}

OrderedJson to_json(const HeldCloth& h) {
  return {{"region", h.region},
          {"body_vertex", h.body_vertex},
          {"position_m", {h.position.x(), h.position.y(), h.position.z()}},
          {"gap_mm", std::isfinite(h.gap) ? OrderedJson(1e3 * h.gap) : OrderedJson(nullptr)},
          {"max_stretch", h.max_stretch},
          {"face_count", h.faces.size()},
          {"faces", h.faces}};
}

}  // namespace gp::adapt
