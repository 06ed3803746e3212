// The static solve: the barrier's derivatives, the equilibrium it returns (its force residual
// recomputed here, from two starts, against a long damped dynamic settle), contact that no step
// passes through, and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "cloth/cloth_model.h"
#include "cloth/cloth_simulator.h"
#include "cloth/static_solve.h"
#include "core/error.h"
#include "testing/test_meshes.h"
#include "cloth/tests/function_contact.h"

using namespace gp::cloth;

namespace {

// The 12 by 12 square of side 0.4 m in the vertical xy plane, top edge at y = 0, pinned at its top
// corners (vertices 0 and 12).
gp::Mesh hanging_square() {
  gp::Mesh m = gp::testing::make_grid(12, 12, 0.4, 0.4);
  for (int v = 0; v < m.V.rows(); ++v) m.V.row(v) = Eigen::RowVector3d(m.V(v, 0), -m.V(v, 2), 0.0);
  return m;
}

// A sphere as the body.
BodyDistanceQuery sphere(const Eigen::Vector3d& center, double radius) {
  return [center, radius](int, const Eigen::Vector3d& p, bool) {
    BodyDistance d;
    const Eigen::Vector3d r = p - center;
    d.signed_distance = r.norm() - radius;
    d.outward = r.normalized();
    return d;
  };
}

// A horizontal cylinder (axis z through the origin) as the body.
BodyDistanceQuery cylinder(double radius) {
  return [radius](int, const Eigen::Vector3d& p, bool) {
    BodyDistance d;
    const Eigen::Vector3d r(p.x(), p.y(), 0.0);
    d.signed_distance = r.norm() - radius;
    d.outward = r.normalized();
    return d;
  };
}

// The cylinder of cylinder() at radius R as the damped steps meet it (cloth_simulator.h): a
// velocity constraint at the radius, and the projection out to it.
void cylinder_contact(gp::cloth::testing::FunctionContact& body, double R) {
  body.on_project = [R](Eigen::MatrixXd& Y, Eigen::MatrixXd& Vel) {
    for (int v = 0; v < Y.rows(); ++v) {
      const Eigen::Vector2d p(Y(v, 0), Y(v, 1));
      if (p.norm() >= R) continue;
      const Eigen::Vector3d n(p.x() / p.norm(), p.y() / p.norm(), 0.0);
      Y.row(v).head<2>() = (R * p.normalized()).transpose();
      const double vn = Vel.row(v).dot(n.transpose());
      if (vn < 0.0) Vel.row(v) -= vn * n.transpose();
    }
  };
  body.on_constraints = [R](const Eigen::MatrixXd& Y, double h, std::vector<VelocityConstraint>& out) {
    for (int v = 0; v < Y.rows(); ++v) {
      const Eigen::Vector2d p(Y(v, 0), Y(v, 1));
      if (p.norm() > R + 1e-4) continue;
      VelocityConstraint c;
      c.vertex = v;
      c.normal = Eigen::Vector3d(p.x() / p.norm(), p.y() / p.norm(), 0.0);
      c.normal_velocity = std::max(R - p.norm(), 0.0) / h;
      c.touching = p.norm() <= R + 1e-6;
      out.push_back(c);
    }
  };
}

// grad E recomputed from the model and the barrier's formula (static_solve.h), RMS over the free
// vertices in mean vertex weights: what the solve calls its residual, computed independently.
double force_residual(const ClothSimulator& sim, const Eigen::MatrixXd& X, const BodyDistanceQuery& body,
                      const Eigen::VectorXd& walls, const StaticSolveOptions& o) {
  Eigen::MatrixXd G = cloth_gradient(X, sim.faces(), sim.rest_state(), sim.parameters());
  const Eigen::VectorXd areas = sim.rest_state().masses / sim.parameters().density;
  std::vector<char> pinned(X.rows(), 0);
  for (int v : sim.pinned()) pinned[v] = 1;
  double sum = 0.0, mass = 0.0;
  int n = 0;
  for (int v = 0; v < X.rows(); ++v) {
    if (pinned[v]) continue;
    if (body) {
      const BodyDistance d = body(v, X.row(v).transpose(), false);
      const double s = (d.signed_distance - walls(v)) / o.barrier_band;
      G.row(v) += o.barrier_pressure * areas(v) * barrier_phi_d1(s) * d.outward.transpose();
    }
    sum += G.row(v).squaredNorm();
    mass += sim.rest_state().masses(v);
    ++n;
  }
  return std::sqrt(sum / n) / (mass / n * sim.parameters().gravity.norm());
}

// A strip 0.6 m long and 0.1 m wide (30 by 5 quads) lying flat 1 cm above the cylinder of
// cylinder(0.1), across it, its short edges pinned and lowered beside the cylinder to (+-0.28 m,
// 0.02 m): the strip drapes over the top with about 3 % slack between the pins and the body.
struct DrapedStrip {
  gp::Mesh mesh;
  std::vector<int> pins;
  Eigen::MatrixXd start;  // the pins lowered
};
DrapedStrip draped_strip() {
  DrapedStrip d;
  d.mesh = gp::testing::make_grid(30, 5, 0.6, 0.1);
  Eigen::MatrixXd& V = d.mesh.V;
  V.col(0).array() -= 0.3;
  V.col(1).setConstant(0.11);
  V.col(2).array() -= 0.05;
  d.start = V;
  for (int v = 0; v < V.rows(); ++v) {
    if (std::abs(V(v, 0)) < 0.3 - 1e-9) continue;
    d.pins.push_back(v);
    d.start(v, 0) = V(v, 0) > 0.0 ? 0.28 : -0.28;
    d.start(v, 1) = 0.02;
  }
  return d;
}

// The force residual of an active-set equilibrium on cylinder(R) with the comfort offset `offset`,
// recomputed from the model: grad E with, at each free vertex at its level (radius R + offset, to
// 10 micrometres), the radial part pressing it onto the body left out; RMS over the free vertices in
// mean vertex weights. Also the smallest radius of a free vertex.
double held_residual(const ClothSimulator& sim, const Eigen::MatrixXd& X, double R, double offset,
                     double& min_radius) {
  Eigen::MatrixXd G = cloth_gradient(X, sim.faces(), sim.rest_state(), sim.parameters());
  std::vector<char> pinned(X.rows(), 0);
  for (int v : sim.pinned()) pinned[v] = 1;
  double sum = 0.0, mass = 0.0;
  int n = 0;
  min_radius = std::numeric_limits<double>::infinity();
  for (int v = 0; v < X.rows(); ++v) {
    if (pinned[v]) continue;
    const Eigen::Vector3d r(X(v, 0), X(v, 1), 0.0);
    min_radius = std::min(min_radius, r.norm());
    const Eigen::Vector3d normal = r.normalized();
    const double pressing = G.row(v).dot(normal.transpose());
    if (r.norm() < R + offset + 1e-5 && pressing > 0.0) G.row(v) -= pressing * normal.transpose();
    sum += G.row(v).squaredNorm();
    mass += sim.rest_state().masses(v);
    ++n;
  }
  return std::sqrt(sum / n) / (mass / n * sim.parameters().gravity.norm());
}

// A 30 cm sheet 5 cm above a ball (radius 3 cm, at the origin), pinned at its four corners 7 cm
// below the ball's centre: it falls 10 cm and more, so the first Newton steps would carry a vertex
// into or beyond the ball without the step limit.
struct BallScene {
  static constexpr int n = 16;
  static constexpr double radius = 0.03, offset = 0.004;
  gp::Mesh mesh;
  std::vector<int> pins{0, n, n * (n + 1), n * (n + 1) + n};
  Eigen::MatrixXd start;
  int middle = n / 2 * (n + 1) + n / 2;
};

BallScene ball_scene() {
  BallScene b;
  b.mesh = gp::testing::make_grid(BallScene::n, BallScene::n, 0.3, 0.3);
  b.mesh.V.col(0).array() -= 0.15;
  b.mesh.V.col(2).array() -= 0.15;
  b.mesh.V.col(1).setConstant(0.05);
  b.start = b.mesh.V;
  for (int v : b.pins) b.start(v, 1) = -0.07;
  return b;
}

// The distance of the vertex of X (#V by 3) nearest the ball to its surface [m].
double closest_to_ball(const Eigen::MatrixXd& X) {
  return X.rowwise().norm().minCoeff() - BallScene::radius;
}

}  // namespace

