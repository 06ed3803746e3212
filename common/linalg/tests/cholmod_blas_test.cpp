#include <catch2/catch.hpp>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "linalg/cholmod_blas.h"
#include "linalg/cholmod_solver.h"

// The project's dense kernels behind CHOLMOD (cholmod_blas.cpp): each BLAS
// routine against a plain triple loop, over every flag, with leading
// dimensions larger than the matrices and zero sizes; and CHOLMOD's
// supernodal factorization calling them.

extern "C" {
void dgemm_(const char*, const char*, const int*, const int*, const int*, const double*, const double*, const int*,
            const double*, const int*, const double*, double*, const int*);
void dsyrk_(const char*, const char*, const int*, const int*, const double*, const double*, const int*,
            const double*, double*, const int*);
void dtrsm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*,
            const double*, const int*, double*, const int*);
void dtrsv_(const char*, const char*, const char*, const int*, const double*, const int*, double*, const int*);
void dgemv_(const char*, const int*, const int*, const double*, const double*, const int*, const double*,
            const int*, const double*, double*, const int*);
void dpotrf_(const char*, const int*, double*, const int*, int*);
}

namespace {

// A column-major matrix stored with a leading dimension `ld` >= rows, the
// padding filled with a value that must never be read into a result.
struct Stored {
  int rows, cols, ld;
  std::vector<double> data;
  Stored(int r, int c, int pad, std::mt19937_64& rng) : rows(r), cols(c), ld(r + pad), data(ld * std::max(c, 1)) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double& x : data) x = 1e30;
    for (int j = 0; j < c; ++j)
      for (int i = 0; i < r; ++i) data[j * ld + i] = u(rng);
  }
  Eigen::MatrixXd dense() const {
    Eigen::MatrixXd m(rows, cols);
    for (int j = 0; j < cols; ++j)
      for (int i = 0; i < rows; ++i) m(i, j) = data[j * ld + i];
    return m;
  }
};

Eigen::MatrixXd op(const Eigen::MatrixXd& m, char t) { return t == 'N' ? m : Eigen::MatrixXd(m.transpose()); }

}  // namespace

TEST_CASE("dgemm matches the product for every transpose, with padding and beta", "[linalg][blas]") {
  std::mt19937_64 rng(1);
  for (char ta : {'N', 'T', 'C'})
    for (char tb : {'N', 'T'})
      for (auto [m, n, k] : {std::tuple{5, 3, 4}, std::tuple{17, 9, 33}, std::tuple{1, 1, 1}, std::tuple{4, 6, 0}}) {
        Stored A(ta == 'N' ? m : k, ta == 'N' ? k : m, 2, rng), B(tb == 'N' ? k : n, tb == 'N' ? n : k, 1, rng),
            C(m, n, 3, rng);
        const double alpha = -0.7, beta = 0.3;
        const Eigen::MatrixXd want = alpha * op(A.dense(), ta == 'N' ? 'N' : 'T') * op(B.dense(), tb) + beta * C.dense();
        dgemm_(&ta, &tb, &m, &n, &k, &alpha, A.data.data(), &A.ld, B.data.data(), &B.ld, &beta, C.data.data(), &C.ld);
        INFO(ta << tb << " " << m << "x" << n << "x" << k);
        CHECK((C.dense() - want).norm() <= 1e-13 * (1.0 + want.norm()));
      }
  // beta = 0 never reads C (which may hold NaN).
  Stored A(3, 3, 0, rng), B(3, 3, 0, rng), C(3, 3, 0, rng);
  for (double& x : C.data) x = std::nan("");
  const int three = 3;
  const double one = 1.0, zero = 0.0;
  dgemm_("N", "N", &three, &three, &three, &one, A.data.data(), &three, B.data.data(), &three, &zero, C.data.data(),
         &three);
  CHECK(C.dense().allFinite());
}

TEST_CASE("dsyrk updates only its triangle", "[linalg][blas]") {
  std::mt19937_64 rng(2);
  for (char uplo : {'L', 'U'})
    for (char t : {'N', 'T'}) {
      const int n = 11, k = 7;
      Stored A(t == 'N' ? n : k, t == 'N' ? k : n, 2, rng), C(n, n, 1, rng);
      const Eigen::MatrixXd before = C.dense();
      const double alpha = 1.3, beta = -0.5;
      const Eigen::MatrixXd Ad = op(A.dense(), t);
      const Eigen::MatrixXd full = alpha * Ad * Ad.transpose() + beta * before;
      dsyrk_(&uplo, &t, &n, &k, &alpha, A.data.data(), &A.ld, &beta, C.data.data(), &C.ld);
      const Eigen::MatrixXd got = C.dense();
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const bool in = uplo == 'L' ? i >= j : i <= j;
          CHECK(got(i, j) == Approx(in ? full(i, j) : before(i, j)).margin(1e-13));
        }
    }
}

