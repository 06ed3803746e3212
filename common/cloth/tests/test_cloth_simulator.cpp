// Time stepping: a hanging cloth settles at the paper's step and at 4x that,
// pins are exact, solver strategies agree, and failures are rejected or thrown.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Geometry>

#include "cloth/cloth_simulator.h"
#include "core/error.h"
#include "testing/test_meshes.h"
#include "cloth/tests/function_contact.h"

using namespace gp::cloth;

namespace {

// The paper's 2.5 ms step, which these tests were written for (the
// simulator's default is the project's 10 ms).
SimulatorOptions paper_step() {
  SimulatorOptions options;
  options.dt = 0.0025;
  return options;
}

// A square cloth of side `size` in the vertical xy plane, top edge at y = 0,
// hanging down; vertex (i, j) = j*(n+1) + i with j = 0 the top row.
gp::Mesh hanging_square(int n, double size) {
  gp::Mesh m = gp::testing::make_grid(n, n, size, size);
  for (int v = 0; v < m.V.rows(); ++v) {
    const double x = m.V(v, 0), z = m.V(v, 2);
    m.V.row(v) = Eigen::RowVector3d(x, -z, 0.0);
  }
  return m;
}

struct SettleResult {
  double max_speed;
  double lowest_y;
  long rejected;
};

SettleResult settle(double dt, double seconds, SolverStrategy strategy) {
  const int n = 20;
  const gp::Mesh m = hanging_square(n, 0.5);
  SimulatorOptions options = paper_step();
  options.dt = dt;
  options.strategy = strategy;
  ClothSimulator sim(m.V, m.F, ClothParameters{}, options);
  sim.set_pinned({0, n});
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int s = 0; s < steps; ++s) sim.step();
  REQUIRE(sim.positions().allFinite());
  // Pinned corners stay exactly where they were.
  CHECK(sim.positions().row(0) == m.V.row(0));
  CHECK(sim.positions().row(n) == m.V.row(n));
  return {sim.max_speed(), sim.positions().col(1).minCoeff(), sim.counters().rejected};
}

// The 12 by 12 square of side 0.4 m pinned at its top corners, after `steps` steps.
ClothSimulator hang_square_12(const ClothParameters& params, const SimulatorOptions& options, int steps) {
  const gp::Mesh m = hanging_square(12, 0.4);
  ClothSimulator sim(m.V, m.F, params, options);
  sim.set_pinned({0, 12});
  for (int s = 0; s < steps; ++s) sim.step();
  return sim;
}

}  // namespace

TEST_CASE("a cloth pinned at two corners settles without NaN at dt and 4 dt", "[simulator]") {
  const SettleResult small = settle(0.0025, 2.0, SolverStrategy::pcg_reused_factor);
  const SettleResult large = settle(0.01, 2.0, SolverStrategy::pcg_reused_factor);
  INFO("dt 0.0025: max speed " << small.max_speed << " lowest " << small.lowest_y);
  INFO("dt 0.01:   max speed " << large.max_speed << " lowest " << large.lowest_y);
  // Sags below its initial bottom edge (y = -0.5) but not by much (stiff fabric).
  CHECK(small.lowest_y < -0.5);
  CHECK(small.lowest_y > -0.65);
  CHECK(large.lowest_y < -0.5);
  CHECK(large.lowest_y > -0.65);
  // Settled: slow everywhere after two seconds.
  CHECK(small.max_speed < 0.05);
  CHECK(large.max_speed < 0.05);
  CHECK(std::abs(small.lowest_y - large.lowest_y) < 0.01);
  CHECK(small.rejected == 0);
  CHECK(large.rejected == 0);
}