TEST_CASE("the barrier's derivatives match finite differences", "[static]") {
  for (double s : {0.01, 0.1, 0.3, 0.5, 0.8, 0.99}) {
    const double h = 1e-6 * s;
    INFO("s = " << s);
    CHECK(barrier_phi_d1(s) == Approx((barrier_phi(s + h) - barrier_phi(s - h)) / (2 * h)).epsilon(1e-6));
    CHECK(barrier_phi_d2(s) == Approx((barrier_phi_d1(s + h) - barrier_phi_d1(s - h)) / (2 * h)).epsilon(1e-6));
    CHECK(barrier_phi_d2(s) > 0.0);  // convex: the Hessian term is PSD
  }
  // Zero at and above the band, C1 there; infinite at and behind the wall.
  CHECK(barrier_phi(1.0) == 0.0);
  CHECK(barrier_phi(1.5) == 0.0);
  CHECK(barrier_phi_d1(1.0 - 1e-9) == Approx(0.0).margin(1e-12));
  CHECK(std::isinf(barrier_phi(0.0)));
  CHECK(std::isinf(barrier_phi(-0.1)));
  CHECK(std::isinf(barrier_phi(std::nan(""))));
}

TEST_CASE("a hanging square's static equilibrium: residual below the tolerance, the same from two starts, "
          "and where a long damped settle ends",
          "[static]") {
  const gp::Mesh m = hanging_square();
  SimulatorOptions so;
  so.dt = 0.01;
  ClothSimulator sim(m.V, m.F, ClothParameters{}, so);
  sim.set_pinned({0, 12});
  const Eigen::VectorXd offsets = Eigen::VectorXd::Zero(m.V.rows());
  StaticSolver solver;
  const StaticSolveOptions& o = solver.options();

  Eigen::MatrixXd from_rest = m.V;
  const StaticSolveReport a = solver.solve(sim, {}, offsets, from_rest);
  INFO("from rest: " << a.iterations << " iterations, residual " << a.residual);
  REQUIRE(a.converged);
  CHECK(a.iterations < 100);
  CHECK(a.residual < o.tolerance);
  CHECK(a.residuals.front() > 0.9);  // the whole weight unbalanced at the start
  const double recomputed = force_residual(sim, from_rest, {}, offsets, o);
  CHECK(recomputed == Approx(a.residual).epsilon(1e-6));
  CHECK(from_rest.row(0) == m.V.row(0));  // the pins stay
  CHECK(from_rest.row(12) == m.V.row(12));

  // Another start in the cloth's plane: sheared, squashed and swung 10 cm to the side.
  Eigen::MatrixXd from_other = m.V;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (v == 0 || v == 12) continue;
    const double y = m.V(v, 1);
    from_other(v, 0) += 0.1 * (-y / 0.4) + 0.02 * std::sin(9.0 * m.V(v, 0));
    from_other(v, 1) = 0.8 * y;
  }
  const StaticSolveReport b = solver.solve(sim, {}, offsets, from_other);
  INFO("from the other start: " << b.iterations << " iterations, residual " << b.residual);
  REQUIRE(b.converged);
  const double apart = (from_rest - from_other).rowwise().norm().maxCoeff();
  INFO("largest distance between the two equilibria " << apart << " m");
  CHECK(apart < 1e-4);

  // Six seconds of damped implicit Euler steps from rest end within 1 mm of it.
  for (int s = 0; s < 600; ++s) sim.step();
  const double to_dynamic = (sim.positions() - from_rest).rowwise().norm().maxCoeff();
  INFO("largest distance to the damped settle " << to_dynamic << " m, its speed " << sim.max_speed() << " m/s");
  CHECK(sim.max_speed() < 0.01);
  CHECK(to_dynamic < 1e-3);
}

