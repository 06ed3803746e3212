#include "adapt/garment_motion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "cloth/cloth_model.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "core/union_find.h"
#include "mesh/measures.h"
#include "mesh/point_triangle.h"

namespace gp::adapt {
namespace {


// The room reported in front of cloth the body holds is sought this far [m].
constexpr double kHeldGapRadius = 0.05;

cloth::ClothParameters parameters_from(const Material& m) {
  cloth::ClothParameters p;
  p.k_stretch = m.k_stretch;
  p.k_stretch_weft = m.k_stretch_weft;  // the fabric's weft (common/fabric/README.md)
  p.k_shear = m.k_shear;
  p.k_bend = m.k_bend;
  p.damping_stretch = m.damping_stretch;
  p.damping_shear = m.damping_shear;
  p.damping_bend = m.damping_bend;
  p.density = m.density;
  p.compression_ratio = m.compression_ratio;
  if (m.turned_grain()) p.grain_angles = m.grain_angles;  // a bias-cut region (garment_file.h)
  return p;
}

void check_options(const MotionRunOptions& options) {
  if (options.schedule.substeps < 1 || options.adaptation.every < 1 || options.settle.max_steps < 0 || options.schedule.threads < 1) {
    throw UsageError("substeps, adapt_every and threads must be at least 1, settle_max_steps non-negative");
  }
  if (options.schedule.adaptation_lag < 0) {
    throw UsageError("the adaptation lag must be non-negative, got " + std::to_string(options.schedule.adaptation_lag));
  }
  if (!(options.adaptation.max_area_growth > 1.0)) throw UsageError("max_area_growth must be above 1");
  if (!(options.adaptation.speed > 0.0) || !std::isfinite(options.adaptation.speed)) {
    throw UsageError("adapt_speed must be finite and positive");
  }
  if (!(options.settle.damping >= 0.0) || !std::isfinite(options.settle.damping)) {
    throw UsageError("settle_damping must be finite and non-negative");
  }
  check_options(options.contact);
  if (options.schedule.frame_stride < 0) {
    throw UsageError("frame_stride must be non-negative, got " + std::to_string(options.schedule.frame_stride));
  }
  if (!options.rest_triangles.empty() && options.adaptation.enabled) {
    throw UsageError("per-face rest triangles need adapt off (the rest shape is then fixed)");
  }
}

// A body stage of the motion: the interpolation parameters of one step's body.
struct BodyRequest {
  int from, to;
  double t;
};

// A body stage made ready for the step: positions, pin targets and the
// collision tree with the body's velocity since the previous stage.
struct BodyStage {
  Eigen::MatrixXd V, targets;
  collision::BodyFrame frame;
  double seconds = 0.0;  // interpolation and pin targets (the tree's time is the collider's)
};

// A rest shape computed from the positions after some step, applied later.
struct Adaptation {
  Eigen::MatrixXd V_rest;
  AdaptReport report;
  double seconds = 0.0;
};

}  // namespace

const std::vector<std::pair<Equilibrium, const char*>>& equilibrium_names() {
  static const std::vector<std::pair<Equilibrium, const char*>> names = {{Equilibrium::static_solve, "static"},
                                                                         {Equilibrium::dynamic, "dynamic"}};
  return names;
}

int applied_adaptation_lag(const MotionRunOptions& options) {
  return std::max(0, std::min(options.schedule.adaptation_lag, options.adaptation.every - 1));
}

struct GarmentMotion::Impl {
  PoseInterpolator& interpolator;
  const MotionSpec& motion;
  const Eigen::MatrixXi F;
  const GarmentFile& garment;
  const MotionRunOptions options;
  const std::vector<MotionFrame> frames;
  const Clock::time_point start = Clock::now();
  MotionRunResult result;

  // Pins: the bound vertices of pinned loops and their bindings.
  std::vector<int> pin_ids;
  std::vector<SurfacePoint> pin_binding;
  std::vector<int> pin_hints;  // warm starts of the pin targets' body queries

  Eigen::MatrixXd V_body, targets;  // the current body stage
  // The body as the cloth meets it: the body and its hand hulls, the
  // collider, the continuous contact and the per-vertex offsets (a vertex
  // that starts inside the garment's offset is pushed out at
  // initial_push_speed: a push of centimetres in one step tears the cloth in
  // concave regions, armpits, between arm and torso).
  std::optional<BodyContact> body;
  std::optional<cloth::ClothSimulator> sim;
  std::optional<cloth::StaticSolver> static_solver;  // Equilibrium::static_solve

  std::vector<int> adapt_frames;  // options.adaptation.frames, sorted

  std::optional<RestShapeAdapter> adapter;
  Eigen::MatrixXd V_rest;
  double design_area = 0.0;
  bool settling = false;  // at a key pose, the body standing still
  bool cloth_slow = false;  // settling, and the cloth has slowed below adaptation.speed