TEST_CASE("damping changes the way to the static equilibrium, not the equilibrium", "[simulator]") {
  // The hanging square after 6 s with the material's damping, and with a
  // hundredth of it from 0.5 s on (full damping damps the release first).
  // Its slowest mode, the compressed cloth between the pins, creeps at the
  // compression's tenth of the stiffness: at 3 s the damped run still moved
  // at 2e-6 m/s and lay 2 micrometres from the other.
  SimulatorOptions options = paper_step();
  options.dt = 0.01;
  ClothSimulator damped = hang_square_12(ClothParameters{}, options, 600);
  ClothSimulator light = hang_square_12(ClothParameters{}, options, 50);
  light.set_damping_scale(0.01);
  for (int s = 50; s < 600; ++s) light.step();
  const double distance = (damped.positions() - light.positions()).rowwise().norm().maxCoeff();
  INFO("largest distance " << distance << " m; speeds " << damped.max_speed() << " and " << light.max_speed() << " m/s");
  CHECK(damped.max_speed() < 0.01);
  CHECK(light.max_speed() < 0.01);
  CHECK(distance < 1e-6);
  // A scale of 1 is the material's damping again: the same step as never scaled.
  ClothSimulator a = hang_square_12(ClothParameters{}, options, 10);
  ClothSimulator b = hang_square_12(ClothParameters{}, options, 10);
  b.set_damping_scale(0.0);
  b.set_damping_scale(1.0);
  a.step();
  b.step();
  CHECK(a.positions() == b.positions());
  CHECK_THROWS_AS(b.set_damping_scale(-1.0), gp::UsageError);
  CHECK_THROWS_AS(b.set_damping_scale(std::nan("")), gp::UsageError);
}

TEST_CASE("solver strategies give the same trajectory", "[simulator]") {
  Eigen::MatrixXd result[3];
  const SolverStrategy strategies[3] = {SolverStrategy::pcg_reused_factor,
                                        SolverStrategy::refactor_every_step, SolverStrategy::pcg_jacobi};
  long factorizations[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    SimulatorOptions options = paper_step();
    options.strategy = strategies[k];
    options.cg_tolerance = 1e-10;
    options.cg_max_iterations = 5000;
    const ClothSimulator sim = hang_square_12(ClothParameters{}, options, 80);
    result[k] = sim.positions();
    factorizations[k] = sim.counters().factorizations;
    CHECK(sim.counters().last_residual <= 1e-9);
  }
  CHECK((result[0] - result[1]).cwiseAbs().maxCoeff() < 1e-7);
  CHECK((result[0] - result[2]).cwiseAbs().maxCoeff() < 1e-7);
  CHECK(factorizations[1] == 80);
  CHECK(factorizations[0] < 40);
  CHECK(factorizations[2] == 0);
}

TEST_CASE("the membrane-pattern preconditioner changes the cost, not the trajectory", "[simulator]") {
  // A hanging cloth that folds (bending matters): factoring only the one-ring
  // pattern must give the trajectory of the full factor within the CG
  // tolerance.
  Eigen::MatrixXd result[2];
  long iterations[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    SimulatorOptions options = paper_step();
    options.strategy = SolverStrategy::refactor_every_step;
    options.membrane_pattern_preconditioner = k == 1;
    options.cg_tolerance = 1e-10;
    ClothParameters params;
    params.k_bend = 1e-4;  // 100 times the default: the dropped couplings weigh more
    params.damping_bend = 1e-3;
    const ClothSimulator sim = hang_square_12(params, options, 60);
    result[k] = sim.positions();
    iterations[k] = sim.counters().cg_iterations;
    CHECK(sim.counters().last_residual <= 1e-10);
  }
  CHECK((result[0] - result[1]).cwiseAbs().maxCoeff() < 1e-7);
  CHECK(iterations[0] == 0);  // the full factor solves directly
  CHECK(iterations[1] > 0);   // the membrane factor needs CG ...
  CHECK(iterations[1] < 60 * 40);  // ... but few per step (measured 30)
}

