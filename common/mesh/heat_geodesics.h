#pragma once
// Geodesic distance by the heat method (Crane, Weischedel and Wardetzky 2013, "Geodesics in
// heat"): heat diffused for t = h^2 (h the mean edge length), its normalized negative gradient
// integrated back by a Poisson solve. Smooth in the positions, unlike Dijkstra's edge-bound levels.
#include <vector>
#include <Eigen/Core>

namespace gp {

// Distance (metres) of every vertex of V (#V by 3), F (#F by 3) from the
// vertices `sources` (distance 0); vertices not connected to a source get
// +infinity. Throws NumericalError when a solve fails.
Eigen::VectorXd heat_geodesic_distance(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const std::vector<int>& sources);

}  // namespace gp
