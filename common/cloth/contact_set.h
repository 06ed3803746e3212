#pragma once
// The velocity-level contact constraints of one implicit step (Baraff & Witkin 1998, sec. 5.3,
// "constraint filtering"): which candidates of the body (step_contact.h) become constraints, the filter
// S that removes the constrained normal components (eq. 17), and the release rule that lets the
// cloth leave the body. The contact history (released, in contact) carries over between (sub)steps.
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cloth/step_contact.h"

namespace gp::cloth {

class ContactSet {
 public:
  // What carries over from one (sub)step to the next, per vertex (#V, or empty before the first).
  struct History {
    std::vector<char> released;    // the body pulled this vertex in the last (sub)step
    std::vector<char> in_contact;  // constrained in the last (sub)step and not released
  };

  // Forgets the history (another body).
  void clear_history();
  // This (sub)step's constraints from the body's candidates (step_contact.h, sorted here by vertex,
  // stably) for vertex_count vertices: free vertices only (free_id: #V, -1 for pinned), released
  // ones skipped, in ascending vertex order, at most two per vertex (the second made orthogonal to
  // the first). Returns how many.
  long gather(std::vector<VelocityConstraint>& candidates, int vertex_count, const Eigen::VectorXi& free_id);
  // After a solve of A sol = b (A lower triangle over the free dofs): the constraint force
  // h f_c = A sol - b on a constrained normal that points into the body by more than
  // release_fraction times the vertex's weight h m |g| releases it for the next (sub)step.
  // Returns how many were released.
  long update_released(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& sol, const Eigen::VectorXd& b,
                       const Eigen::VectorXd& masses, double gravity, double release_fraction, double h,
                       int vertex_count);

  // S v: removes the constrained normal components of v (3 #free).
  void filter(Eigen::VectorXd& v) const;
  // Sets the constrained normal components of sol (3 #free) to their prescribed velocities.
  void impose(Eigen::VectorXd& sol) const;

  bool empty() const { return constraints_.empty(); }
  size_t size() const { return constraints_.size(); }
  const VelocityConstraint& constraint(size_t k) const { return constraints_[k]; }
  int free_index(size_t k) const { return constraint_free_[k]; }  // free vertex index of constraint k

  const History& history() const { return history_; }
  void restore(History history) { history_ = std::move(history); }

 private:
  std::vector<VelocityConstraint> constraints_;
  std::vector<int> constraint_free_;
  History history_;
};

}  // namespace gp::cloth