TEST_CASE("pinned vertices follow their targets exactly and free ones follow", "[simulator]") {
  const gp::Mesh m = hanging_square(10, 0.3);
  ClothSimulator sim(m.V, m.F, ClothParameters{}, paper_step());
  sim.set_pinned({0, 10});
  Eigen::MatrixXd targets(2, 3);
  for (int s = 1; s <= 100; ++s) {
    const double shift = 0.001 * s;  // 0.4 m/s to the right
    targets.row(0) = m.V.row(0) + Eigen::RowVector3d(shift, 0, 0);
    targets.row(1) = m.V.row(10) + Eigen::RowVector3d(shift, 0, 0);
    sim.set_pin_targets(targets);
    sim.step();
    CHECK((sim.positions().row(0) - targets.row(0)).norm() == 0.0);
    CHECK((sim.positions().row(10) - targets.row(1)).norm() == 0.0);
  }
  // The rest of the cloth was dragged along.
  CHECK(sim.positions().col(0).mean() - m.V.col(0).mean() > 0.05);
  CHECK_THROWS_AS(sim.set_pin_targets(Eigen::MatrixXd::Zero(3, 3)), gp::UsageError);
  CHECK_THROWS_AS(sim.set_pinned({1, 1}), gp::UsageError);
  CHECK_THROWS_AS(sim.set_pinned({-1}), gp::UsageError);
}

TEST_CASE("an unrecoverable step throws NumericalError and leaves the state untouched", "[simulator]") {
  const gp::Mesh m = hanging_square(6, 0.3);
  ClothSimulator sim(m.V, m.F, ClothParameters{}, paper_step());
  Eigen::MatrixXd Vel = Eigen::MatrixXd::Zero(m.V.rows(), 3);
  Vel(5, 1) = std::numeric_limits<double>::quiet_NaN();
  sim.set_velocities(Vel);
  const Eigen::MatrixXd X0 = sim.positions();
  CHECK_THROWS_AS(sim.step(), gp::NumericalError);
  CHECK(sim.positions() == X0);
  CHECK(sim.counters().rejected == 5);  // one failing chain, depths 0 to 4
  // The NaN velocity reaches the right-hand side: CHOLMOD's solve throws first.
  CHECK(sim.counters().rejections.solve_failed == 5);
  CHECK(sim.counters().rejections.total() == 5);
  CHECK(sim.counters().inverted_faces.empty());
}

TEST_CASE("a rejected step is retried as two half steps", "[simulator]") {
  // A collision handler that breaks (writes NaN) whenever a vertex moves more than
  // 7 mm within one step: the full 10 ms step at 1 m/s is rejected, its halves pass.
  const gp::Mesh m = hanging_square(8, 0.2);
  SimulatorOptions options = paper_step();
  options.dt = 0.01;
  ClothParameters params;
  params.gravity.setZero();
  ClothSimulator sim(m.V, m.F, params, options);
  sim.set_velocities(Eigen::MatrixXd::Constant(m.V.rows(), 3, 0.0).rowwise() +
                     Eigen::RowVector3d(0.0, -1.0, 0.0));
  const ClothSimulator* observed = &sim;
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [observed](Eigen::MatrixXd& X, Eigen::MatrixXd&) {
    if ((X - observed->positions()).rowwise().norm().maxCoeff() > 0.007) {
      X(0, 0) = std::numeric_limits<double>::quiet_NaN();
    }
  };
  for (int s = 0; s < 5; ++s) sim.step();
  CHECK(sim.positions().allFinite());
  CHECK(sim.counters().steps == 5);
  CHECK(sim.counters().rejected == 5);
  CHECK(sim.counters().rejections.non_finite == 5);
  CHECK(sim.counters().rejections.total() == 5);
  CHECK(sim.counters().substeps == 10);
  // The cloth fell 5 cm as a rigid body.
  CHECK((sim.positions() - m.V).col(1).mean() == Approx(-0.05).epsilon(1e-6));
}

