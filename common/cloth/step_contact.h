#pragma once
// What one cloth (sub)step asks of the body it meets, in this order
// (cloth/README.md, "Contacts"): the cloth knows nothing of the body;
// adapt/body_contact.h answers for the fit, a test for the body it builds.
#include <vector>

#include <Eigen/Core>

namespace gp::cloth {

// A velocity constraint inside the implicit solve (Baraff & Witkin 1998, sec. 5.3, constraint
// filtering): n . v' = normal_velocity [m/s] for `vertex`, n unit and away from the body; the
// tangential motion stays free.
struct VelocityConstraint {
  int vertex = -1;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  double normal_velocity = 0.0;
  // False: the vertex is only near the body, held only if it was held in the previous (sub)step.
  bool touching = true;
};

class StepContact {
 public:
  virtual ~StepContact() = default;

  // Before the solve, at positions X (#V by 3) and step h [s]: appends the candidate constraints,
  // at most two per vertex and listed together (a crease's second normal orthogonal to the first).
  // Which become constraints, and their release: contact_set.h.
  virtual void constraints(const Eigen::MatrixXd& X, double h, std::vector<VelocityConstraint>& out) = 0;

  // After the solve (#V by 3 each): may move vertices out of the body; a moved free vertex gets the
  // velocity of its displacement, pinned vertices are restored.
  virtual void project(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) = 0;

  // After the projection, over the (sub)step [s_start, s_end] of the whole step: may move vertices
  // of X_end so that the cloth does not pass through the body on its way from X_start
  // (collision/continuous_contact.h); moved and pinned vertices as in project().
  virtual void sweep(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end) = 0;
};

}  // namespace gp::cloth