TEST_CASE("a strip pressed onto a cylinder rests outside it at equilibrium, as the damped contact run", "[static]") {
  const double R = 0.1;
  gp::Mesh m = gp::testing::make_grid(24, 6, M_PI, 0.2);
  for (int v = 0; v < m.V.rows(); ++v) {
    const double a = m.V(v, 0), z = m.V(v, 2);
    m.V.row(v) = Eigen::RowVector3d(R * std::cos(a), R * std::sin(a), z);
  }
  std::vector<int> pins;
  for (int v = 0; v < m.V.rows(); ++v) {
    if (m.V(v, 1) < 1e-9) pins.push_back(v);
  }
  SimulatorOptions so;
  so.dt = 0.0025;
  ClothSimulator sim(m.V, m.F, ClothParameters{}, so);
  sim.set_pinned(pins);
  StaticSolveOptions o;
  o.barrier_band = 5e-4;
  StaticSolver solver(o);
  const Eigen::VectorXd offsets = Eigen::VectorXd::Zero(m.V.rows());
  Eigen::MatrixXd X = m.V;
  const StaticSolveReport r = solver.solve(sim, StaticBody{cylinder(R), {}}, offsets, X);
  INFO(r.iterations << " iterations, residual " << r.residual << ", " << r.contacts << " vertices in the band");
  REQUIRE(r.converged);
  CHECK(r.contacts > 50);
  double min_radius = 1e9;  // of the free vertices (the pins are on the cylinder)
  for (int v = 0; v < X.rows(); ++v) {
    if (m.V(v, 1) > 1e-9) min_radius = std::min(min_radius, X.row(v).head<2>().norm());
  }
  // The barrier's band straddles the offset (here 0): the strip rests within half a band of it.
  CHECK(min_radius > R - 0.5 * o.barrier_band);
  CHECK(min_radius < R + 0.5 * o.barrier_band);
  const Eigen::VectorXd walls = Eigen::VectorXd::Constant(X.rows(), -0.5 * o.barrier_band);
  CHECK(force_residual(sim, X, cylinder(R), walls, o) == Approx(r.residual).epsilon(1e-6));

  // The damped run with velocity constraints at the radius (cloth_simulator.h) ends within 1 mm.
  gp::cloth::testing::FunctionContact step_body;
  sim.set_contact(&step_body);
  cylinder_contact(step_body, R);
  for (int s = 0; s < 1200; ++s) sim.step();
  const double apart = (sim.positions() - X).rowwise().norm().maxCoeff();
  INFO("largest distance to the damped contact run " << apart << " m, its speed " << sim.max_speed() << " m/s");
  CHECK(sim.max_speed() < 1e-3);
  CHECK(apart < 1e-3);
}

