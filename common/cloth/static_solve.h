#pragma once
// The cloth's static equilibrium against a still body, solved directly: the minimum of
//   E(x) = E_membrane(x) + E_bend(x) + E_gravity(x) + contact
// over the free vertices by Newton's method with a line search, each iteration an implicit Euler
// step from rest with pseudo time step tau, so that M / tau^2 regularises the directions only
// bending holds (a free hem that can buckle). Contact is a barrier (Li et al. 2020, "Incremental
// Potential Contact", sec. 4) or an active set of vertices held along the body's normal (Baraff &
// Witkin 1998, sec. 5.3); either way the line search keeps every vertex outside its wall, so no step
// passes through the body. Converged: the force residual (RMS of grad E over the free vertices, in
// their mean weight m g) is below the tolerance. The method in full: cloth/README.md, "The static
// solve".
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