TEST_CASE("the step-end handler sees each (sub)step's start and its span of the step", "[simulator]") {
  // The same breaking handler as above forces halves; a step-end handler that
  // records the spans and moves one vertex by 1 mm gives it the velocity of
  // that displacement, and pins stay where their targets put them.
  const gp::Mesh m = hanging_square(8, 0.2);
  SimulatorOptions options = paper_step();
  options.dt = 0.01;
  ClothParameters params;
  params.gravity.setZero();
  ClothSimulator sim(m.V, m.F, params, options);
  sim.set_pinned({0});
  sim.set_velocities(Eigen::MatrixXd::Constant(m.V.rows(), 3, 0.0).rowwise() + Eigen::RowVector3d(0.0, -1.0, 0.0));
  const ClothSimulator* observed = &sim;
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [observed](Eigen::MatrixXd& X, Eigen::MatrixXd&) {
    if ((X - observed->positions()).rowwise().norm().maxCoeff() > 0.007) {
      X(1, 0) = std::numeric_limits<double>::quiet_NaN();
    }
  };
  std::vector<std::pair<double, double>> spans;
  bool starts_match = true;
  Eigen::MatrixXd last_start, last_end;
  step_body.on_sweep = [&](const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s0, double s1) {
    spans.emplace_back(s0, s1);
    starts_match = starts_match && X_start == observed->positions();
    X_end(5, 2) += 0.001;
    X_end(0, 2) += 0.5;  // a pinned vertex: restored
    last_start = X_start;
    last_end = X_end;
  };
  sim.set_pin_targets(m.V.topRows(1));
  sim.step();
  CHECK(starts_match);
  // The full step's attempt (rejected), then its two halves.
  REQUIRE(spans.size() >= 2);
  CHECK(spans[spans.size() - 2] == std::make_pair(0.0, 0.5));
  CHECK(spans.back() == std::make_pair(0.5, 1.0));
  CHECK(sim.positions().row(0) == m.V.row(0));
  // Vertex 5, moved by the handler, ends where it put it, with the velocity
  // of its displacement over the half step.
  CHECK(sim.positions().row(5) == last_end.row(5));
  CHECK((sim.velocities().row(5) - (last_end.row(5) - last_start.row(5)) / 0.005).norm() < 1e-9);
}

TEST_CASE("a new rest shape changes forces but keeps the state", "[simulator]") {
  const gp::Mesh m = hanging_square(6, 0.3);
  ClothParameters params;
  params.gravity.setZero();
  // The compression pushes the cloth out; at the paper's symmetric stiffness
  // it gets there within the 50 steps (a tenth of it takes ten times longer).
  params.compression_ratio = 1.0;
  ClothSimulator sim(m.V, m.F, params, paper_step());
  sim.step();
  CHECK(sim.max_speed() < 1e-12);  // at rest, no gravity: nothing moves
  sim.set_rest_shape(1.1 * m.V);   // rest larger than current: the cloth expands
  for (int s = 0; s < 50; ++s) sim.step();
  CHECK(sim.rest_state().total_area == Approx(1.21 * 0.09).epsilon(1e-9));
  const double width = sim.positions().col(0).maxCoeff() - sim.positions().col(0).minCoeff();
  CHECK(width > 0.31);
  CHECK_THROWS_AS(sim.set_rest_shape(Eigen::MatrixXd::Zero(3, 3)), gp::UsageError);
}

