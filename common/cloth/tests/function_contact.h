#pragma once
// A body for tests that build their own (cloth/step_contact.h): each of the step's three calls runs
// its function, or does nothing where that is empty.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "cloth/step_contact.h"

namespace gp::cloth::testing {

struct FunctionContact : StepContact {
  std::function<void(const Eigen::MatrixXd& X, double h, std::vector<VelocityConstraint>& out)> on_constraints;
  std::function<void(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel)> on_project;
  std::function<void(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end)> on_sweep;

  void constraints(const Eigen::MatrixXd& X, double h, std::vector<VelocityConstraint>& out) override {
    if (on_constraints) on_constraints(X, h, out);
  }
  void project(Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) override {
    if (on_project) on_project(X, Vel);
  }
  void sweep(const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start, double s_end) override {
    if (on_sweep) on_sweep(X_start, X_end, s_start, s_end);
  }
};

}  // namespace gp::cloth::testing