TEST_CASE("a sheet falling onto a small ball drapes over it and no step passes through", "[static]") {
  const BallScene b = ball_scene();
  ClothSimulator sim(b.mesh.V, b.mesh.F);
  sim.set_pinned(b.pins);
  Eigen::MatrixXd X = b.start;
  StaticSolver solver;
  const Eigen::VectorXd offsets = Eigen::VectorXd::Constant(b.mesh.V.rows(), b.offset);
  const StaticSolveReport r = solver.solve(sim, StaticBody{sphere(Eigen::Vector3d::Zero(), b.radius), {}}, offsets, X);
  INFO(r.iterations << " iterations, residual " << r.residual << ", " << r.contacts << " vertices in the band");
  REQUIRE(r.converged);
  CHECK(r.contacts > 0);
  const double closest = closest_to_ball(X);
  INFO("closest vertex " << closest << " m from the ball");
  CHECK(closest > b.offset - 0.5 * solver.options().barrier_band);
  CHECK(closest < b.offset + 0.5 * solver.options().barrier_band);
  // The middle of the sheet rests on top of the ball, not below it.
  CHECK(X(b.middle, 1) > b.radius);
}

TEST_CASE("contact as an active set: a strip draped over a cylinder rests where the barrier's and a long "
          "damped settle's do, its residual below the tolerance",
          "[static]") {
  const double R = 0.1, offset = 0.005;
  const DrapedStrip strip = draped_strip();
  SimulatorOptions so;
  so.dt = 0.0025;
  ClothSimulator sim(strip.mesh.V, strip.mesh.F, ClothParameters{}, so);
  sim.set_pinned(strip.pins);
  const Eigen::VectorXd offsets = Eigen::VectorXd::Constant(strip.mesh.V.rows(), offset);
  const StaticBody body{cylinder(R), {}};

  StaticSolveOptions held_options;
  held_options.contact = StaticContact::active_set;
  StaticSolver held(held_options);
  Eigen::MatrixXd X = strip.start;
  const StaticSolveReport a = held.solve(sim, body, offsets, X);
  INFO("active set: " << a.iterations << " iterations, residual " << a.residual << ", " << a.contacts
                      << " vertices held, " << a.released << " releases");
  REQUIRE(a.converged);
  CHECK(a.residual < held_options.tolerance);
  CHECK(a.contacts > 10);  // the strip lies over the cylinder's top
  double min_radius = 0.0;
  const double recomputed = held_residual(sim, X, R, offset, min_radius);
  CHECK(recomputed < held_options.tolerance);
  CHECK(recomputed == Approx(a.residual).epsilon(1e-3));
  // Held at the offset, no vertex within it.
  CHECK(min_radius > R + offset - 1e-6);
  CHECK(min_radius < R + offset + 1e-5);

  // The barrier with a narrow band (it rests within a quarter millimetre of the offset).
  StaticSolveOptions barrier_options;
  barrier_options.barrier_band = 5e-4;
  StaticSolver barrier(barrier_options);
  Eigen::MatrixXd Y = strip.start;
  const StaticSolveReport b = barrier.solve(sim, body, offsets, Y);
  INFO("barrier: " << b.iterations << " iterations, residual " << b.residual);
  REQUIRE(b.converged);
  const double to_barrier = (X - Y).rowwise().norm().maxCoeff();
  INFO("largest distance between the two equilibria " << to_barrier << " m");
  CHECK(to_barrier < 1e-3);

  // Eight seconds of damped steps with velocity constraints at the offset end within 1 mm of it.
  gp::cloth::testing::FunctionContact step_body;
  cylinder_contact(step_body, R + offset);
  sim.set_contact(&step_body);
  sim.set_positions(strip.start);
  for (int s = 0; s < 3200; ++s) sim.step();
  const double to_dynamic = (sim.positions() - X).rowwise().norm().maxCoeff();
  INFO("largest distance to the damped settle " << to_dynamic << " m, its speed " << sim.max_speed() << " m/s");
  CHECK(sim.max_speed() < 1e-3);
  CHECK(to_dynamic < 1e-3);
}