TEST_CASE("a fold that persists in the smallest substep is accepted and counted", "[simulator]") {
  // The handler turns triangle 0 over in every (sub)step, as a body squeezing
  // the cloth would: the step is retried once with halved substeps, then kept.
  // A 1 cm patch: the handler's jump (a triangle's height) becomes the vertex's
  // velocity (position-based update), which must stay under the speed and
  // energy checks so that only the fold decides.
  const gp::Mesh m = gp::testing::make_grid(4, 4, 0.01, 0.01);
  ClothParameters params;
  params.gravity.setZero();
  params.density = 100.0;  // heavy: the forced fold's energy stays under the explosion floor
  ClothSimulator sim(m.V, m.F, params, paper_step());
  const Eigen::Vector3i tri = m.F.row(0).transpose();
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [tri](Eigen::MatrixXd& X, Eigen::MatrixXd&) {
    const Eigen::Vector3d a = X.row(tri(0)), b = X.row(tri(1)), c = X.row(tri(2));
    const Eigen::Vector3d e = (b - a).normalized();
    const Eigen::Vector3d d = c - a;
    X.row(tri(2)) = (a + 2.0 * d.dot(e) * e - d).transpose();  // mirror c through the line a-b
  };
  sim.step();
  CHECK(sim.counters().steps == 1);
  CHECK(sim.counters().accepted_flips >= 1);
  CHECK(sim.counters().rejected == 1);  // one halving (max_fold_halvings), then accepted
  CHECK(sim.counters().rejections.inverted == 1);
  CHECK(sim.counters().rejections.total() == 1);
  // The rejected attempt names the faces it turned over (triangle 0 and one
  // more face of the mirrored vertex); the accepted fold is not a rejection.
  REQUIRE(sim.counters().inverted_faces.size() == static_cast<size_t>(m.F.rows()));
  CHECK(sim.counters().inverted_faces[0] == 1);
  long inverted = 0;
  for (long c : sim.counters().inverted_faces) inverted += c;
  CHECK(inverted == 2);
  const auto most = most_inverted_faces(sim.counters(), 10);
  REQUIRE(most.size() == 2);
  CHECK(most[0] == std::make_pair(0, 1L));  // ties in face order
  CHECK(most[1].second == 1);
  CHECK(most_inverted_faces(sim.counters(), 1).size() == 1);
  CHECK(sim.positions().allFinite());
}

TEST_CASE("a fold that lasts is met with half steps from its second step on", "[simulator]") {
  // The handler of the test above turns triangle 0 over in every (sub)step for
  // four steps, then stops. Without fold streaks every step tries the full
  // step, throws it away and takes the two halves; with them only the first
  // step does, the next three start as the halves, and so compute the same
  // positions bit for bit. The first step without a fold is still taken in
  // halves (it ends the streak), the one after it whole.
  const gp::Mesh m = gp::testing::make_grid(4, 4, 0.01, 0.01);
  ClothParameters params;
  params.gravity.setZero();
  params.density = 100.0;
  const Eigen::Vector3i tri = m.F.row(0).transpose();
  auto folding = std::make_shared<bool>(true);
  gp::cloth::testing::FunctionContact step_body;  // both simulators meet it; it outlives them
  step_body.on_project = [tri, folding](Eigen::MatrixXd& X, Eigen::MatrixXd&) {
    if (!*folding) return;
    const Eigen::Vector3d a = X.row(tri(0)), b = X.row(tri(1)), c = X.row(tri(2));
    const Eigen::Vector3d e = (b - a).normalized();
    const Eigen::Vector3d d = c - a;
    X.row(tri(2)) = (a + 2.0 * d.dot(e) * e - d).transpose();
  };
  auto make = [&](bool streaks) {
    SimulatorOptions options = paper_step();
    options.fold_streaks = streaks;
    ClothSimulator sim(m.V, m.F, params, options);
    sim.set_contact(&step_body);
    return sim;
  };
  ClothSimulator with = make(true), without = make(false);
  for (int s = 0; s < 4; ++s) {
    with.step();
    without.step();
    INFO("step " << s);
    CHECK(with.positions() == without.positions());
    CHECK(with.velocities() == without.velocities());
  }
  CHECK(without.counters().rejected == 4);
  CHECK(with.counters().rejected == 1);
  CHECK(with.counters().fold_streak_steps == 3);
  CHECK(without.counters().fold_streak_steps == 0);
  CHECK(with.counters().substeps == 8);
  CHECK(with.counters().accepted_flips == without.counters().accepted_flips);

  *folding = false;
  with.step();  // in the streak: two halves, no fold, the streak ends
  CHECK(with.counters().fold_streak_steps == 4);
  CHECK(with.counters().substeps == 10);
  with.step();  // a whole step again
  CHECK(with.counters().fold_streak_steps == 4);
  CHECK(with.counters().substeps == 11);
  CHECK(with.counters().rejected == 1);

  // A state set from outside starts without a streak.
  *folding = true;
  with.step();
  CHECK(with.counters().rejected == 2);
  with.set_positions(m.V);
  *folding = false;
  with.step();
  CHECK(with.counters().substeps == 14);  // 11 + the halves of the folding step + one whole step
}

