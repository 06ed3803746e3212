#pragma once
// The cotangent Laplacian and the lumped mass matrix of a triangle mesh
// (Pinkall and Polthier 1993; Meyer et al. 2003 for the mass).
#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace gp {

// L, #V by #V, symmetric positive semidefinite (the negative of the
// Laplace-Beltrami operator, integrated): L_ij = -(cot a_ij + cot b_ij) / 2
// for an edge ij with opposite angles a_ij, b_ij, L_ii = -sum_j L_ij.
// V #V by 3, F #F by 3; faces of zero area contribute nothing.
Eigen::SparseMatrix<double> cotan_laplacian(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// Lumped (barycentric) mass: a third of the area of every face around each vertex, #V.
Eigen::VectorXd lumped_mass(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

}  // namespace gp
