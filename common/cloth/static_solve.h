#pragma once
// The cloth's static equilibrium against a still body, solved directly: the minimum of the
// potential
//   E(x) = E_membrane(x) + E_bend(x) + E_gravity(x) + sum_i B_i(d_i(x_i))
// over the free vertices (pinned ones held where they are), by Newton's method with a line search.
//
// Contact is a barrier on the distances d of each vertex to the body's triangles (the incremental
// potential contact of Li et al. 2020, "Incremental Potential Contact", sec. 4, point against
// triangle; see StaticBody):
//   B_i = sum_d kappa a_i g phi(s),  s = (d - w_i) / g,  phi(s) = -(s - 1)^2 ln s  for s < 1, else 0,
// with a_i the vertex's rest area [m^2], kappa a pressure [Pa] (kappa |phi'(s)| is the contact
// pressure at s; |phi'(1/2)| = 1.19), g the band where the barrier acts and w_i its wall, half the
// band below the vertex's comfort offset (lower where the vertex starts below that): cloth pressed
// onto the body rests near the offset, as the damped steps' hard offset holds it. The Hessian keeps
// B'' n n^T + B' Hess(d), Hess(d) the curvature of the distance to a feature ((I - n n^T) / d at a
// vertex, less the edge direction's part at an edge, 0 at an interior), projected to PSD per vertex
// as the membrane's Hessian is per triangle: the curvature term (negative where the barrier pushes)
// lets a vertex slide around a body edge it is pressed onto in one step instead of many.
//
// Each iteration solves, like an implicit Euler step from rest with pseudo time step tau [s],
//   (M / tau^2 + H_psd + k_bend Q + sum_i Hess(B_i)_psd) dx = -grad E(x)
// M / tau^2 is a proximal term towards the current iterate in the mass metric: it makes the
// directions only bending holds (a free hem that can buckle) well posed and the iterates
// deterministic, and fades against the membrane stiffness as tau grows (towards Newton's method):
// tau doubles after a full step and shrinks to a quarter after a step the line search cut below
// 1/10. The line search backtracks (Armijo) from the largest step that keeps every vertex outside
// its wall and moves no vertex near the body by more than `max_displacement` (a vertex whose
// displacement stays below its distance to the wall cannot reach it, whatever the path), so no
// step passes through the body.
//
// Converged: the force residual, the root mean square of grad E over the free vertices in units of
// their mean weight m g, is below `tolerance`. No damping, no velocities: the result is where the
// cloth comes to rest, not how.
//
// Contact as an active set (StaticSolveOptions::contact active_set) instead of the barrier: the
// potential is the cloth's alone, and the body is the constraint d_i(x_i) >= l_i on each free
// vertex, l_i its comfort offset (at most half the room in a pinch), the level the damped steps'
// hard offset holds. A vertex at its level (within 1 micrometre), or held in the last iteration and
// within the band of it, is held: the Newton step prescribes its displacement along the body's
// outward normal n (n . dx = max(l - d, 0), at most max_displacement; the same filtered system the
// time steps solve, cloth/contact_set.h, with sol = dx / tau), and leaves it free along the body. A
// vertex in a crease is held along a second normal, to the body feature at its level most inclined
// to the first (down to 0.6 degrees apart). The Lagrange force on a held normal at the iterate,
// lambda = n . grad E, is the body's push; where it would have to pull the vertex towards the body
// by more than `release_force`, that normal is let go before the step (the vertex, or only its
// crease's second side). The line search takes the trial
// points x + alpha dx with every vertex that ended below its level moved out to it along the body's
// normal (a projected search), under the same safe-step limit as the barrier's, with the wall at the
// level: no step passes through the body. The force residual at an active-set iterate leaves out, at
// a held vertex, the part of grad E that presses it onto the body (the body bears it); a pull away
// from the body counts in full.
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cloth/cloth_simulator.h"

