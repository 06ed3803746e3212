#pragma once
// Checks the generated body must pass: a closed, oriented 2-manifold of one
// genus-0 component (its self-intersection test is geometry/self_intersections.h).
#include <Eigen/Core>
#include <string>

namespace gp {

// Throws GeometryError naming `what` unless F (#F by 3) has no boundary edge,
// every edge in exactly two faces (consistently oriented), a single
// component and Euler characteristic 2.
void check_closed_genus0(const Eigen::MatrixXi& F, const std::string& what);

}  // namespace gp
