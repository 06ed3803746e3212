#include "mesh/heat_geodesics.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>

#include "core/error.h"
#include "mesh/laplacian.h"
#include "mesh/topology.h"

namespace gp {

Eigen::VectorXd heat_geodesic_distance(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                       const std::vector<int>& sources) {
  const int n = static_cast<int>(V.rows());
  Eigen::VectorXd phi = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  if (sources.empty() || n == 0) return phi;
  // Vertices connected to a source.
  Eigen::VectorXi component;
  face_components(F, component);
  std::vector<char> reached(static_cast<size_t>(n), 0), source(static_cast<size_t>(n), 0);
  std::vector<char> live_component(static_cast<size_t>(F.rows()), 0);
  const auto vf = vertex_faces(F, n);
  for (int s : sources) {
    source[static_cast<size_t>(s)] = 1;
    for (int f : vf[static_cast<size_t>(s)]) live_component[static_cast<size_t>(component[f])] = 1;
  }
  for (int f = 0; f < F.rows(); ++f)
    if (live_component[static_cast<size_t>(component[f])])
      for (int k = 0; k < 3; ++k) reached[static_cast<size_t>(F(f, k))] = 1;

  const Eigen::SparseMatrix<double> L = cotan_laplacian(V, F);
  const Eigen::VectorXd M = lumped_mass(V, F);
  double h = 0.0;
  int edges = 0;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k, ++edges) h += (V.row(F(f, k)) - V.row(F(f, (k + 1) % 3))).norm();
  h /= std::max(1, edges);
  const double t = h * h;
  // Unreached vertices get unit mass and no coupling, so that the systems stay definite.
  Eigen::SparseMatrix<double> A = t * L;
  Eigen::VectorXd diag = M;
  for (int v = 0; v < n; ++v)
    if (!reached[static_cast<size_t>(v)] || !(diag[v] > 0.0)) diag[v] = 1.0;
  for (int v = 0; v < n; ++v) A.coeffRef(v, v) += diag[v];
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
  for (int s : sources) delta[s] = 1.0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> heat(A);
  if (heat.info() != Eigen::Success) throw NumericalError("heat geodesics: the heat step could not be factored");
  const Eigen::VectorXd u = heat.solve(delta);

  // X = -grad u / |grad u| per face; its integrated divergence per vertex.
  Eigen::VectorXd div = Eigen::VectorXd::Zero(n);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d p[3] = {V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))};
    const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]);
    const double area2 = normal.norm();
    if (!(area2 > 0.0)) continue;
    const Eigen::Vector3d nhat = normal / area2;
    Eigen::Vector3d grad = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) grad += u[F(f, k)] * nhat.cross(p[(k + 2) % 3] - p[(k + 1) % 3]);
    grad /= area2;
    const double g = grad.norm();
    if (!(g > 0.0)) continue;
    const Eigen::Vector3d X = -grad / g;
    for (int k = 0; k < 3; ++k) {
      // 1/2 (cot theta_1 (e_1 . X) + cot theta_2 (e_2 . X)) at vertex k.
      const Eigen::Vector3d e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
      auto cot = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.dot(b) / a.cross(b).norm(); };
      const double cot2 = cot(p[k] - p[(k + 2) % 3], p[(k + 1) % 3] - p[(k + 2) % 3]);  // angle at k+2, opposite e1
      const double cot1 = cot(p[k] - p[(k + 1) % 3], p[(k + 2) % 3] - p[(k + 1) % 3]);  // angle at k+1, opposite e2
      div[F(f, k)] += 0.5 * (cot2 * e1.dot(X) + cot1 * e2.dot(X));
    }
  }
  // L phi = -div with phi = 0 at the sources (L is the positive Laplacian).
  std::vector<int> index(static_cast<size_t>(n), -1);
  int m = 0;
  for (int v = 0; v < n; ++v)
    if (reached[static_cast<size_t>(v)] && !source[static_cast<size_t>(v)]) index[static_cast<size_t>(v)] = m++;
  std::vector<Eigen::Triplet<double>> trip;
  for (int c = 0; c < L.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it) {
      const int i = index[static_cast<size_t>(it.row())], j = index[static_cast<size_t>(c)];
      if (i >= 0 && j >= 0) trip.emplace_back(i, j, it.value());
    }
  Eigen::SparseMatrix<double> Lf(m, m);
  Lf.setFromTriplets(trip.begin(), trip.end());
  Eigen::VectorXd b(m);
  for (int v = 0; v < n; ++v)
    if (index[static_cast<size_t>(v)] >= 0) b[index[static_cast<size_t>(v)]] = -div[v];
  for (int v = 0; v < n; ++v) phi[v] = reached[static_cast<size_t>(v)] ? 0.0 : std::numeric_limits<double>::infinity();
  if (m > 0) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> poisson(Lf);
    if (poisson.info() != Eigen::Success) throw NumericalError("heat geodesics: the Poisson step could not be factored");
    const Eigen::VectorXd x = poisson.solve(b);
    for (int v = 0; v < n; ++v)
      if (index[static_cast<size_t>(v)] >= 0) phi[v] = x[index[static_cast<size_t>(v)]];
  }
  return phi;
}

}  // namespace gp