  // Work beside the stepping thread (MotionRunOptions::schedule.threads): the next
  // body stage and the lagging adaptation.
  const std::launch policy;
  const int lag;
  std::future<Adaptation> pending_adaptation;
  long apply_after_step = 0;
  std::vector<BodyRequest> requests;
  size_t next_request = 0;
  std::future<BodyStage> next_stage;

  Impl(PoseInterpolator& interp, const MotionSpec& m, const Eigen::MatrixXd& V_garment, const Eigen::MatrixXi& F_,
       const GarmentFile& g, const MotionRunOptions& o)
      : interpolator(interp),
        motion(m),
        F(F_),
        garment(g),
        options(o),
        frames(motion_frames(m)),
        policy(o.schedule.threads > 1 ? std::launch::async : std::launch::deferred),
        lag(applied_adaptation_lag(o)) {
    check_options(options);
    if (frames.empty()) throw SpecError("the motion has no frames");
    adapt_frames = options.adaptation.frames;
    std::sort(adapt_frames.begin(), adapt_frames.end());
    for (int f : adapt_frames) {
      if (f <= 0 || f >= static_cast<int>(frames.size()) || frames[static_cast<size_t>(f)].key >= 0) {
        throw UsageError("adaptation frame " + std::to_string(f) + " is not an in-between frame of the motion (" +
                         std::to_string(frames.size()) + " frames)");
      }
    }
    bind_pins(V_garment);
    set_up_body(V_garment);
    set_up_cloth(V_garment);
    set_up_adaptation(V_garment);
    plan_body_stages();
  }

  void bind_pins(const Eigen::MatrixXd& V_garment) {
    std::set<int> seen;
    for (const GarmentLoop& loop : garment.loops) {
      if (!loop.pinned || loop.binding.size() != loop.vertex_ids.size()) continue;
      for (size_t k = 0; k < loop.vertex_ids.size(); ++k) {
        const int v = loop.vertex_ids[k];
        if (v < 0 || v >= V_garment.rows()) throw GeometryError("pinned vertex id out of range", "loop " + loop.name);
        if (!seen.insert(v).second) continue;
        pin_ids.push_back(v);
        pin_binding.push_back(loop.binding[k]);
      }
    }
  }

  Eigen::MatrixXd pin_targets(const Eigen::MatrixXd& V) const {
    const Eigen::MatrixXi& F_body = interpolator.faces();
    const Eigen::MatrixXd N = vertex_normals(V, F_body);
    Eigen::MatrixXd T(pin_ids.size(), 3);
    for (size_t k = 0; k < pin_ids.size(); ++k) {
      T.row(k) = evaluate_binding(V, N, F_body, pin_binding[k], garment.offset).transpose();
    }
    return T;
  }

  void set_up_body(const Eigen::MatrixXd& V_garment) {
    const auto t0 = Clock::now();
    V_body = interpolator.frame(frames[0].from, frames[0].to, frames[0].t);
    targets = pin_targets(V_body);
    result.times.body += seconds_since(t0);
    const Eigen::MatrixXi& F_body = interpolator.faces();
    // The hulls from the pose the garment was designed (and cleared) on.
    const std::vector<std::string>& names = interpolator.pose_names();
    const auto design = std::find(names.begin(), names.end(), garment.body.design_pose);
    collision::ContactSurface surface = collision::contact_surface(
        design != names.end() ? interpolator.pose(static_cast<int>(design - names.begin())) : V_body, F_body,
        options.contact.surface);
    // The faces the garment can reach in the first frame or in any key pose:
    // a hand that hangs far from the skirt at the start comes down onto it
    // later (culled by the first frame alone, it passed through the skirt:
    // the demo-dress's hands on the thighs, 101 crossings).
    std::vector<int> reachable =
        collision::reachable_body_faces(surface.positions(V_body), surface.F, V_garment, options.contact.reach);
    std::set<int> key_poses;  // a pose the motion returns to is searched once
    for (const MotionKey& key : motion.keys) key_poses.insert(key.pose_index);
    for (int pose : key_poses) {
      const std::vector<int> more = collision::reachable_body_faces(surface.positions(interpolator.pose(pose)),
                                                                    surface.F, V_garment, options.contact.reach);
      reachable.insert(reachable.end(), more.begin(), more.end());
    }
    std::sort(reachable.begin(), reachable.end());
    reachable.erase(std::unique(reachable.begin(), reachable.end()), reachable.end());
    body.emplace(std::move(surface), V_body, std::move(reachable), F, V_garment, pin_ids, garment.offset,
                 options.contact, options.schedule.threads);
    result.contact_surface = body->surface();
    result.culled_body_faces = body->collider().face_ids().size();
    pin_hints.assign(pin_ids.size(), -1);
    clear_pin_targets();
    result.initial_crossings = body->initial_crossings();
    result.continuous_contact = body->continuous_active();
    result.initial_min_distance = body->initial_min_distance();
  }

