#include "cloth/contact_set.h"

#include <algorithm>
#include <cmath>

namespace gp::cloth {
namespace {

// A vertex's second contact direction is dropped when it is within about 17
// degrees of the first (the two constraints would be nearly the same).
constexpr double kSmallestCreaseSine = 0.3;

}  // namespace

void ContactSet::clear_history() {
  history_.released.clear();
  history_.in_contact.clear();
}

long ContactSet::gather(std::vector<VelocityConstraint>& candidates, int vertex_count, const Eigen::VectorXi& free_id) {
  constraints_.clear();
  constraint_free_.clear();
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const VelocityConstraint& a, const VelocityConstraint& c) { return a.vertex < c.vertex; });
  std::vector<char>& released = history_.released;
  std::vector<char>& in_contact = history_.in_contact;
  if (released.size() != static_cast<size_t>(vertex_count)) released.assign(vertex_count, 0);
  if (in_contact.size() != static_cast<size_t>(vertex_count)) in_contact.assign(vertex_count, 0);
  for (const VelocityConstraint& c : candidates) {
    if (c.vertex < 0 || c.vertex >= vertex_count) continue;
    const int fi = free_id(c.vertex);
    const double len = c.normal.norm();
    if (fi < 0 || !(len > 0.0) || !std::isfinite(c.normal_velocity)) continue;
    if (released[c.vertex] || !(c.touching || in_contact[c.vertex])) continue;
    VelocityConstraint k = c;
    k.normal /= len;
    const bool second = !constraints_.empty() && constraints_.back().vertex == c.vertex;
    if (second) {
      // Two directions of one vertex (a crease, Baraff & Witkin 1998, sec.
      // 5.3): the second normal is made orthogonal to the first, and its
      // prescribed speed follows from both, so that n1.v' = a1 and n2.v' = a2
      // hold together: n2' = (n2 - d n1) / s, a2' = (a2 - d a1) / s with
      // d = n1.n2, s = |n2 - d n1|. Nearly parallel ones add nothing.
      if (constraints_.size() >= 2 && constraints_[constraints_.size() - 2].vertex == c.vertex) continue;
      const VelocityConstraint& first = constraints_.back();
      const double d = first.normal.dot(k.normal);
      const Eigen::Vector3d perpendicular = k.normal - d * first.normal;
      const double sine = perpendicular.norm();
      if (!(sine > kSmallestCreaseSine)) continue;
      k.normal = perpendicular / sine;
      k.normal_velocity = (c.normal_velocity - d * first.normal_velocity) / sine;
    }
    constraints_.push_back(k);
    constraint_free_.push_back(fi);
  }
  return static_cast<long>(constraints_.size());
}

long ContactSet::update_released(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& sol,
                                 const Eigen::VectorXd& b, const Eigen::VectorXd& masses, double gravity,
                                 double release_fraction, double h, int vertex_count) {
  std::vector<char>& released = history_.released;
  std::vector<char>& in_contact = history_.in_contact;
  if (released.size() != static_cast<size_t>(vertex_count)) released.assign(vertex_count, 0);
  std::fill(released.begin(), released.end(), 0);
  in_contact.assign(vertex_count, 0);
  for (const VelocityConstraint& c : constraints_) in_contact[c.vertex] = 1;
  if (constraints_.empty()) return 0;
  const Eigen::VectorXd residual = A.selfadjointView<Eigen::Lower>() * sol - b;
  long count = 0;
  for (size_t k = 0; k < constraints_.size(); ++k) {
    const double threshold = release_fraction * h * masses(constraints_[k].vertex) * gravity;
    if (constraints_[k].normal.dot(residual.segment<3>(3 * constraint_free_[k])) < -threshold) {
      released[constraints_[k].vertex] = 1;
      in_contact[constraints_[k].vertex] = 0;
      ++count;
    }
  }
  return count;
}

void ContactSet::filter(Eigen::VectorXd& v) const {
  for (size_t k = 0; k < constraints_.size(); ++k) {
    const Eigen::Vector3d& n = constraints_[k].normal;
    auto seg = v.segment<3>(3 * constraint_free_[k]);
    seg -= n * n.dot(seg);
  }
}

void ContactSet::impose(Eigen::VectorXd& sol) const {
  for (size_t k = 0; k < constraints_.size(); ++k) {
    const Eigen::Vector3d& n = constraints_[k].normal;
    auto seg = sol.segment<3>(3 * constraint_free_[k]);
    seg += n * (constraints_[k].normal_velocity - n.dot(seg));
  }
}

}  // namespace gp::cloth