namespace gp::cloth {

// The body as seen from one point: signed distance [m] (negative inside), the unit direction from the
// closest body point towards the point's free side, and the room [m] in front of the closest point
// (the distance along `outward` to the next body surface, infinity when none): in a pinch the wall is
// at most half the room.
struct BodyDistance {
  double signed_distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d outward = Eigen::Vector3d::UnitY();
  double room = std::numeric_limits<double>::infinity();
};
// The body's distance at point p for cloth vertex `vertex` (a warm-start key); must depend on p and
// the body alone (the line search compares trial points). `with_room` false: room may be left
// infinite (it is read once per iteration, at the iterate).
using BodyDistanceQuery = std::function<BodyDistance(int vertex, const Eigen::Vector3d& p, bool with_room)>;
// A feature of the body's triangles (an interior, an edge or a vertex) near a point: its closest
// point and what the distance's curvature needs (an edge's direction).
struct BodyFeature {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  int kind = 0;  // 0 a triangle's interior, 1 an edge, 2 a vertex
  Eigen::Vector3d edge = Eigen::Vector3d::Zero();  // unit, for an edge
};
// Every feature whose closest point lies within `radius` of p, each once, appended to `features`.
using BodyFeatureQuery =
    std::function<void(const Eigen::Vector3d& p, double radius, std::vector<BodyFeature>& features)>;

// The body of a static solve. With `features`, a vertex outside the body meets a barrier per body
// feature within its band, on the distance to that feature (smooth where the closest triangle
// changes, as in a crease: the closest point alone turns its direction there by a jump, and Newton's
// method stalls on it); a vertex inside meets the closest point's signed distance alone. Without
// `features`, every vertex meets the closest point alone (a smooth body such as an analytic sphere).
struct StaticBody {
  BodyDistanceQuery distance;  // empty: no body
  BodyFeatureQuery features;
};
// How the static solve meets the body (see the top of this header).
enum class StaticContact { barrier, active_set };
// Each way with its name in options and reports ("barrier", "active_set").
const std::vector<std::pair<StaticContact, const char*>>& static_contact_names();

// Defaults measured in common/cloth/README.md ("The static solve").
struct StaticSolveOptions {
  StaticContact contact = StaticContact::barrier;
  double tolerance = 0.01;      // force residual of an equilibrium [mean vertex weights, RMS]
  int max_iterations = 300;     // Newton iterations of solve()
  double barrier_pressure = 1000.0;  // kappa [Pa]
  double barrier_band = 0.002;       // g: the barrier acts this far above the wall [m]
  double max_displacement = 0.01;    // per iteration, for a vertex within reach of its wall [m]
  double initial_step = 0.05;        // pseudo time step tau at the first iteration [s]
  double max_step = 10.0;            // [s]
  double min_step = 1e-3;            // the solve gives up below it [s]
  // active_set: a held vertex that the body would have to pull towards it by more than this is
  // released [mean vertex weights m g, the residual's unit]: at most the tolerance, since a vertex
  // held against its pull keeps its pull in the residual.
  double release_force = 0.01;
};

struct StaticSolveReport {
  bool converged = false;
  int iterations = 0;              // Newton iterations (systems solved)
  double residual = 0.0;           // force residual at the returned positions [mean vertex weights]
  std::vector<double> residuals;   // at each iterate, the first at the start
  long line_search_trials = 0;     // energy evaluations of trial points
  int contacts = 0;                // vertices within the barrier's band (active_set: held) at the end
  long released = 0;               // active_set: vertices released over the iterations (a vertex may count often)
  double energy = 0.0;             // E at the returned positions [J]
};

// Solves for the equilibrium from positions X (#V by 3; the pinned vertices of `sim` stay at their
// rows of X) with the material, rest state and pins of `sim`, against the body `body` (none when
// empty) with per-vertex comfort offsets `offsets` (#V) [m]. Returns the positions in X. Throws
// UsageError on a size mismatch, NumericalError when the linear solve fails.
class StaticSolver {
 public:
  explicit StaticSolver(const StaticSolveOptions& options = {});
  ~StaticSolver();
  StaticSolver(StaticSolver&&) noexcept;
  StaticSolver& operator=(StaticSolver&&) noexcept;

  StaticSolveReport solve(const ClothSimulator& sim, const StaticBody& body, const Eigen::VectorXd& offsets,
                          Eigen::MatrixXd& X);
  // The same with at most `max_iterations` Newton iterations, starting from the pseudo time step the
  // last solve ended with (an equilibrium sought in parts, the rest shape adapted between them).
  StaticSolveReport resume(const ClothSimulator& sim, const StaticBody& body, const Eigen::VectorXd& offsets,
                           Eigen::MatrixXd& X, int max_iterations);
  // The next resume() starts from options().initial_step again (another equilibrium).
  void restart();
  const StaticSolveOptions& options() const;
  // Accumulated over every solve [s]: forces_assembly (the system and the energy at the iterate),
  // factorization, solve, collisions (the body's distances and the barrier at the iterate), checks
  // (the line search); factorizations and CG iterations.
  const PhaseTimes& times() const;
  const SolverCounters& counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The barrier's energy phi(s) = -(s - 1)^2 ln s on (0, 1), 0 at and above 1, and its first and second
// derivatives (infinite energy at s <= 0).
double barrier_phi(double s);
double barrier_phi_d1(double s);
double barrier_phi_d2(double s);

}  // namespace gp::cloth
