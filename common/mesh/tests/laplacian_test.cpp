#include <catch2/catch.hpp>

#include <cmath>

#include "mesh/heat_geodesics.h"
#include "mesh/laplacian.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "testing/test_meshes.h"

TEST_CASE("the cotangent Laplacian is symmetric, PSD, and kills affine functions on a flat grid", "[mesh]") {
  const gp::Mesh grid = gp::testing::make_grid(8, 6, 0.4, 0.3);
  const Eigen::SparseMatrix<double> L = gp::cotan_laplacian(grid.V, grid.F);
  CHECK((Eigen::MatrixXd(L) - Eigen::MatrixXd(L).transpose()).cwiseAbs().maxCoeff() < 1e-12);
  // Rows sum to zero (constants are in the kernel).
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(grid.V.rows());
  CHECK((L * ones).cwiseAbs().maxCoeff() < 1e-12);
  // An affine function is harmonic at inner vertices.
  const Eigen::VectorXd f = 2.0 * grid.V.col(0) - 3.0 * grid.V.col(2) + Eigen::VectorXd::Constant(grid.V.rows(), 0.5);
  const Eigen::VectorXd Lf = L * f;
  std::vector<char> boundary(static_cast<size_t>(grid.V.rows()), 0);
  for (const auto& loop : gp::boundary_loops(grid.F))
    for (int v : loop) boundary[static_cast<size_t>(v)] = 1;
  for (int v = 0; v < grid.V.rows(); ++v)
    if (!boundary[static_cast<size_t>(v)]) CHECK(std::abs(Lf[v]) < 1e-12);
  // PSD: the Dirichlet energy of any field is non-negative and 0.5 f^T L f of
  // the affine field is its gradient's squared norm times the area.
  const double area = gp::face_areas(grid.V, grid.F).sum();
  CHECK(0.5 * f.dot(L * f) == Approx(0.5 * (4.0 + 9.0) * area).epsilon(1e-9));
  CHECK(gp::lumped_mass(grid.V, grid.F).sum() == Approx(area).epsilon(1e-12));
}

TEST_CASE("heat geodesics: distance from an edge of a flat sheet and around a cylinder", "[mesh][geodesics]") {
  const gp::Mesh grid = gp::testing::make_grid(30, 30, 0.6, 0.6);
  std::vector<int> edge;
  for (int v = 0; v < grid.V.rows(); ++v)
    if (grid.V(v, 0) < 1e-12) edge.push_back(v);
  const Eigen::VectorXd d = gp::heat_geodesic_distance(grid.V, grid.F, edge);
  double worst = 0.0;
  for (int v = 0; v < grid.V.rows(); ++v) worst = std::max(worst, std::abs(d[v] - grid.V(v, 0)));
  INFO("worst error " << worst << " m over a 0.6 m sheet (edges 2 cm)");
  CHECK(worst < 0.01);
  // On a cylinder, from one rim: the distance is the height.
  const gp::Mesh cyl = gp::testing::make_open_cylinder(32, 20, 0.1, 0.5);
  std::vector<int> rim;
  for (int v = 0; v < cyl.V.rows(); ++v)
    if (cyl.V(v, 1) < 1e-12) rim.push_back(v);
  const Eigen::VectorXd h = gp::heat_geodesic_distance(cyl.V, cyl.F, rim);
  double err = 0.0;
  for (int v = 0; v < cyl.V.rows(); ++v) err = std::max(err, std::abs(h[v] - cyl.V(v, 1)));
  CHECK(err < 0.01);
  // A move of 1e-7 m moves the distances by about as little.
  gp::Mesh moved = cyl;
  moved.V.array() += 1e-7 * Eigen::ArrayXXd::Random(moved.V.rows(), 3);
  const Eigen::VectorXd h2 = gp::heat_geodesic_distance(moved.V, moved.F, rim);
  CHECK((h2 - h).cwiseAbs().maxCoeff() < 1e-5);
}
