#include "adapt/key_pose_report.h"

#include "collision/crossings.h"

namespace gp::adapt {

OrderedJson key_pose_json(const KeyPoseResult& k, const std::string& mesh, const std::vector<std::string>* failures,
                          double area_fraction_torn) {
  const bool checked = failures != nullptr;
  OrderedJson held_cloth = OrderedJson::array();
  for (const HeldCloth& h : k.held_cloth) held_cloth.push_back(to_json(h));
  OrderedJson j;
  j["key"] = k.key;
  j["pose"] = k.pose;
  if (k.frame >= 0) {  // an in-between frame
    j["frame"] = k.frame;
    j["transition"] = k.transition;
    j["t"] = k.t;
  }
  j["mesh"] = mesh;
  if (checked) {
    j["verdict"] = failures->empty() ? "pass" : "fail";
    j["failures"] = *failures;
  }
  j["max_stretch"] = k.max_stretch;
  j["p99_stretch"] = k.p99_stretch;
  j["mean_stretch"] = k.mean_stretch;
  j["area_fraction_above_limit"] = k.area_fraction_above;
  if (checked) j["area_fraction_torn"] = area_fraction_torn;
  j["deepest_penetration_m"] = k.deepest_penetration;
  if (checked) {
    j["crossings"] = collision::to_json(k.crossings);
  } else {
    j["rest_area_growth"] = k.rest_area_growth;
    j["rest_area_change_last_window"] = k.rest_area_change;
  }
  j["steps"] = k.steps;
  j["settle_steps"] = k.settle_steps;
  j["settled"] = k.settled;
  if (k.solved_static) {
    j["newton_iterations"] = k.newton_iterations;
    j["force_residual"] = k.force_residual;
    j["force_residuals"] = k.force_residuals;
  }
  if (!checked) {
    j["max_speed_m_per_s"] = k.max_speed;
    j["max_net_speed_m_per_s"] = k.max_net_speed;
    j["crossings"] = collision::to_json(k.crossings);
  }
  j["held_by_body"] = k.held;
  j["held_cloth"] = held_cloth;
  return j;
}

}  // namespace gp::adapt