TEST_CASE("contact as an active set: a strip pulled off the cylinder is released from it", "[static]") {
  const double R = 0.1, offset = 0.005;
  const DrapedStrip strip = draped_strip();
  ClothSimulator sim(strip.mesh.V, strip.mesh.F);
  sim.set_pinned(strip.pins);
  const Eigen::VectorXd offsets = Eigen::VectorXd::Constant(strip.mesh.V.rows(), offset);
  const StaticBody body{cylinder(R), {}};
  StaticSolveOptions o;
  o.contact = StaticContact::active_set;
  StaticSolver solver(o);
  Eigen::MatrixXd X = strip.start;
  const StaticSolveReport on = solver.solve(sim, body, offsets, X);
  REQUIRE(on.converged);
  REQUIRE(on.contacts > 10);
  // The pins lifted 28 cm: the strip, 0.6 m between pins 0.56 m apart, sags about 10 cm below them,
  // clear of the cylinder's top (0.105 m) by more than 8 cm, if its held vertices let go.
  for (int v : strip.pins) X(v, 1) = 0.3;
  const StaticSolveReport off = solver.solve(sim, body, offsets, X);
  INFO(off.iterations << " iterations, residual " << off.residual << ", " << off.released << " releases, "
                      << off.contacts << " vertices held at the end");
  REQUIRE(off.converged);
  CHECK(off.released >= on.contacts);
  CHECK(off.contacts == 0);
  double min_radius = 0.0;
  CHECK(held_residual(sim, X, R, offset, min_radius) < o.tolerance);
  CHECK(min_radius > R + offset + 0.05);
}

TEST_CASE("contact as an active set: a sheet falling onto a small ball drapes over it and no step passes through",
          "[static]") {
  const BallScene b = ball_scene();
  ClothSimulator sim(b.mesh.V, b.mesh.F);
  sim.set_pinned(b.pins);
  Eigen::MatrixXd X = b.start;
  StaticSolveOptions o;
  o.contact = StaticContact::active_set;
  StaticSolver solver(o);
  const Eigen::VectorXd offsets = Eigen::VectorXd::Constant(b.mesh.V.rows(), b.offset);
  const StaticSolveReport r = solver.solve(sim, StaticBody{sphere(Eigen::Vector3d::Zero(), b.radius), {}}, offsets, X);
  INFO(r.iterations << " iterations, residual " << r.residual << ", " << r.contacts << " vertices held");
  REQUIRE(r.converged);
  CHECK(r.contacts > 0);
  const double closest = closest_to_ball(X);
  INFO("closest vertex " << closest << " m from the ball");
  CHECK(closest > b.offset - 1e-6);
  CHECK(X(b.middle, 1) > b.radius);
}

TEST_CASE("the static solve refuses bad input", "[static]") {
  const gp::Mesh m = hanging_square();
  ClothSimulator sim(m.V, m.F);
  StaticSolver solver;
  Eigen::MatrixXd X = m.V;
  Eigen::VectorXd offsets = Eigen::VectorXd::Zero(m.V.rows());
  Eigen::MatrixXd wrong = m.V.topRows(3);
  CHECK_THROWS_AS(solver.solve(sim, {}, offsets, wrong), gp::UsageError);
  CHECK_THROWS_AS(solver.solve(sim, {}, offsets.head(3), X), gp::UsageError);
  X(5, 1) = std::nan("");
  CHECK_THROWS_AS(solver.solve(sim, {}, offsets, X), gp::NumericalError);
  StaticSolveOptions bad;
  bad.tolerance = 0.0;
  CHECK_THROWS_AS(StaticSolver(bad), gp::UsageError);
  bad = StaticSolveOptions{};
  bad.min_step = 1.0;
  CHECK_THROWS_AS(StaticSolver(bad), gp::UsageError);
  bad = StaticSolveOptions{};
  bad.release_force = -1.0;
  CHECK_THROWS_AS(StaticSolver(bad), gp::UsageError);
}
