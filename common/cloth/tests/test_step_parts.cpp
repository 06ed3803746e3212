// The simulator's parts on their own: the assembled system, the contact set's
// selection, filter and release rule, and the step checks' typed outcomes.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "cloth/contact_set.h"
#include "cloth/step_validation.h"
#include "cloth/system_assembly.h"
#include "core/error.h"
#include "testing/test_meshes.h"

using namespace gp::cloth;

namespace {

// A dense symmetric copy of the lower-triangle A.
Eigen::MatrixXd dense_symmetric(const Eigen::SparseMatrix<double>& A) {
  const Eigen::MatrixXd L = Eigen::MatrixXd(A);
  Eigen::MatrixXd S = L + L.transpose();
  S.diagonal() = L.diagonal();
  return S;
}

VelocityConstraint candidate(int vertex, const Eigen::Vector3d& normal, double speed, bool touching = true) {
  VelocityConstraint c;
  c.vertex = vertex;
  c.normal = normal;
  c.normal_velocity = speed;
  c.touching = touching;
  return c;
}

}  // namespace

TEST_CASE("the assembled system is symmetric positive definite and at rest pulls only by gravity", "[step_parts]") {
  const gp::Mesh m = gp::testing::make_grid(4, 4, 0.4, 0.4);
  const ClothParameters params;
  const ClothRestState rest = build_rest_state(m.V, m.F, params);
  for (const std::vector<int>& pinned : {std::vector<int>{}, std::vector<int>{0, 4}}) {
    SystemAssembly system;
    system.build(m.F, rest.Q, static_cast<int>(m.V.rows()), pinned);
    REQUIRE(system.free_count() == m.V.rows() - static_cast<long>(pinned.size()));
    for (int v : pinned) CHECK(system.free_ids()(v) == -1);
    CHECK(system.step_size() == -1.0);
    const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(m.V.rows(), 3);
    const double h = 0.01;
    const double energy = system.assemble(m.V, zero, zero, m.F, rest, params, 1.0, h);
    CHECK(system.step_size() == h);
    CHECK(std::abs(energy) < 1e-12);  // the rest shape stores no elastic energy
    const Eigen::MatrixXd A = dense_symmetric(system.matrix());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
    CHECK(eig.eigenvalues().minCoeff() > 0.0);
    // The diagonal holds at least the vertex's mass; diagonal() reads it.
    for (int v = 0; v < m.V.rows(); ++v) {
      const int fi = system.free_ids()(v);
      if (fi < 0) continue;
      for (int c = 0; c < 3; ++c) {
        CHECK(system.diagonal(3 * fi + c) == A(3 * fi + c, 3 * fi + c));
        CHECK(A(3 * fi + c, 3 * fi + c) >= rest.masses(v));
      }
      // b = h m g at rest with no velocity.
      const Eigen::Vector3d expected = h * rest.masses(v) * params.gravity;
      CHECK((system.rhs().segment<3>(3 * fi) - expected).norm() <= 1e-9 * expected.norm());
    }
  }
}

TEST_CASE("the assembled right-hand side moves the pinned vertices' coupling over", "[step_parts]") {
  const gp::Mesh m = gp::testing::make_grid(3, 3, 0.3, 0.3);
  ClothParameters params;
  params.gravity.setZero();
  const ClothRestState rest = build_rest_state(m.V, m.F, params);
  const std::vector<int> pinned{0};
  SystemAssembly pinned_system, free_system;
  pinned_system.build(m.F, rest.Q, static_cast<int>(m.V.rows()), pinned);
  free_system.build(m.F, rest.Q, static_cast<int>(m.V.rows()), {});
  Eigen::MatrixXd V_prescribed = Eigen::MatrixXd::Zero(m.V.rows(), 3);
  V_prescribed.row(0) = Eigen::RowVector3d(0.1, -0.2, 0.3);
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(m.V.rows(), 3);
  const double h = 0.01;
  pinned_system.assemble(m.V, zero, V_prescribed, m.F, rest, params, 1.0, h);
  free_system.assemble(m.V, zero, zero, m.F, rest, params, 1.0, h);
  // With every vertex free, b_f - A_fp v_p is the pinned system's right-hand side.
  const Eigen::MatrixXd A = dense_symmetric(free_system.matrix());
  const Eigen::VectorXd coupling = A.block(3, 0, A.rows() - 3, 3) * V_prescribed.row(0).transpose();
  const Eigen::VectorXd expected = free_system.rhs().tail(A.rows() - 3) - coupling;
  CHECK((pinned_system.rhs() - expected).norm() <= 1e-12 * std::max(1.0, coupling.norm()));
  CHECK(coupling.norm() > 0.0);
}