  void set_up_cloth(const Eigen::MatrixXd& V_garment) {
    sim.emplace(V_garment, F, parameters_from(garment.material), options.solver);
    sim->set_pinned(pin_ids);
    if (!options.rest_triangles.empty()) sim->set_rest_triangles(options.rest_triangles);

    sim->set_contact(&*body);
  }

  void set_up_adaptation(const Eigen::MatrixXd& V_garment) {
    adapter.emplace(V_garment, F, with_fabric_limits(options.adaptation.adapter, garment.material));
    design_area = mesh_area(V_garment, F);
    V_rest = V_garment;
    if (options.initial_rest.size()) {
      if (options.initial_rest.rows() != V_garment.rows() || options.initial_rest.cols() != 3) {
        throw UsageError("the initial rest shape must be #V by 3 like the garment");
      }
      V_rest = options.initial_rest;
      sim->set_rest_shape(V_rest);
    }
    // Paint (T3) is part of the design: applied once, with or without
    // adaptation, unless the rest is given as final (rest triangles, or a
    // later cycle's rest shape, which holds its paint already).
    bool painted = false;
    for (double p : garment.paint) painted = painted || p != 1.0;
    if (!painted || !options.rest_triangles.empty() || options.initial_rest.size()) return;
    if (garment.paint.size() != static_cast<size_t>(F.rows())) {
      throw GeometryError("paint has " + std::to_string(garment.paint.size()) + " factors for " +
                          std::to_string(F.rows()) + " faces");
    }
    const Eigen::VectorXd factors = Eigen::Map<const Eigen::VectorXd>(garment.paint.data(), garment.paint.size());
    const auto ta = Clock::now();
    record_adaptation(adapter->adapt(V_rest, V_rest, &factors));
    result.times.adaptation += seconds_since(ta);
  }

  // The body stages after frame 0 in order: each frame's `substeps`
  // interpolated bodies, so that a step never sees more than its share of the
  // body's motion within the frame.
  void plan_body_stages() {
    for (size_t i = 1; i < frames.size(); ++i) {
      const MotionFrame& frame = frames[i];
      const MotionFrame& previous = frames[i - 1];
      const double t_start = previous.transition == frame.transition ? previous.t : 0.0;
      for (int s = 1; s <= options.schedule.substeps; ++s) {
        const double w = static_cast<double>(s) / options.schedule.substeps;
        requests.push_back({frame.from, frame.to, (1.0 - w) * t_start + w * frame.t});
      }
    }
  }

  // Depends on the body alone, so with threads > 1 the next stage is prepared
  // on the worker while the cloth steps through the current one.
  BodyStage prepare_stage(BodyRequest r, const Eigen::MatrixXd& V_previous) const {
    const auto t_stage = Clock::now();
    BodyStage stage;
    stage.V = interpolator.frame(r.from, r.to, r.t);
    stage.targets = pin_targets(stage.V);
    stage.seconds = seconds_since(t_stage);
    stage.frame = body->prepare(stage.V, V_previous, options.solver.dt);
    return stage;
  }

  void request_next_stage() {
    if (next_request >= requests.size()) return;
    next_stage = std::async(
        policy, [this](BodyRequest r, Eigen::MatrixXd V_previous) { return prepare_stage(r, V_previous); },
        requests[next_request++], V_body);
  }

  // The result of work launched with `policy`; the time the stepping thread
  // waited for the worker is counted (run in turn, it is the work's own time).
  template <class T>
  T await(std::future<T>& future) {
    const auto t_wait = Clock::now();
    T value = future.get();
    if (policy == std::launch::async) result.times.waiting += seconds_since(t_wait);
    return value;
  }

  void move_to_next_stage() {
    BodyStage stage = await(next_stage);
    result.times.body += stage.seconds;
    body->move_to(std::move(stage.frame), stage.V);
    V_body = std::move(stage.V);
    targets = std::move(stage.targets);
    clear_pin_targets();
    request_next_stage();
  }

  // The pin targets moved out to their clearance from the current body
  // (BodyContactOptions::pin_clearance).
  void clear_pin_targets() {
    const auto t0 = Clock::now();
    body->keep_pins_off(targets, pin_hints, result.pins);
    result.times.body += seconds_since(t0);
  }

  void record_adaptation(const AdaptReport& r) {
    if (!r.changed) return;
    if (r.area_after > options.adaptation.max_area_growth * design_area) {
      char what[200];
      std::snprintf(what, sizeof(what),
                    "the rest shape grew to x%.2f the design's area (at most x%.2f): the adaptation runs away where "
                    "the cloth cannot follow its rest shape",
                    r.area_after / design_area, options.adaptation.max_area_growth);
      throw NumericalError(what, "step " + std::to_string(result.steps));
    }
    sim->set_rest_shape(V_rest);
    ++result.adaptations;
    result.arap.iterations += r.arap.iterations;
    result.arap.max_iterations = std::max(result.arap.max_iterations, r.arap.iterations);
    result.arap.max_residual = std::max(result.arap.max_residual, r.arap.residual);
    result.arap.converged = result.arap.converged && r.arap.converged;
  }

