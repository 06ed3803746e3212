#include "interp/gradient_poisson.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <string>

#include <Eigen/SparseCore>

#include "core/error.h"
#include "interp/deformation_gradient.h"

namespace gp {

FaceEdges face_edges(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  FaceEdges E(F.rows(), 6);
  for (int f = 0; f < F.rows(); ++f) {
    const auto v0 = V.row(F(f, 0));
    E.block<1, 3>(f, 0) = V.row(F(f, 1)) - v0;
    E.block<1, 3>(f, 3) = V.row(F(f, 2)) - v0;
  }
  return E;
}

GradientPoissonSolver::GradientPoissonSolver(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                             CholmodOptions options)
    : F_(F), n_vertices_(static_cast<int>(V_rest.rows())), solver_(options) {
  const auto start = std::chrono::steady_clock::now();
  const int nf = static_cast<int>(F.rows());
  if (nf == 0) throw GeometryError("mesh has no triangles");

  // Components of the Laplacian's graph: vertices joined through faces (parts
  // touching at a single vertex are one component, unlike edge-connected faces).
  std::vector<int> parent(static_cast<size_t>(n_vertices_));
  for (int v = 0; v < n_vertices_; ++v) parent[static_cast<size_t>(v)] = v;
  auto find = [&](int v) {
    while (parent[static_cast<size_t>(v)] != v) {
      parent[static_cast<size_t>(v)] = parent[static_cast<size_t>(parent[static_cast<size_t>(v)])];
      v = parent[static_cast<size_t>(v)];
    }
    return v;
  };
  std::vector<char> used(static_cast<size_t>(n_vertices_), 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      used[static_cast<size_t>(F(f, k))] = 1;
      const int a = find(F(f, 0)), b = find(F(f, k));
      if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
    }
  // Number components by their lowest vertex id.
  vertex_component_ = Eigen::VectorXi::Constant(n_vertices_, -1);
  std::vector<int> root_component(static_cast<size_t>(n_vertices_), -1);
  n_components_ = 0;
  for (int v = 0; v < n_vertices_; ++v) {
    if (!used[static_cast<size_t>(v)]) continue;
    int& c = root_component[static_cast<size_t>(find(v))];
    if (c < 0) c = n_components_++;
    vertex_component_(v) = c;
  }
  std::vector<char> pinned_component(n_components_, 0);
  reduced_id_ = Eigen::VectorXi::Constant(n_vertices_, -1);
  int n_unknowns = 0;
  for (int v = 0; v < n_vertices_; ++v) {
    const int c = vertex_component_(v);
    if (c < 0) continue;
    if (!pinned_component[c]) {
      pinned_component[c] = 1;  // lowest id of the component stays at the origin
      continue;
    }
    reduced_id_(v) = n_unknowns++;
  }

  // Per-face weights A_f (E^T E)^-1 with E the rest edges; E^T E = [[a, b], [b, c]]
  // has determinant |r1 x r2|^2 = 4 A_f^2, so A_f M_f = adj(E^T E) / (4 A_f).
  const double tiny = degenerate_double_area(V_rest);
  weights_.resize(nf, 3);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(nf) * 9);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d r1 = (V_rest.row(F(f, 1)) - V_rest.row(F(f, 0))).transpose();
    const Eigen::Vector3d r2 = (V_rest.row(F(f, 2)) - V_rest.row(F(f, 0))).transpose();
    const double area2 = r1.cross(r2).norm();
    if (!(area2 > tiny))
      throw GeometryError("degenerate triangle in the rest pose of the Poisson solve",
                          "face " + std::to_string(f));
    const double a = r1.squaredNorm(), b = r1.dot(r2), c = r2.squaredNorm();
    const double scale = 1.0 / (2.0 * area2);  // 1 / (4 A_f)
    const double m11 = c * scale, m12 = -b * scale, m22 = a * scale;
    weights_.row(f) << m11, m12, m22;
    // C_f^T W C_f with C_f = [[-1, 1, 0], [-1, 0, 1]].
    const double local[3][3] = {{m11 + 2 * m12 + m22, -m11 - m12, -m12 - m22},
                                {-m11 - m12, m11, m12},
                                {-m12 - m22, m12, m22}};
    for (int i = 0; i < 3; ++i) {
      const int ri = reduced_id_(F(f, i));
      if (ri < 0) continue;
      for (int j = 0; j < 3; ++j) {
        const int rj = reduced_id_(F(f, j));
        if (rj >= 0 && rj <= ri) triplets.emplace_back(ri, rj, local[i][j]);
      }
    }
  }
  if (n_unknowns > 0) {
    Eigen::SparseMatrix<double> L(n_unknowns, n_unknowns);
    L.setFromTriplets(triplets.begin(), triplets.end());
    L.makeCompressed();
    solver_.compute(L);
  }
  rhs_.resize(n_unknowns, 3);
  factorization_seconds_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void GradientPoissonSolver::solve(const FaceEdges& target, Eigen::MatrixXd& V_out) {
  if (target.rows() != F_.rows())
    throw UsageError("target edges have " + std::to_string(target.rows()) + " rows for " +
                     std::to_string(F_.rows()) + " faces");
  V_out.setZero(n_vertices_, 3);
  if (rhs_.rows() == 0) return;
  rhs_.setZero();
  for (int f = 0; f < F_.rows(); ++f) {
    const double m11 = weights_(f, 0), m12 = weights_(f, 1), m22 = weights_(f, 2);
    const Eigen::Vector3d e1 = target.block<1, 3>(f, 0).transpose();
    const Eigen::Vector3d e2 = target.block<1, 3>(f, 3).transpose();
    // b += C_f^T (A_f M_f) T_f^T: corner 1 gets g1, corner 2 gets g2, corner 0 -(g1 + g2).
    const Eigen::Vector3d g1 = m11 * e1 + m12 * e2;
    const Eigen::Vector3d g2 = m12 * e1 + m22 * e2;
    const int r0 = reduced_id_(F_(f, 0)), r1 = reduced_id_(F_(f, 1)), r2 = reduced_id_(F_(f, 2));
    if (r0 >= 0) rhs_.row(r0) -= (g1 + g2).transpose();
    if (r1 >= 0) rhs_.row(r1) += g1.transpose();
    if (r2 >= 0) rhs_.row(r2) += g2.transpose();
  }
  solver_.solve(rhs_, x_);
  for (int v = 0; v < n_vertices_; ++v)
    if (reduced_id_(v) >= 0) V_out.row(v) = x_.row(reduced_id_(v));
}

}  // namespace gp