TEST_CASE("the contact set keeps touching or held vertices, a crease's second normal orthogonal", "[step_parts]") {
  Eigen::VectorXi free_id(4);
  free_id << 0, 1, -1, 2;  // vertex 2 pinned
  const double s45 = std::sqrt(0.5);
  const auto candidates = [&]() {
    std::vector<VelocityConstraint> out;
    out.push_back(candidate(3, Eigen::Vector3d(0, 2, 0), 0.5));               // normalized
    out.push_back(candidate(0, Eigen::Vector3d(0, 1, 0), 1.0));
    out.push_back(candidate(0, Eigen::Vector3d(s45, s45, 0), 2.0));           // a crease: 45 degrees
    out.push_back(candidate(0, Eigen::Vector3d(0, 0, 1), 0.0));               // a third: dropped
    out.push_back(candidate(1, Eigen::Vector3d(0, 1, 0), 0.0, false));        // near, never held: dropped
    out.push_back(candidate(2, Eigen::Vector3d(0, 1, 0), 0.0));               // pinned: dropped
    out.push_back(candidate(3, Eigen::Vector3d(0, 1, 0.05), 0.0));            // nearly parallel: dropped
    out.push_back(candidate(5, Eigen::Vector3d(0, 1, 0), 0.0));               // out of range: dropped
    out.push_back(candidate(1, Eigen::Vector3d(0, 0, 0), 0.0));               // no normal: dropped
    out.push_back(candidate(1, Eigen::Vector3d(0, 1, 0), std::nan("")));      // no speed: dropped
    return out;
  };
  ContactSet contacts;
  std::vector<VelocityConstraint> none, all = candidates();
  CHECK(contacts.gather(none, 4, free_id) == 0);
  REQUIRE(contacts.gather(all, 4, free_id) == 3);
  CHECK(contacts.constraint(0).vertex == 0);
  CHECK(contacts.constraint(1).vertex == 0);
  CHECK(contacts.constraint(2).vertex == 3);
  CHECK(contacts.free_index(2) == 2);
  CHECK(contacts.constraint(2).normal.isApprox(Eigen::Vector3d::UnitY()));
  // The crease: n2' orthogonal to n1, a2' such that n2.v = 2 and n1.v = 1 hold together.
  const Eigen::Vector3d n1 = contacts.constraint(0).normal, n2 = contacts.constraint(1).normal;
  CHECK(std::abs(n1.dot(n2)) < 1e-15);
  CHECK(n2.norm() == Approx(1.0));
  Eigen::VectorXd sol = Eigen::VectorXd::Zero(9);
  contacts.impose(sol);
  const Eigen::Vector3d v0 = sol.segment<3>(0);
  CHECK(v0.dot(Eigen::Vector3d::UnitY()) == Approx(1.0));
  CHECK(v0.dot(Eigen::Vector3d(s45, s45, 0)) == Approx(2.0));
  CHECK(sol(7) == Approx(0.5));  // vertex 3 (free index 2), y
  // The filter removes exactly the constrained components.
  Eigen::VectorXd r = Eigen::VectorXd::Ones(9);
  contacts.filter(r);
  CHECK(std::abs(r.segment<3>(0).dot(n1)) < 1e-15);
  CHECK(std::abs(r.segment<3>(0).dot(n2)) < 1e-15);
  CHECK(r.segment<3>(3) == Eigen::Vector3d::Ones());
  CHECK(r(7) == 0.0);
}