  // Lagging adaptations (MotionRunOptions::schedule.adaptation_lag): the one computed
  // from the positions after step k runs beside the next steps and is applied
  // after step k + lag, or before any adaptation at the end of a key pose.
  void apply_adaptation() {
    if (!pending_adaptation.valid()) return;
    Adaptation a = await(pending_adaptation);
    result.times.adaptation += a.seconds;
    V_rest = std::move(a.V_rest);
    record_adaptation(a.report);
  }

  void launch_adaptation() {
    const RestShapeAdapter& a = *adapter;

    pending_adaptation = std::async(
        policy,
        [&a](Eigen::MatrixXd X, Eigen::MatrixXd V) {
          const auto ta = Clock::now();
          Adaptation out;
          out.report = a.adapt(X, V);
          out.V_rest = std::move(V);
          out.seconds = seconds_since(ta);
          return out;
        },
        sim->positions(), V_rest);
    apply_after_step = result.steps + lag;
  }

  void adapt_now() {
    apply_adaptation();
    const auto ta = Clock::now();
    record_adaptation(adapter->adapt(sim->positions(), V_rest));
    result.times.adaptation += seconds_since(ta);
  }

  // One simulation step towards the pin targets, with the adaptations it is due.
  void step() {
    sim->set_pin_targets(targets);
    body->advance_offsets(options.solver.dt);
    sim->step();
    ++result.steps;
    if (result.steps >= apply_after_step) apply_adaptation();
    const bool adapting = options.adaptation.enabled && ((settling && cloth_slow) || options.adaptation.during_transitions);
    if (adapting && result.steps % options.adaptation.every == 0) {
      launch_adaptation();
      if (lag == 0) apply_adaptation();
    }
  }

  // Largest principal stretch per face against the rest triangles the
  // simulator uses (the rest shape's, or given ones such as a sewn pattern's).
  Eigen::VectorXd largest_stretches() const {
    // A fabric with limits of its own: every direction against its own limit,
    // in units of the fit's 1 + delta (common/fabric/README.md, "Stretch limits").
    const Material& m = garment.material;
    if (m.has_own_limits())
      return (1.0 + options.adaptation.adapter.delta) *
             cloth::face_limit_stretches(sim->positions(), F, sim->rest_state(), m.stretch_limit_warp, m.stretch_limit_weft);
    return cloth::face_principal_stretches(sim->positions(), F, sim->rest_state()).col(0);
  }

  void report(const ProgressCallback& progress, std::string line, int key, size_t frame, int settle_steps,
              bool key_done, double max_stretch) const {
    if (!progress) return;
    progress({std::move(line), key, static_cast<int>(motion.keys.size()), frame, frames.size(), result.steps,
              settle_steps, key_done, max_stretch});
  }

