#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "linalg/cholmod_serial_openmp.h"
#include "linalg/cholmod_solver.h"

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// 2D grid Laplacian (5-point stencil, nx*ny unknowns) plus `shift` on the
// diagonal: SPD for shift > 0, singular for shift = 0, indefinite below.
SparseMatrix grid_laplacian(int nx, int ny, double shift) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [nx](int i, int j) { return j * nx + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      double diag = shift;
      const int neighbours[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
      for (const auto& nb : neighbours) {
        if (nb[0] < 0 || nb[0] >= nx || nb[1] < 0 || nb[1] >= ny) continue;
        t.emplace_back(id(i, j), id(nb[0], nb[1]), -1.0);
        diag += 1.0;
      }
      t.emplace_back(id(i, j), id(i, j), diag);
    }
  SparseMatrix A(nx * ny, nx * ny);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

Eigen::MatrixXd deterministic_rhs(int n, int k) {
  Eigen::MatrixXd B(n, k);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) B(i, j) = std::sin(0.37 * i + 1.3 * j) + 0.1 * j;
  return B;
}

double relative_residual(const SparseMatrix& A, const Eigen::MatrixXd& X, const Eigen::MatrixXd& B) {
  return (A * X - B).norm() / B.norm();
}

}  // namespace

TEST_CASE("supernodal and simplicial factors solve a grid Laplacian with several right-hand sides",
          "[linalg]") {
  const SparseMatrix A = grid_laplacian(40, 30, 1e-2);
  const Eigen::MatrixXd B = deterministic_rhs(A.rows(), 3);
  for (auto method : {gp::CholmodOptions::Method::supernodal, gp::CholmodOptions::Method::simplicial}) {
    gp::CholmodSolver solver({method});
    solver.compute(A);
    REQUIRE(solver.factorized());
    CHECK(solver.size() == 1200);
    CHECK(solver.factor_nonzeros() >= A.nonZeros() / 2);
    const Eigen::MatrixXd X = solver.solve(B);
    CHECK(relative_residual(A, X, B) < 1e-10);
    // One column at a time gives the same answer as the block solve.
    for (int j = 0; j < 3; ++j) {
      const Eigen::MatrixXd xj = solver.solve(B.col(j));
      CHECK((xj - X.col(j)).norm() <= 1e-12 * X.col(j).norm());
    }
  }
}

TEST_CASE("upper-triangle entries are ignored and a lower-only matrix gives the same result",
          "[linalg]") {
  const SparseMatrix A = grid_laplacian(12, 9, 0.5);
  SparseMatrix lower = A.triangularView<Eigen::Lower>();
  const Eigen::MatrixXd B = deterministic_rhs(A.rows(), 2);
  gp::CholmodSolver full, low;
  full.compute(A);
  low.compute(lower);
  CHECK((full.solve(B) - low.solve(B)).norm() < 1e-12 * full.solve(B).norm());
}

TEST_CASE("refactorizing with the same pattern reuses the symbolic analysis", "[linalg]") {
  gp::CholmodSolver solver;
  const SparseMatrix A1 = grid_laplacian(20, 20, 1.0);
  solver.analyze(A1);
  solver.factorize(A1);
  CHECK(solver.analyze_count() == 1);
  const SparseMatrix A2 = grid_laplacian(20, 20, 3.0);  // same pattern, new values
  solver.factorize(A2);
  CHECK(solver.analyze_count() == 1);
  const Eigen::MatrixXd B = deterministic_rhs(400, 3);
  CHECK(relative_residual(A2, solver.solve(B), B) < 1e-12);

  // A different pattern triggers a new analysis automatically.
  const SparseMatrix A3 = grid_laplacian(10, 40, 1.0);
  solver.factorize(A3);
  CHECK(solver.analyze_count() == 2);
  CHECK(relative_residual(A3, solver.solve(B), B) < 1e-12);
}

TEST_CASE("matrices that are not positive definite raise NumericalError", "[linalg]") {
  for (auto method : {gp::CholmodOptions::Method::supernodal, gp::CholmodOptions::Method::simplicial}) {
    gp::CholmodSolver solver({method});
    // Singular (pure Neumann Laplacian) and indefinite.
    CHECK_THROWS_AS(solver.compute(grid_laplacian(15, 15, 0.0)), gp::NumericalError);
    CHECK_FALSE(solver.factorized());
    CHECK_THROWS_AS(solver.compute(grid_laplacian(15, 15, -0.5)), gp::NumericalError);
    // A negative diagonal entry names where the factorization failed.
    SparseMatrix A = grid_laplacian(5, 5, 1.0);
    A.coeffRef(7, 7) = -4.0;
    try {
      solver.compute(A);
      FAIL("no error for an indefinite matrix");
    } catch (const gp::NumericalError& e) {
      CHECK(std::string(e.what()).find("not positive definite") != std::string::npos);
      // In the input's numbering, whatever order the factor eliminates in.
      CHECK(std::string(e.what()).find("original row 7)") != std::string::npos);
    }
    // After a failure the same solver recovers with a good matrix.
    const SparseMatrix good = grid_laplacian(15, 15, 0.1);
    solver.compute(good);
    const Eigen::MatrixXd B = deterministic_rhs(225, 1);
    CHECK(relative_residual(good, solver.solve(B), B) < 1e-12);
  }
}