TEST_CASE("a constraint whose force pulls towards the body is released for the next step", "[step_parts]") {
  // One free vertex of mass m, A = m I: the constraint force is A v - b.
  const double m = 0.01, h = 0.01, g = 9.81, fraction = 20.0;
  Eigen::SparseMatrix<double> A(3, 3);
  for (int i = 0; i < 3; ++i) A.insert(i, i) = m;
  A.makeCompressed();
  const Eigen::VectorXi free_id = Eigen::VectorXi::Zero(1);
  const Eigen::VectorXd masses = Eigen::VectorXd::Constant(1, m);
  std::vector<VelocityConstraint> touching{candidate(0, Eigen::Vector3d::UnitY(), 0.0)};
  std::vector<VelocityConstraint> near{candidate(0, Eigen::Vector3d::UnitY(), 0.0, false)};
  const double threshold = fraction * h * m * g;
  for (const double pull : {0.5, 2.0}) {  // times the threshold
    ContactSet contacts;
    REQUIRE(contacts.gather(touching, 1, free_id) == 1);
    const Eigen::VectorXd sol = Eigen::VectorXd::Zero(3);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(3);
    b(1) = pull * threshold;  // A sol - b points into the body
    const long released = contacts.update_released(A, sol, b, masses, g, fraction, h, 1);
    CHECK(released == (pull > 1.0 ? 1 : 0));
    CHECK(contacts.history().released[0] == (pull > 1.0 ? 1 : 0));
    // A merely near vertex stays constrained only while it was held and not released.
    CHECK(contacts.gather(near, 1, free_id) == (pull > 1.0 ? 0 : 1));
  }
  ContactSet fresh;
  CHECK(fresh.gather(near, 1, free_id) == 0);
}

TEST_CASE("the step checks name the first failed check as a typed outcome", "[step_parts]") {
  const gp::Mesh m = gp::testing::make_grid(2, 2, 0.2, 0.2);
  const ClothParameters params;
  const ClothRestState rest = build_rest_state(m.V, m.F, params);
  const SimulatorOptions options;
  const Eigen::MatrixXd zero = Eigen::MatrixXd::Zero(m.V.rows(), 3);

  StepOutcome ok = validate_step(m.V, m.V, zero, m.F, rest, params, options, 0.0, false);
  CHECK(ok.accepted());
  CHECK(ok.flipped_faces.empty());

  Eigen::MatrixXd X_nan = m.V;
  X_nan(3, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK(validate_step(m.V, X_nan, zero, m.F, rest, params, options, 0.0, false).rejection == Rejection::non_finite);

  Eigen::MatrixXd V_fast = zero;
  V_fast(4, 0) = 1.01 * options.max_speed;
  const StepOutcome fast = validate_step(m.V, m.V, V_fast, m.F, rest, params, options, 0.0, false);
  CHECK(fast.rejection == Rejection::too_fast);
  CHECK(fast.detail.find("m/s") != std::string::npos);

  // The grid lies in the xz plane: moving corner vertex 0 past the far
  // corner of its 0.1 m cell turns its faces over.
  Eigen::MatrixXd X_flip = m.V;
  int corner_face = -1;
  for (int f = 0; f < m.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (m.F(f, k) == 0 && corner_face < 0) corner_face = f;
    }
  }
  REQUIRE(corner_face >= 0);
  X_flip.row(0) = Eigen::RowVector3d(0.2, 0.0, 0.2);  // past the diagonal of the 0.1 cell
  const StepOutcome flipped = validate_step(m.V, X_flip, zero, m.F, rest, params, options, 1e9, false);
  CHECK(flipped.rejection == Rejection::inverted);
  REQUIRE(!flipped.flipped_faces.empty());
  CHECK(flipped.flipped_faces.front() == corner_face);
  CHECK(flipped.accepted_folds == 0);
  const StepOutcome fold = validate_step(m.V, X_flip, zero, m.F, rest, params, options, 1e9, true);
  CHECK(fold.accepted());
  CHECK(fold.accepted_folds == static_cast<long>(flipped.flipped_faces.size()));

  // Kinetic energy far above the floor of 10 J/kg from nothing.
  const Eigen::MatrixXd V_swift = Eigen::MatrixXd::Constant(m.V.rows(), 3, 0.5 * options.max_speed / std::sqrt(3.0));
  const StepOutcome burst = validate_step(m.V, m.V, V_swift, m.F, rest, params, options, 0.0, false);
  CHECK(burst.rejection == Rejection::energy_growth);
  CHECK(burst.detail.find("energy") != std::string::npos);

  RejectionCounts counts;
  ++count_of(counts, Rejection::inverted);
  ++count_of(counts, Rejection::energy_growth);
  CHECK(counts.inverted == 1);
  CHECK(counts.total() == 2);
  CHECK_THROWS_AS(count_of(counts, Rejection::none), gp::Error);
}