  // The body stops at a key pose: step until the cloth is slow, its largest
  // stretch steady and (with adaptation) the rest area a fixed point, or the cap.
  void settle(KeyPoseResult& key, size_t frame_index, const ProgressCallback& progress) {
    double previous_stretch = largest_stretches().maxCoeff();
    // Rest area at every check, for the fixed-point test: with adaptation the
    // key pose is settled only once the rest area has changed by less than
    // fixed_point_area_change over the last fixed_point_steps steps.
    std::vector<std::pair<int, double>> area_history{{0, mesh_area(V_rest, F)}};
    auto area_change_over_window = [&]() {
      const double now = area_history.back().second;
      double change = 0.0;
      for (auto it = area_history.rbegin(); it != area_history.rend(); ++it) {
        change = std::max(change, std::abs(now - it->second) / now);
        if (key.settle_steps - it->first >= options.settle.fixed_point_steps) break;
      }
      return change;
    };
    sim->set_damping_scale(options.settle.damping);
    settling = true;
    cloth_slow = false;
    int slow_since = 0;  // settle steps when the cloth slowed below adaptation.speed
    // Held cloth (MotionRunOptions::settle.held_steps): the lowest largest stretch
    // so far and the settle step it was reached at.
    double best_stretch = previous_stretch;
    int best_since = 0;
    while (key.settle_steps < options.settle.max_steps) {
      const Eigen::MatrixXd X_check = sim->positions();
      int window = 0;
      for (; window < options.adaptation.every && key.settle_steps < options.settle.max_steps;
           ++window, ++key.settle_steps) {
        step();
      }
      key.max_net_speed = (sim->positions() - X_check).rowwise().norm().maxCoeff() / (window * options.solver.dt);
      if (!cloth_slow && key.max_net_speed < options.adaptation.speed) {
        cloth_slow = true;
        slow_since = key.settle_steps;
      }
      const double stretch = largest_stretches().maxCoeff();
      const bool slow = key.max_net_speed < options.settle.speed;
      const bool steady = std::abs(stretch - previous_stretch) < options.settle.stretch_change;
      const double stretch_change = std::abs(stretch - previous_stretch);
      previous_stretch = stretch;
      area_history.emplace_back(key.settle_steps, mesh_area(V_rest, F));
      key.rest_area_change = area_change_over_window();
      const bool fixed = !options.adaptation.enabled || (cloth_slow && key.settle_steps - slow_since >= options.settle.fixed_point_steps &&
                                            key.rest_area_change < options.settle.fixed_point_area_change);
      if (progress && key.settle_steps % 40 == 0) {
        char line[256];
        std::snprintf(line, sizeof(line),
                      "settling %s: %d steps, max speed %.4f m/s (net %.4f), max stretch %.4f (change %.4f), "
                      "rest area change %.3f%% over the last %d steps",
                      key.pose.c_str(), key.settle_steps, sim->max_speed(), key.max_net_speed, stretch,
                      stretch_change, 100.0 * key.rest_area_change,
                      std::min(key.settle_steps, options.settle.fixed_point_steps));
        report(progress, line, key.key, frame_index, key.settle_steps, false, stretch);
      }
      if (slow && steady && fixed && body->offsets_grown()) {
        key.settled = true;
        break;
      }
      if (stretch < (1.0 - options.settle.held_improvement) * best_stretch) {
        best_stretch = stretch;
        best_since = key.settle_steps;
      }
      if (options.settle.held_steps > 0 && body->offsets_grown() && stretch > options.settle.held_stretch &&
          key.settle_steps - best_since >= options.settle.held_steps) {
        key.held = true;
        break;
      }
    }
    sim->set_damping_scale(1.0);
    settling = false;
    cloth_slow = false;
    if (options.settle.max_steps == 0) key.settled = sim->max_speed() < options.settle.speed;
    key.max_speed = sim->max_speed();
  }

  // The body stops at a key pose: its static equilibrium solved directly
  // (cloth/static_solve.h) and, with adaptation, the rest shape adapted there
  // and the equilibrium solved again until the rest area is a fixed point.
  // Cloth stretched beyond held_stretch at an equilibrium that the last
  // adaptation did not relieve by held_improvement is held by the body.
  // adapt: adapt the rest shape on the way to the fixed point (options.adaptation.enabled at a key pose or an
  // adaptation frame; an in-between frame that is only recorded is solved without).
  void settle_static(KeyPoseResult& key, size_t frame_index, const ProgressCallback& progress, bool adapt) {
    if (!static_solver) static_solver.emplace(options.settle.statics);
    key.solved_static = true;
    // The offsets are the garment's from here on: the barrier pushes a vertex
    // that is still inside its offset out gradually (its wall rises with it).
    body->use_garment_offsets();
    std::vector<int> hints;
    const cloth::StaticBody statics = body->static_body(hints, 3.0 * garment.offset + options.settle.statics.barrier_band);
    // With adaptation the equilibrium is sought in parts of adaptation.every
    // iterations; between them, once the cloth moves less than
    // adapt_displacement or its largest stretch is steady, the rest shape is
    // adapted to the cloth there (as the dynamic settling adapts once the
    // cloth is slow). Once an adaptation changes the rest area by less than
    // fixed_point_area_change, the equilibrium is converged without adapting
    // and the fixed point tested there: an adaptation at the converged cloth
    // that changes the area by less again ends the pose, after one more
    // solve of the last rest shape's equilibrium (its figures are those of a
    // true equilibrium). Adapting every part to the end, the tail of a fit
    // spent hundreds of iterations on changes of 0.01 % each: every
    // adaptation kicked the cloth off the equilibrium that the test needed
    // (adapt/README.md, "The static solve").
    enum class Phase { adapting, converging, final_solve };
    Phase phase = adapt ? Phase::adapting : Phase::final_solve;
    static_solver->restart();
    const int cap = options.settle.statics.max_iterations;
    double best_stretch = std::numeric_limits<double>::infinity();
    int best_at = 0;
    double last_change = std::numeric_limits<double>::infinity();
    double previous_stretch = largest_stretches().maxCoeff();
    const auto adapt_and_measure = [&]() {
      const double area_before = mesh_area(V_rest, F);
      adapt_now();
      last_change = std::abs(mesh_area(V_rest, F) - area_before) / area_before;
      key.rest_area_change = last_change;
      return last_change;
    };
    while (true) {
      Eigen::MatrixXd X = sim->positions();
      for (size_t k = 0; k < pin_ids.size(); ++k) X.row(pin_ids[k]) = targets.row(static_cast<Eigen::Index>(k));
      const int left = cap - key.newton_iterations;
      const int part = phase == Phase::adapting ? std::min(options.adaptation.every, left) : left;
      const Eigen::MatrixXd X_before = X;
      const cloth::StaticSolveReport r = static_solver->resume(*sim, statics, body->vertex_offsets(), X, part);
      result.newton_iterations += r.iterations;
      result.line_search_trials += r.line_search_trials;
      sim->set_positions(X);
      sim->set_velocities(Eigen::MatrixXd::Zero(X.rows(), 3));
      key.newton_iterations += r.iterations;
      key.settle_steps = key.newton_iterations;
      key.force_residual = r.residual;
      // The residual at each iterate; a part's first is the last one's end.
      key.force_residuals.insert(key.force_residuals.end(), r.residuals.begin() + (key.force_residuals.empty() ? 0 : 1),
                                 r.residuals.end());
      const double stretch = largest_stretches().maxCoeff();
      if (progress) {
        char line[256];
        std::snprintf(line, sizeof(line),
                      "solving %s: %d Newton iterations, force residual %.3g (tolerance %.3g), max stretch %.4f, "
                      "last rest area change %.3f%%",
                      key.pose.c_str(), key.newton_iterations, r.residual, options.settle.statics.tolerance, stretch,
                      std::isfinite(last_change) ? 100.0 * last_change : 100.0);
        report(progress, line, key.key, frame_index, key.settle_steps, false, stretch);
      }
      if (stretch < (1.0 - options.settle.held_improvement) * best_stretch) {
        best_stretch = stretch;
        best_at = key.newton_iterations;
      }
      if (options.settle.held_steps > 0 && stretch > options.settle.held_stretch &&
          key.newton_iterations - best_at >= options.settle.statics.held_iterations) {
        key.held = true;
        break;
      }
      const double moved = (X - X_before).rowwise().norm().maxCoeff();
      // Slow, or its largest stretch steady (a sleeve may still swing into
      // place while the cloth the body stretches stays as it is).
      const bool steady = std::abs(stretch - previous_stretch) < options.settle.stretch_change;
      previous_stretch = stretch;
      if (phase == Phase::adapting && (moved < options.settle.statics.adapt_displacement || steady || r.converged)) {
        if (adapt_and_measure() < options.settle.fixed_point_area_change) phase = Phase::converging;
      } else if (phase == Phase::converging && r.converged) {
        // The fixed-point test at the converged cloth.
        const double change = adapt_and_measure();
        if (change == 0.0) {  // nothing clipped: this equilibrium is the pose's
          key.settled = true;
          break;
        }
        phase = change < options.settle.fixed_point_area_change ? Phase::final_solve : Phase::adapting;
      } else if (phase == Phase::final_solve && r.converged) {
        key.settled = true;
        break;
      }
      if (key.newton_iterations >= cap) break;
    }
    key.max_speed = 0.0;
    key.max_net_speed = 0.0;
  }