TEST_CASE("dtrsm and dtrsv solve with every side, triangle, transpose and diagonal", "[linalg][blas]") {
  std::mt19937_64 rng(3);
  for (char side : {'L', 'R'})
    for (char uplo : {'L', 'U'})
      for (char trans : {'N', 'T'})
        for (char diag : {'N', 'U'}) {
          const int m = 9, n = 4, na = side == 'L' ? m : n;
          Stored A(na, na, 2, rng), B(m, n, 1, rng);
          for (int i = 0; i < na; ++i) A.data[i * A.ld + i] += 4.0;  // well conditioned
          Eigen::MatrixXd T = A.dense();
          if (uplo == 'L')
            T = T.triangularView<Eigen::Lower>();
          else
            T = T.triangularView<Eigen::Upper>();
          if (diag == 'U') T.diagonal().setOnes();
          const Eigen::MatrixXd opT = op(T, trans);
          const double alpha = 0.5;
          const Eigen::MatrixXd B0 = B.dense();
          dtrsm_(&side, &uplo, &trans, &diag, &m, &n, &alpha, A.data.data(), &A.ld, B.data.data(), &B.ld);
          const Eigen::MatrixXd X = B.dense();
          const Eigen::MatrixXd back = side == 'L' ? Eigen::MatrixXd(opT * X) : Eigen::MatrixXd(X * opT);
          INFO(side << uplo << trans << diag);
          CHECK((back - alpha * B0).norm() <= 1e-12 * B0.norm());
          if (side == 'L') {
            Stored x(m, 1, 0, rng);
            const Eigen::VectorXd x0 = x.dense().col(0);
            const int inc = 1;
            dtrsv_(&uplo, &trans, &diag, &m, A.data.data(), &A.ld, x.data.data(), &inc);
            CHECK((opT * x.dense().col(0) - x0).norm() <= 1e-12 * x0.norm());
          }
        }
}

TEST_CASE("dgemv with both transposes and strided vectors", "[linalg][blas]") {
  std::mt19937_64 rng(4);
  for (char t : {'N', 'T'})
    for (int inc : {1, 2, -1}) {
      const int m = 7, n = 5, nx = t == 'N' ? n : m, ny = t == 'N' ? m : n;
      Stored A(m, n, 2, rng);
      std::vector<double> x(nx * std::abs(inc)), y(ny * std::abs(inc));
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      for (double& v : x) v = u(rng);
      for (double& v : y) v = u(rng);
      auto element = [&](const std::vector<double>& v, int count, int i) {
        return v[inc > 0 ? i * inc : (count - 1 - i) * -inc];
      };
      Eigen::VectorXd xv(nx), yv(ny);
      for (int i = 0; i < nx; ++i) xv(i) = element(x, nx, i);
      for (int i = 0; i < ny; ++i) yv(i) = element(y, ny, i);
      const double alpha = 2.0, beta = -1.0;
      const Eigen::VectorXd want = alpha * op(A.dense(), t) * xv + beta * yv;
      dgemv_(&t, &m, &n, &alpha, A.data.data(), &A.ld, x.data(), &inc, &beta, y.data(), &inc);
      for (int i = 0; i < ny; ++i) CHECK(element(y, ny, i) == Approx(want(i)).margin(1e-13));
    }
}

TEST_CASE("dpotrf factors positive definite blocks and names the first bad pivot", "[linalg][blas]") {
  std::mt19937_64 rng(5);
  const int n = 12;
  Stored M(n, n, 3, rng);
  const Eigen::MatrixXd G = M.dense();
  const Eigen::MatrixXd A = G * G.transpose() + n * Eigen::MatrixXd::Identity(n, n);
  for (char uplo : {'L', 'U'}) {
    std::vector<double> a(static_cast<size_t>(n) * (n + 3), 1e30);
    const int lda = n + 3;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) a[j * lda + i] = A(i, j);
    int info = -1;
    dpotrf_(&uplo, &n, a.data(), &lda, &info);
    CHECK(info == 0);
    Eigen::MatrixXd F(n, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) F(i, j) = a[j * lda + i];
    const Eigen::MatrixXd L = uplo == 'L' ? Eigen::MatrixXd(F.triangularView<Eigen::Lower>())
                                          : Eigen::MatrixXd(F.triangularView<Eigen::Upper>().transpose());
    CHECK((L * L.transpose() - A).norm() <= 1e-12 * A.norm());
  }
  // Indefinite at the third column: info = 3.
  Eigen::MatrixXd B = Eigen::MatrixXd::Identity(4, 4);
  B(2, 2) = -1.0;
  int info = 0;
  const int four = 4;
  dpotrf_("L", &four, B.data(), &four, &info);
  CHECK(info == 3);
  // A zero-sized block.
  const int zero = 0;
  dpotrf_("L", &zero, B.data(), &four, &info);
  CHECK(info == 0);
}

TEST_CASE("CHOLMOD's supernodal factorization and solves run on these kernels", "[linalg][blas]") {
  // A 3D grid Laplacian: large enough for supernodes with dense blocks.
  const int s = 14, n = s * s * s;
  std::vector<Eigen::Triplet<double>> t;
  auto id = [s](int i, int j, int k) { return (k * s + j) * s + i; };
  for (int k = 0; k < s; ++k)
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        t.emplace_back(id(i, j, k), id(i, j, k), 6.1);
        if (i + 1 < s) t.emplace_back(id(i + 1, j, k), id(i, j, k), -1.0);
        if (j + 1 < s) t.emplace_back(id(i, j + 1, k), id(i, j, k), -1.0);
        if (k + 1 < s) t.emplace_back(id(i, j, k + 1), id(i, j, k), -1.0);
      }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::SparseMatrix<double> full = A.selfadjointView<Eigen::Lower>();
  const long calls_before = gp::cholmod_blas_calls();
  gp::CholmodSolver solver;  // supernodal
  solver.compute(A);
  REQUIRE(solver.is_supernodal());
  const long after_factor = gp::cholmod_blas_calls();
  CHECK(after_factor > calls_before);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(n, 1);
  const Eigen::MatrixXd X = solver.solve(B);
  CHECK(gp::cholmod_blas_calls() > after_factor);
  CHECK((full * X - B).norm() <= 1e-10 * B.norm());
}