TEST_CASE("non-finite entries, wrong shapes and out-of-order calls are reported", "[linalg]") {
  gp::CholmodSolver solver;
  CHECK_THROWS_AS(solver.solve(Eigen::MatrixXd::Ones(4, 1)), gp::UsageError);
  SparseMatrix A = grid_laplacian(6, 6, 1.0);
  A.coeffRef(3, 3) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_AS(solver.compute(A), gp::NumericalError);
  CHECK_THROWS_AS(solver.compute(SparseMatrix(3, 4)), gp::UsageError);
  CHECK_THROWS_AS(solver.compute(SparseMatrix(0, 0)), gp::UsageError);
  solver.compute(grid_laplacian(6, 6, 1.0));
  CHECK_THROWS_AS(solver.solve(Eigen::MatrixXd::Ones(35, 1)), gp::UsageError);
}

TEST_CASE("huge and tiny scales factor to the same relative accuracy", "[linalg]") {
  const SparseMatrix A = grid_laplacian(25, 25, 0.05);
  const Eigen::MatrixXd B = deterministic_rhs(625, 3);
  for (double scale : {1e-12, 1.0, 1e12}) {
    gp::CholmodSolver solver;
    const SparseMatrix As = A * scale;
    solver.compute(As);
    CHECK(relative_residual(As, solver.solve(B), B) < 1e-10);
  }
}

TEST_CASE("a refactorized supernodal factor with new values solves the new matrix", "[linalg]") {
  // The supernodal factor is of the permuted matrix, refilled from A's
  // entries at every factorization: new values in the same pattern, with
  // entries above the diagonal present or not.
  const SparseMatrix A = grid_laplacian(40, 40, 0.1);
  const Eigen::MatrixXd B = deterministic_rhs(1600, 2);
  gp::CholmodSolver solver;
  solver.compute(A);
  REQUIRE(solver.is_supernodal());
  CHECK(relative_residual(A, solver.solve(B), B) < 1e-12);
  SparseMatrix A2 = A;
  for (int k = 0; k < A2.outerSize(); ++k) {
    for (SparseMatrix::InnerIterator it(A2, k); it; ++it) it.valueRef() *= it.row() == it.col() ? 1.5 + 0.01 * k : 0.9;
  }
  SparseMatrix lower = A2.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  for (const SparseMatrix* M : {&A2, &lower}) {
    solver.factorize(*M);
    CHECK(solver.analyze_count() == 1);
    CHECK(relative_residual(A2, solver.solve(B), B) < 1e-12);
  }
}

TEST_CASE("repeated solves give bit-identical results", "[linalg]") {
  const SparseMatrix A = grid_laplacian(30, 30, 0.2);
  const Eigen::MatrixXd B = deterministic_rhs(900, 3);
  gp::CholmodSolver solver;
  solver.compute(A);
  Eigen::MatrixXd X1, X2;
  solver.solve(B, X1);
  solver.solve(B, X2);
  CHECK(X1 == X2);
  gp::CholmodSolver other;
  other.compute(A);
  CHECK(other.solve(B) == X1);
}

TEST_CASE("a moved solver keeps its factor and the source stays usable", "[linalg]") {
  const SparseMatrix A = grid_laplacian(10, 10, 0.3);
  const Eigen::MatrixXd B = deterministic_rhs(100, 3);
  gp::CholmodSolver first;
  first.compute(A);
  gp::CholmodSolver second(std::move(first));
  CHECK(second.factorized());
  CHECK(relative_residual(A, second.solve(B), B) < 1e-12);
  CHECK_FALSE(first.factorized());  // NOLINT(bugprone-use-after-move): documented state
  CHECK_THROWS_AS(first.solve(B), gp::UsageError);
  first.compute(A);
  CHECK(relative_residual(A, first.solve(B), B) < 1e-12);
}

TEST_CASE("CHOLMOD's parallel regions run on the calling thread and start no thread", "[linalg]") {
  // Threads of this process (Linux): an OpenMP runtime would start its team
  // on the first region that asks for one and keep it.
  auto thread_count = [] {
    std::error_code error;
    long count = 0;
    for (std::filesystem::directory_iterator it("/proc/self/task", error), end; !error && it != end; it.increment(error))
      ++count;
    return count;
  };
  const long threads_before = thread_count();
  if (threads_before == 0) WARN("skipped the thread count: /proc/self/task is not readable");
  // 150 x 150 grid: supernodes far above the sizes (1,024 entries, 64
  // columns, 128 rows) at which CHOLMOD's loops ask for a team of four.
  const SparseMatrix A = grid_laplacian(150, 150, 0.01);
  const long regions_before = gp::cholmod_openmp_regions();
  gp::CholmodSolver solver;
  solver.compute(A);
  REQUIRE(solver.is_supernodal());
  const long regions = gp::cholmod_openmp_regions() - regions_before;
  // 13,660 regions here: several per supernode and per descendant update.
  CHECK(regions > 1000);
  if (threads_before > 0) CHECK(thread_count() == threads_before);
  const Eigen::MatrixXd B = deterministic_rhs(A.rows(), 2);
  CHECK(relative_residual(A, solver.solve(B), B) < 1e-10);
}