TEST_CASE("a triangle the solve turns over in free cloth is retried, then accepted as a fold", "[simulator]") {
  // A corner vertex thrown across its triangle's opposite edge at 10 m/s
  // (10 cm in the 10 ms step, the triangle 2.5 cm across), with no handler:
  // the solve itself turns the face over, the step is retried as two halves,
  // the vertex still crosses in the first half, and at max_fold_halvings the
  // fold is accepted.
  const gp::Mesh m = gp::testing::make_grid(4, 4, 0.1, 0.1);
  ClothParameters params;
  params.gravity.setZero();
  params.density = 1000.0;  // heavy and undamped: inertia carries the vertex through
  params.damping_stretch = 0.0;
  params.damping_shear = 0.0;
  ClothSimulator sim(m.V, m.F, params, SimulatorOptions{});
  int corner = 0;  // the corner (x = 0.1, z = 0), in a single triangle
  for (int v = 1; v < m.V.rows(); ++v) {
    if (m.V(v, 0) - m.V(v, 2) > m.V(corner, 0) - m.V(corner, 2)) corner = v;
  }
  Eigen::MatrixXd Vel = Eigen::MatrixXd::Zero(m.V.rows(), 3);
  Vel.row(corner) = Eigen::RowVector3d(-10.0, 0.0, 10.0) / std::sqrt(2.0);
  sim.set_velocities(Vel);
  sim.step();
  CHECK(sim.counters().steps == 1);
  CHECK(sim.counters().rejected == 1);
  CHECK(sim.counters().rejections.inverted == 1);
  CHECK(sim.counters().accepted_flips >= 1);
  const auto most = most_inverted_faces(sim.counters(), 10);
  REQUIRE(!most.empty());
  CHECK(most[0].second == 1);
  CHECK(sim.positions().allFinite());
}

TEST_CASE("rejected steps are counted by reason", "[simulator]") {
  // A vertex thrown at 30 m/s (above max_speed 20) in every (sub)step: the step
  // fails at every depth for that reason alone, and throws.
  const gp::Mesh m = hanging_square(6, 0.3);
  ClothSimulator sim(m.V, m.F, ClothParameters{}, paper_step());
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [](Eigen::MatrixXd&, Eigen::MatrixXd& Vel) { Vel(3, 0) = 30.0; };
  CHECK_THROWS_AS(sim.step(), gp::NumericalError);
  const SolverCounters& c = sim.counters();
  CHECK(c.rejected == 5);
  CHECK(c.rejections.too_fast == 5);
  CHECK(c.rejections.inverted == 0);
  CHECK(c.rejections.energy_growth == 0);
  CHECK(c.rejections.non_finite == 0);
  CHECK(c.rejections.solve_failed == 0);
}

