#pragma once
// What one cloth step asks of the body it meets, in the order it asks
// (ClothSimulator::step, cloth/README.md "Contacts"): before the solve the
// candidate velocity constraints, after it the projection out of the body,
// then the continuous detection between the step's start and end. The cloth
// knows nothing of the body; adapt/body_contact.h answers for the fit, and a
// test answers with whatever body it builds. The three calls are made for
// every (sub)step, halved ones included, in this order.
#include <vector>

#include <Eigen/Core>

namespace gp::cloth {

// A velocity-level contact constraint inside the implicit solve (Baraff & Witkin 1998, sec. 5.3,
// "constraint filtering"): the solved velocity of `vertex` has normal component n . v' =
// normal_velocity [m/s] (n unit, pointing away from the body); its tangential motion stays free.
// Neighbours see the contact while their velocities are solved (cloth/README.md, "Contacts").
struct VelocityConstraint {
  int vertex = -1;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
  double normal_velocity = 0.0;
  // True when the vertex touches or penetrates (a new contact); false for a vertex merely near the
  // body, constrained only while in contact since the previous (sub)step (a released one can leave).
  bool touching = true;
};

class StepContact {
 public:
  virtual ~StepContact() = default;

  // Before the solve, at the positions X (#V by 3) and the (sub)step size h [s]: appends the
  // candidate constraints (at most two per vertex, listed together: a vertex in a crease is held
  // along both sides' normals, the second made orthogonal to the first; pinned vertices are
  // ignored). A candidate becomes a constraint when it touches, or when its vertex was constrained
  // in the previous (sub)step and not released; a constraint whose force pulled the cloth towards
  // the body is released (Baraff & Witkin's release rule), so the cloth can leave the body
  // (contact_set.h). None: the solve is unconstrained.
  virtual void constraints(const Eigen::MatrixXd& X, double h, std::vector<VelocityConstraint>& out) = 0;

  // After the solve, with the new positions and velocities (#V by 3): may move vertices out of the
  // body and change their velocities. A free vertex it moves gets the velocity of its displacement
  // over the step; pinned vertices are restored afterwards.
  virtual void project(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) = 0;

  // After the projection, with the positions X_start, X_end (#V by 3) at the start and end of the
  // (sub)step, which covers [s_start, s_end] of the whole step: may move vertices of X_end so that
  // the cloth does not pass through the body between them (collision/continuous_contact.h). Moved
  // free vertices get the velocity of their displacement; pinned vertices are restored.
  virtual void sweep(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end) = 0;
};

}  // namespace gp::cloth