  // Where the body holds the cloth: the patches of faces (joined by shared
  // vertices) stretched beyond held_stretch, most stretched first, each with
  // the body point nearest to its most stretched face and the room in front
  // of it (BodyCollider::gap).
  std::vector<HeldCloth> held_patches(const Eigen::VectorXd& stretch) const {
    std::vector<int> over;
    for (int f = 0; f < F.rows(); ++f) {
      if (stretch(f) > options.settle.held_stretch) over.push_back(f);
    }
    if (over.empty()) return {};
    UnionFind sets(over.size());
    std::vector<int> owner(static_cast<size_t>(sim->positions().rows()), -1);
    for (size_t i = 0; i < over.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        int& o = owner[static_cast<size_t>(F(over[i], k))];
        if (o < 0) {
          o = static_cast<int>(i);
        } else {
          sets.unite(o, static_cast<int>(i));
        }
      }
    }
    std::vector<std::vector<int>> groups(over.size());
    for (size_t i = 0; i < over.size(); ++i) groups[static_cast<size_t>(sets.find(static_cast<int>(i)))].push_back(over[i]);
    const collision::ContactSurface& surface = body->surface();
    const collision::BodyCollider& collider = body->collider();
    const Eigen::MatrixXd V_surface = surface.positions(V_body);
    std::vector<HeldCloth> patches;
    for (const std::vector<int>& g : groups) {
      if (g.empty()) continue;
      HeldCloth h;
      h.faces = g;  // ascending, as `over`
      int worst = g.front();
      for (int f : g) {
        if (stretch(f) > stretch(worst)) worst = f;
      }
      h.max_stretch = stretch(worst);
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) c += sim->positions().row(F(worst, k)).transpose() / 3.0;
      const collision::Proximity q = collider.query(c);
      h.position = q.closest;
      h.surface_face = q.face;
      h.barycentric = closest_point_on_triangle(q.closest, V_surface.row(surface.F(q.face, 0)).transpose(),
                                                V_surface.row(surface.F(q.face, 1)).transpose(),
                                                V_surface.row(surface.F(q.face, 2)).transpose())
                          .bary;
      h.gap = collider.facing_distance(q.closest, q.outward, kHeldGapRadius);
      h.region = region_of(V_surface, q.face, q.closest, h.body_vertex);
      patches.push_back(std::move(h));
    }
    std::stable_sort(patches.begin(), patches.end(),
                     [](const HeldCloth& a, const HeldCloth& b) { return a.max_stretch > b.max_stretch; });
    if (patches.size() > 5) patches.resize(5);
    return patches;
  }

  // A name for the contact surface's face f near point p (V_surface: the
  // surface's vertices in this frame): the hull it belongs to ("left hand":
  // the body faces +z, so its left is +x; feet are the hulls in the lowest
  // fifth of the body), else the nearest body vertex. Sets the nearest body
  // vertex.
  std::string region_of(const Eigen::MatrixXd& V_surface, int f, const Eigen::Vector3d& p, int& body_vertex) const {
    const collision::ContactSurface& surface = body->surface();
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const int v = surface.F(f, k);
      const double d = (V_surface.row(v).transpose() - p).norm();
      if (d < best) {
        best = d;
        body_vertex = v < surface.body_vertex_count ? v : surface.sources[static_cast<size_t>(v - surface.body_vertex_count)];
      }
    }
    if (!surface.is_hull_face(f)) return "body vertex " + std::to_string(body_vertex);
    const double low = V_body.col(1).minCoeff(), high = V_body.col(1).maxCoeff();
    const double mid_x = 0.5 * (V_body.col(0).minCoeff() + V_body.col(0).maxCoeff());
    const std::string side = p.x() > mid_x ? "left" : "right";
    return side + (p.y() < low + 0.2 * (high - low) ? " foot" : " hand");
  }

  // The key pose's drape and its stretch and penetration figures.
  void record(KeyPoseResult& key) {
    key.V_draped = sim->positions();
    key.face_max_stretch = largest_stretches();
    Eigen::VectorXd rest_areas(F.rows());
    for (int f = 0; f < F.rows(); ++f) rest_areas(f) = sim->rest_state().triangles[f].area;
    stretch_figures(key.face_max_stretch, rest_areas, 1.0 + options.adaptation.adapter.delta, key);
    int hint = -1;
    for (int v = 0; v < key.V_draped.rows(); ++v) {
      const collision::Proximity q = body->collider().query(key.V_draped.row(v).transpose(), hint);
      hint = q.face;
      key.deepest_penetration = std::max(key.deepest_penetration, -q.signed_distance);
    }
    key.crossings = collision::find_crossings(V_body, interpolator.faces(), key.V_draped, F);
    key.held_cloth = held_patches(key.face_max_stretch);
    // Given rest triangles (a verification, a sewn pattern) are the rest shape.
    key.rest_area_growth = (options.rest_triangles.empty() ? mesh_area(V_rest, F) : rest_areas.sum()) / design_area;
    key.steps = result.steps;
  }

  // The cloth settled at frame i with the body still, by the run's equilibrium, and adapted there
  // when `adapt`.
  void settle_pose(KeyPoseResult& key, size_t i, const ProgressCallback& progress, bool adapt) {
    if (options.settle.equilibrium == Equilibrium::static_solve) {
      settle_static(key, i, progress, adapt);
    } else {
      settle(key, i, progress);
      // And at the end of each pose, unless the body holds the cloth: its
      // figures are then those it was found held with.
      if (adapt && !key.held) adapt_now();
    }
  }

  // An in-between frame held still and recorded (result.frames). An adaptation frame settles and
  // adapts as a key pose does, and the transition goes on from there. Any other is observed: its
  // static equilibrium solved without adaptation, whatever the run's equilibrium (its figures must
  // not carry the cloth's inertia), from the cloth as the transition left it, which then goes on
  // as if the frame had not been solved, so the key poses are the same with or without observed
  // frames.
  void hold_frame(const MotionFrame& frame, size_t i, const ProgressCallback& progress, bool adapt) {
    const Eigen::MatrixXd X_moving = sim->positions(), V_moving = sim->velocities();
    BodyContact::Offsets offsets_moving = body->offsets();
    body->stand_still(V_body);
    KeyPoseResult f;
    f.key = frame.transition + 1;
    f.frame = static_cast<int>(i);
    f.transition = frame.transition;
    f.t = frame.t;
    char name[160];
    std::snprintf(name, sizeof(name), "%s to %s at %.3f", motion.keys[static_cast<size_t>(frame.transition)].pose.c_str(),
                  motion.keys[static_cast<size_t>(frame.transition) + 1].pose.c_str(), frame.t);
    f.pose = name;
    if (adapt) {
      settle_pose(f, i, progress, true);
      record(f);
    } else {
      settle_static(f, i, progress, false);
      record(f);
      sim->set_positions(X_moving);
      sim->set_velocities(V_moving);
      body->restore(std::move(offsets_moving));
    }
    result.frames.push_back(std::move(f));
  }

  MotionRunResult run(const ProgressCallback& progress) {
    result.times.setup = seconds_since(start);
    int since_key = 0;  // in-between frames since the last key pose
    request_next_stage();
    for (size_t i = 0; i < frames.size(); ++i) {
      const MotionFrame& frame = frames[i];
      if (i > 0) {
        for (int s = 1; s <= options.schedule.substeps; ++s) {
          move_to_next_stage();
          step();
        }
      }
      if (progress && i > 0 && i % 5 == 0 && frame.key < 0) {
        char line[200];
        std::snprintf(line, sizeof(line), "frame %zu/%zu (%s): %ld steps, %d adaptations, %.1f steps/s", i,
                      frames.size() - 1, motion.keys[static_cast<size_t>(frame.transition) + 1].pose.c_str(),
                      result.steps, result.adaptations, result.steps / std::max(seconds_since(start), 1e-9));
        report(progress, line, frame.transition + 1, i, 0, false, largest_stretches().maxCoeff());
      }
      if (frame.key < 0) {
        ++since_key;
        const bool adapt_here = options.adaptation.enabled && std::binary_search(adapt_frames.begin(), adapt_frames.end(),
                                                                    static_cast<int>(i));
        if (adapt_here || (options.schedule.frame_stride > 0 && since_key % options.schedule.frame_stride == 0)) {
          hold_frame(frame, i, progress, adapt_here);
        }
        continue;
      }
      since_key = 0;

      body->stand_still(V_body);
      KeyPoseResult key;
      key.key = frame.key;
      key.pose = motion.keys[static_cast<size_t>(frame.key)].pose;
      settle_pose(key, i, progress, options.adaptation.enabled);
      result.all_settled = result.all_settled && key.settled;
      record(key);
      if (progress) {
        char line[256];
        std::snprintf(line, sizeof(line),
                      "key %d/%zu %s: %ld steps, settled %s after %d, max stretch %.3f, p99 %.3f, "
                      "above %.2f%%, deepest %.2f mm, %ld crossings, rest area x%.4f (change %.3f%% over the "
                      "last %d steps)",
                      frame.key + 1, motion.keys.size(), key.pose.c_str(), result.steps,
                      key.settled ? "yes" : "no", key.settle_steps, key.max_stretch, key.p99_stretch,
                      100.0 * key.area_fraction_above, 1e3 * key.deepest_penetration, key.crossings.crossings(),
                      key.rest_area_growth,
                      100.0 * key.rest_area_change, std::min(key.settle_steps, options.settle.fixed_point_steps));
        report(progress, line, frame.key, i, key.settle_steps, true, key.max_stretch);
      }
      const bool held = key.held;
      result.keys.push_back(std::move(key));
      if (held) {
        // A held pose fails fast: the poses after it would start from cloth
        // the body holds.
        result.held_key = static_cast<int>(result.keys.size()) - 1;
        result.all_settled = false;
        break;
      }
    }

    result.V_rest = V_rest;
    const cloth::PhaseTimes& pt = sim->times();
    result.times.forces_assembly = pt.forces_assembly + pt.checks;
    result.times.factorization = pt.factorization;
    result.times.solve = pt.solve;
    result.times.collisions = pt.collisions + body->collider_stats().rebuild_seconds;
    result.solver = sim->counters();
    if (static_solver) {
      // The static solves' work beside the steps'.
      const cloth::PhaseTimes& st = static_solver->times();
      result.times.forces_assembly += st.forces_assembly + st.checks;
      result.times.factorization += st.factorization;
      result.times.solve += st.solve;
      result.times.collisions += st.collisions;
      result.static_seconds = st.total();
      result.solver.factorizations += static_solver->counters().factorizations;
      result.solver.cg_iterations += static_solver->counters().cg_iterations;
    }
    result.collisions = body->collider_stats();
    result.contact = body->continuous_stats();
    result.times.total = seconds_since(start);
    return std::move(result);
  }
};

GarmentMotion::GarmentMotion(PoseInterpolator& interpolator, const MotionSpec& motion,
                             const Eigen::MatrixXd& V_garment, const Eigen::MatrixXi& F_garment,
                             const GarmentFile& garment, const MotionRunOptions& options)
    : impl_(std::make_unique<Impl>(interpolator, motion, V_garment, F_garment, garment, options)) {}

GarmentMotion::~GarmentMotion() = default;

MotionRunResult GarmentMotion::run(const ProgressCallback& progress) { return impl_->run(progress); }

MotionRunResult run_garment_motion(PoseInterpolator& interpolator, const MotionSpec& motion,
                                   const Eigen::MatrixXd& V_garment, const Eigen::MatrixXi& F_garment,
                                   const GarmentFile& garment, const MotionRunOptions& options,
                                   const ProgressCallback& progress) {
  return GarmentMotion(interpolator, motion, V_garment, F_garment, garment, options).run(progress);
}

}  // namespace gp::adapt