namespace {

// A cloth strip wrapped over the top half of a horizontal cylinder (axis z,
// radius R) at the contact radius, its two bottom edges pinned; gravity presses
// it onto the cylinder. Returns the largest edge stretch (length / rest length)
// and the smallest radius after `steps` steps.
struct DrapeResult {
  double max_edge_stretch;
  double min_radius;
  long constraints;
};

DrapeResult drape_over_cylinder(bool velocity_contacts, int steps) {
  const double R = 0.1;
  const int nu = 24, nz = 6;
  gp::Mesh m = gp::testing::make_grid(nu, nz, M_PI, 0.2);
  for (int v = 0; v < m.V.rows(); ++v) {
    const double a = m.V(v, 0), z = m.V(v, 2);
    m.V.row(v) = Eigen::RowVector3d(R * std::cos(a), R * std::sin(a), z);
  }
  ClothSimulator sim(m.V, m.F, ClothParameters{}, paper_step());
  std::vector<int> pins;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (m.V(v, 1) < 1e-9) pins.push_back(v);
  }
  sim.set_pinned(pins);
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_project = [R](Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) {
    for (int v = 0; v < X.rows(); ++v) {
      const Eigen::Vector2d p(X(v, 0), X(v, 1));
      const double r = p.norm();
      if (r >= R || r == 0.0) continue;
      const Eigen::Vector3d n(p.x() / r, p.y() / r, 0.0);
      X.row(v).head<2>() = (R * p / r).transpose();
      const double vn = Vel.row(v).dot(n.transpose());
      if (vn < 0.0) Vel.row(v) -= vn * n.transpose();
    }
  };
  if (velocity_contacts) {
    step_body.on_constraints = [R](const Eigen::MatrixXd& X, double h, std::vector<VelocityConstraint>& out) {
      for (int v = 0; v < X.rows(); ++v) {
        const Eigen::Vector2d p(X(v, 0), X(v, 1));
        const double r = p.norm();
        if (r > R + 1e-4 || r == 0.0) continue;
        VelocityConstraint c;
        c.vertex = v;
        c.normal = Eigen::Vector3d(p.x() / r, p.y() / r, 0.0);
        c.normal_velocity = std::max(R - r, 0.0) / h;
        c.touching = r <= R + 1e-6;
        out.push_back(c);
      }
    };
  }
  for (int s = 0; s < steps; ++s) sim.step();
  const Eigen::MatrixXd& X = sim.positions();
  double stretch = 0.0, min_radius = 1e9;
  for (int f = 0; f < m.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      stretch = std::max(stretch, (X.row(a) - X.row(b)).norm() / (m.V.row(a) - m.V.row(b)).norm());
    }
  }
  for (int v = 0; v < X.rows(); ++v) min_radius = std::min(min_radius, X.row(v).head<2>().norm());
  return {stretch, min_radius, sim.counters().constraints};
}

}  // namespace

TEST_CASE("contact as velocity constraints keeps a draped cloth unstretched", "[simulator][contact]") {
  // With the position projection alone, the solve does not know about the
  // contact: every step it moves the cloth into the cylinder and the projection
  // pushes it back, which pumps strain into the strip. Filtered velocity
  // constraints remove the normal motion inside the solve.
  const DrapeResult constrained = drape_over_cylinder(true, 200);
  const DrapeResult projected = drape_over_cylinder(false, 200);
  INFO("velocity constraints: max edge stretch " << constrained.max_edge_stretch << ", min radius "
                                                 << constrained.min_radius);
  INFO("projection only:      max edge stretch " << projected.max_edge_stretch << ", min radius "
                                                 << projected.min_radius);
  CHECK(constrained.constraints > 0);
  CHECK(constrained.max_edge_stretch < 1.01);
  CHECK(constrained.min_radius > 0.1 - 1e-6);
  CHECK(constrained.max_edge_stretch <= projected.max_edge_stretch + 1e-9);
}

TEST_CASE("a contact that would pull the cloth onto the body is released", "[simulator][contact]") {
  // A flat cloth lying on the plane y = 0, one edge pinned and lifted: the cloth
  // must leave the plane instead of being held to it by its constraints.
  const int n = 10;
  gp::Mesh m = gp::testing::make_grid(n, n, 0.3, 0.3);
  m.V.col(1).setZero();
  SimulatorOptions options = paper_step();
  options.contact_release_fraction = 1.0;
  ClothSimulator sim(m.V, m.F, ClothParameters{}, options);
  std::vector<int> pins;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (m.V(v, 0) > 0.3 - 1e-9) pins.push_back(v);
  }
  sim.set_pinned(pins);
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_constraints = [](const Eigen::MatrixXd& X, double h, std::vector<VelocityConstraint>& out) {
    for (int v = 0; v < X.rows(); ++v) {
      if (X(v, 1) > 1e-4) continue;
      VelocityConstraint c;
      c.vertex = v;
      c.normal = Eigen::Vector3d::UnitY();
      c.normal_velocity = std::max(-X(v, 1), 0.0) / h;
      c.touching = X(v, 1) <= 1e-6;
      out.push_back(c);
    }
  };
  Eigen::MatrixXd targets(pins.size(), 3);
  for (int s = 1; s <= 100; ++s) {
    for (size_t k = 0; k < pins.size(); ++k) {
      targets.row(k) = m.V.row(pins[k]) + Eigen::RowVector3d(0.0, 0.2 * s / 100.0, 0.0);
    }
    sim.set_pin_targets(targets);
    sim.step();
  }
  CHECK(sim.counters().released > 0);
  // The row next to the lifted edge has left the plane with it.
  double lifted = 0.0;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (std::abs(m.V(v, 0) - 0.27) < 1e-9) lifted = std::max(lifted, sim.positions()(v, 1));
  }
  CHECK(lifted > 0.1);
  CHECK(sim.positions().col(1).minCoeff() > -1e-6);
}

TEST_CASE("a vertex held in two directions meets both prescribed speeds", "[simulator][contact]") {
  // The hanging square; one free vertex gets two constraints 60 degrees apart
  // (a crease), with different normal speeds, and a third, nearly parallel to
  // the second, that must be ignored. The solved velocity must satisfy both
  // n1.v = a1 and n2.v = a2, whatever gravity and the cloth do tangentially.
  const gp::Mesh m = hanging_square(8, 0.3);
  SimulatorOptions options = paper_step();
  options.contact_release_fraction = 1e9;  // the body may pull here: only the constraint algebra is tested
  ClothSimulator sim(m.V, m.F, ClothParameters{}, options);
  sim.set_pinned({0, 8});
  const int v = 4 * 9 + 4;
  const Eigen::Vector3d n1 = Eigen::Vector3d(0.0, 0.0, 1.0);
  const Eigen::Vector3d n2 = Eigen::Vector3d(0.0, std::sin(M_PI / 3.0), std::cos(M_PI / 3.0));
  const double a1 = 0.02, a2 = -0.01;
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  step_body.on_constraints = [&](const Eigen::MatrixXd&, double, std::vector<VelocityConstraint>& out) {
    VelocityConstraint c;
    c.vertex = v;
    c.normal = n1;
    c.normal_velocity = a1;
    out.push_back(c);
    c.normal = 2.0 * n2;  // normals are normalized by the simulator
    c.normal_velocity = a2;
    out.push_back(c);
    c.normal = (n2 + Eigen::Vector3d(0.0, 0.05, 0.0)).normalized();
    c.normal_velocity = 5.0;
    out.push_back(c);
  };
  for (int s = 0; s < 5; ++s) {
    sim.step();
    const Eigen::Vector3d vel = sim.velocities().row(v).transpose();
    CHECK(vel.dot(n1) == Approx(a1).margin(1e-9));
    CHECK(vel.dot(n2) == Approx(a2).margin(1e-9));
  }
  CHECK(sim.counters().constraints == 10);
  // The tangential direction of the crease (n1 x n2) is free: gravity moves it.
  const Eigen::Vector3d along = n1.cross(n2).normalized();
  CHECK(std::abs(sim.velocities().row(v).dot(along.transpose())) < 1.0);
}
