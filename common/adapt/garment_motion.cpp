#include "adapt/garment_motion.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <numeric>
#include <set>
#include <string>

#include "collision/body_collider.h"
#include "core/error.h"
#include "mesh/measures.h"

namespace gp::adapt {
namespace {

using Clock = std::chrono::steady_clock;

// A vertex within this distance [m] above the comfort offset touches it (the
// position projection leaves vertices at the offset up to rounding).
constexpr double kTouchTolerance = 1e-6;
// Largest speed [m/s] at which a contact constraint pushes a vertex back out to
// the offset.
constexpr double kMaxCorrectionSpeed = 0.5;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

cloth::ClothParameters parameters_from(const Material& m) {
  cloth::ClothParameters p;
  p.k_stretch = m.k_stretch;
  p.k_shear = m.k_shear;
  p.k_bend = m.k_bend;
  p.damping_stretch = m.damping_stretch;
  p.damping_shear = m.damping_shear;
  p.damping_bend = m.damping_bend;
  p.density = m.density;
  return p;
}

// Area-weighted statistics of the per-face stretch.
void stretch_figures(const Eigen::VectorXd& s, const Eigen::VectorXd& area, double limit, KeyPoseResult& k) {
  const double total = area.sum();
  std::vector<int> order(s.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&s](int a, int b) { return s(a) < s(b); });
  double accumulated = 0.0;
  k.p99_stretch = s.size() ? s(order.back()) : 0.0;
  for (int f : order) {
    accumulated += area(f);
    if (accumulated >= 0.99 * total) {
      k.p99_stretch = s(f);
      break;
    }
  }
  k.max_stretch = s.size() ? s.maxCoeff() : 0.0;
  k.mean_stretch = total > 0.0 ? s.dot(area) / total : 0.0;
  double above = 0.0;
  for (Eigen::Index f = 0; f < s.size(); ++f) {
    if (s(f) > limit) above += area(f);
  }
  k.area_fraction_above = total > 0.0 ? above / total : 0.0;
}

}  // namespace

int applied_adaptation_lag(const MotionRunOptions& options) {
  return std::max(0, std::min(options.adaptation_lag, options.adapt_every - 1));
}

MotionRunResult run_garment_motion(PoseInterpolator& interpolator, const MotionSpec& motion,
                                   const Eigen::MatrixXd& V_garment, const Eigen::MatrixXi& F_garment,
                                   const GarmentFile& garment, const MotionRunOptions& options,
                                   const ProgressCallback& progress) {
  const auto run_start = Clock::now();
  if (options.substeps < 1 || options.adapt_every < 1 || options.settle_max_steps < 0 || options.threads < 1) {
    throw UsageError("substeps, adapt_every and threads must be at least 1, settle_max_steps non-negative");
  }
  if (options.adaptation_lag < 0) {
    throw UsageError("the adaptation lag must be non-negative, got " + std::to_string(options.adaptation_lag));
  }
  if (!(options.settle_damping >= 0.0) || !std::isfinite(options.settle_damping)) {
    throw UsageError("settle_damping must be finite and non-negative");
  }
  const std::vector<MotionFrame> frames = motion_frames(motion);
  if (frames.empty()) throw SpecError("the motion has no frames");
  const Eigen::MatrixXi& F_body = interpolator.faces();
  MotionRunResult result;
  const double offset = garment.offset;

  // Pins: bound vertices of pinned loops.
  std::vector<int> pin_ids;
  std::vector<SurfacePoint> pin_binding;
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
  auto pin_targets = [&](const Eigen::MatrixXd& V_body) {
    const Eigen::MatrixXd N = vertex_normals(V_body, F_body);
    Eigen::MatrixXd T(pin_ids.size(), 3);
    for (size_t k = 0; k < pin_ids.size(); ++k) {
      T.row(k) = evaluate_binding(V_body, N, F_body, pin_binding[k], offset).transpose();
    }
    return T;
  };

  auto t0 = Clock::now();
  Eigen::MatrixXd V_body = interpolator.frame(frames[0].from, frames[0].to, frames[0].t);
  Eigen::MatrixXd targets = pin_targets(V_body);
  result.times.body += seconds_since(t0);

  collision::BodyCollider collider(F_body,
                                   collision::reachable_body_faces(V_body, F_body, V_garment, options.reach));
  result.culled_body_faces = collider.face_ids().size();
  collider.set_threads(options.threads);
  collider.set_body(V_body);
  collision::ContinuousContact contact(F_garment, F_body, collider.face_ids(), options.contact);
  contact.set_pinned(pin_ids);
  contact.set_threads(options.threads);
  contact.set_body(V_body);
  result.initial_crossings = collision::find_crossings(V_body, F_body, V_garment, F_garment);
  result.continuous_contact = options.continuous_contact && result.initial_crossings.intersection_free();

  cloth::SimulatorOptions sim_options = options.solver;
  sim_options.dt = options.dt;
  cloth::ClothSimulator sim(V_garment, F_garment, parameters_from(garment.material), sim_options);
  sim.set_pinned(pin_ids);
  if (!options.rest_triangles.empty()) {
    if (options.adapt) throw UsageError("per-face rest triangles need adapt off (the rest shape is then fixed)");
    sim.set_rest_triangles(options.rest_triangles);
  }
  // A garment offset along the body normals can start closer than the offset to
  // another body part (concave regions: armpits, between arm and torso); pushing
  // it out in one step is a jump of centimetres that tears the cloth. Each
  // vertex's offset therefore starts at its initial distance and grows to the
  // comfort offset at options.initial_push_speed.
  Eigen::VectorXd offsets = Eigen::VectorXd::Constant(V_garment.rows(), offset);
  {
    int hint = -1;
    for (int v = 0; v < V_garment.rows(); ++v) {
      const collision::Proximity q = collider.query(V_garment.row(v).transpose(), hint);
      hint = q.face;
      offsets(v) = std::min(offset, q.signed_distance);
    }
  }
  result.initial_min_distance = offsets.minCoeff();
  bool ramp_done = offsets.minCoeff() >= offset;
  auto advance_offsets = [&]() {
    if (ramp_done) return;
    const double grow = options.initial_push_speed * options.dt;
    for (int v = 0; v < offsets.size(); ++v) offsets(v) = std::min(offset, offsets(v) + grow);
    ramp_done = offsets.minCoeff() >= offset;
  };
  sim.set_collision_handler(
      [&collider, &offsets](Eigen::MatrixXd& X, Eigen::MatrixXd& Vel) { collider.resolve(X, Vel, offsets); });
  if (result.continuous_contact) {
    sim.set_step_end_handler([&contact](const Eigen::MatrixXd& X_start, Eigen::MatrixXd& X_end, double s_start,
                                        double s_end) { contact.enforce(X_start, X_end, s_start, s_end); });
  }
  if (options.velocity_contacts) {
    // Contact as a velocity constraint in the solve: the normal velocity follows
    // the body and closes any gap below the offset within the step; never pulls
    // a vertex in the band towards the body.
    const double band = options.contact_band;
    sim.set_contact_handler([&collider, &offsets, band](const Eigen::MatrixXd& X, double h,
                                                        std::vector<cloth::VelocityConstraint>& out) {
      for (const collision::Contact& c : collider.contacts(X, offsets, band)) {
        const double vertex_offset = c.offset;
        cloth::VelocityConstraint k;
        k.vertex = c.vertex;
        k.normal = c.outward;
        // The gap below the offset closes within the step, but no faster than
        // kMaxCorrectionSpeed (halved substeps would otherwise turn a depth into
        // a huge speed); the position projection after the step does the rest.
        k.normal_velocity =
            c.body_normal_speed + std::min(std::max(vertex_offset - c.signed_distance, 0.0) / h, kMaxCorrectionSpeed);
        k.touching = c.signed_distance <= vertex_offset + kTouchTolerance;
        out.push_back(k);
      }
    });
  }

  const RestShapeAdapter adapter(V_garment, F_garment, options.adaptation);
  Eigen::MatrixXd V_rest = V_garment;
  const double design_area = mesh_area(V_garment, F_garment);

  auto record_adaptation = [&](const AdaptReport& r) {
    if (!r.changed) return;
    sim.set_rest_shape(V_rest);
    ++result.adaptations;
    result.arap_iterations += r.arap.iterations;
    result.arap_max_iterations = std::max(result.arap_max_iterations, r.arap.iterations);
    result.arap_max_residual = std::max(result.arap_max_residual, r.arap.residual);
    result.arap_converged = result.arap_converged && r.arap.converged;
  };
  // Lagging adaptations (MotionRunOptions::adaptation_lag): the one computed
  // from the positions after step k runs beside the next steps, on the worker
  // with threads > 1 or when it is applied otherwise, and is applied after
  // step k + lag, or before any adaptation at the end of a key pose.
  struct Adaptation {
    Eigen::MatrixXd V_rest;
    AdaptReport report;
    double seconds = 0.0;
  };
  const std::launch policy = options.threads > 1 ? std::launch::async : std::launch::deferred;
  // The result of work launched with `policy`; the time the stepping thread
  // waited for the worker is counted (run in turn, it is the work's own time).
  auto await = [&](auto& future) {
    const auto t_wait = Clock::now();
    auto value = future.get();
    if (policy == std::launch::async) result.times.waiting += seconds_since(t_wait);
    return value;
  };
  const int lag = applied_adaptation_lag(options);
  std::future<Adaptation> pending_adaptation;
  long apply_after_step = 0;
  auto apply_adaptation = [&]() {
    if (!pending_adaptation.valid()) return;
    Adaptation a = await(pending_adaptation);
    result.times.adaptation += a.seconds;
    V_rest = std::move(a.V_rest);
    record_adaptation(a.report);
  };
  auto adapt_now = [&]() {
    apply_adaptation();
    const auto ta = Clock::now();
    record_adaptation(adapter.adapt(sim.positions(), V_rest));
    result.times.adaptation += seconds_since(ta);
  };

  // Paint (T3) is part of the design: applied once, with or without adaptation.
  bool painted = false;
  for (double p : garment.paint) painted = painted || p != 1.0;
  if (painted) {
    if (garment.paint.size() != static_cast<size_t>(F_garment.rows())) {
      throw GeometryError("paint has " + std::to_string(garment.paint.size()) + " factors for " +
                          std::to_string(F_garment.rows()) + " faces");
    }
    const Eigen::VectorXd factors = Eigen::Map<const Eigen::VectorXd>(garment.paint.data(), garment.paint.size());
    const auto ta = Clock::now();
    record_adaptation(adapter.adapt(V_rest, V_rest, &factors));
    result.times.adaptation += seconds_since(ta);
  }

  auto launch_adaptation = [&]() {
    pending_adaptation = std::async(
        policy,
        [&adapter](Eigen::MatrixXd X, Eigen::MatrixXd V) {
          const auto ta = Clock::now();
          Adaptation a;
          a.report = adapter.adapt(X, V);
          a.V_rest = std::move(V);
          a.seconds = seconds_since(ta);
          return a;
        },
        sim.positions(), V_rest);
    apply_after_step = result.steps + lag;
  };
  auto step = [&](const Eigen::MatrixXd& T) {
    sim.set_pin_targets(T);
    advance_offsets();
    sim.step();
    ++result.steps;
    if (result.steps >= apply_after_step) apply_adaptation();
    if (options.adapt && result.steps % options.adapt_every == 0) {
      launch_adaptation();
      if (lag == 0) apply_adaptation();
    }
  };

  // The body stages after frame 0 in order: each frame's `substeps`
  // interpolated bodies, so that a step never sees more than its share of the
  // body's motion within the frame.
  struct BodyRequest {
    int from, to;
    double t;
  };
  std::vector<BodyRequest> requests;
  for (size_t i = 1; i < frames.size(); ++i) {
    const MotionFrame& frame = frames[i];
    const MotionFrame& previous = frames[i - 1];
    const double t_start = previous.transition == frame.transition ? previous.t : 0.0;
    for (int s = 1; s <= options.substeps; ++s) {
      const double w = static_cast<double>(s) / options.substeps;
      requests.push_back({frame.from, frame.to, (1.0 - w) * t_start + w * frame.t});
    }
  }
  // A body stage made ready for the step: positions, pin targets and the
  // collision tree with the body's velocity since the previous stage. It
  // depends on the body alone, so with threads > 1 the next stage is prepared
  // on the worker while the cloth steps through the current one.
  struct BodyStage {
    Eigen::MatrixXd V, targets;
    collision::BodyFrame frame;
    double seconds = 0.0;  // interpolation and pin targets (the tree's time is the collider's)
  };
  const double step_time = options.dt;
  auto prepare_stage = [&interpolator, &pin_targets, &collider, step_time](BodyRequest r, Eigen::MatrixXd V_previous) {
    const auto t_stage = Clock::now();
    BodyStage stage;
    stage.V = interpolator.frame(r.from, r.to, r.t);
    stage.targets = pin_targets(stage.V);
    const Eigen::MatrixXd body_velocity = (stage.V - V_previous) / step_time;
    stage.seconds = seconds_since(t_stage);
    stage.frame = collider.prepare(stage.V, &body_velocity);
    return stage;
  };
  size_t next_request = 0;
  std::future<BodyStage> next_stage;
  auto request_next_stage = [&]() {
    if (next_request < requests.size()) next_stage = std::async(policy, prepare_stage, requests[next_request++], V_body);
  };

  result.times.setup = seconds_since(run_start);
  const double limit = 1.0 + options.adaptation.delta;
  request_next_stage();
  for (size_t i = 0; i < frames.size(); ++i) {
    const MotionFrame& frame = frames[i];
    if (i > 0) {
      for (int s = 1; s <= options.substeps; ++s) {
        BodyStage stage = await(next_stage);
        result.times.body += stage.seconds;
        collider.set_body(std::move(stage.frame));
        contact.set_body(stage.V);
        V_body = std::move(stage.V);
        targets = std::move(stage.targets);
        request_next_stage();
        step(targets);
      }
    }
    if (progress && i > 0 && i % 5 == 0 && frame.key < 0) {
      char line[200];
      std::snprintf(line, sizeof(line), "frame %zu/%zu (%s): %ld steps, %d adaptations, %.1f steps/s", i,
                    frames.size() - 1, motion.keys[static_cast<size_t>(frame.transition) + 1].pose.c_str(),
                    result.steps, result.adaptations, result.steps / std::max(seconds_since(run_start), 1e-9));
      progress({line, frame.transition + 1, static_cast<int>(motion.keys.size()), i, frames.size(), result.steps, 0,
                false, principal_stretches(V_rest, sim.positions(), F_garment).col(0).maxCoeff()});
    }
    if (frame.key < 0) continue;

    // Key pose: the body stops; settle.
    collider.set_body(V_body);
    contact.set_body(V_body);
    KeyPoseResult key;
    key.key = frame.key;
    key.pose = motion.keys[static_cast<size_t>(frame.key)].pose;
    double previous_stretch = principal_stretches(V_rest, sim.positions(), F_garment).col(0).maxCoeff();
    const int check_every = options.adapt_every;
    // Rest area at every check, for the fixed-point test: with adaptation the
    // key pose is settled only once the rest area has changed by less than
    // fixed_point_area_change over the last fixed_point_steps steps.
    std::vector<std::pair<int, double>> area_history{{0, mesh_area(V_rest, F_garment)}};
    auto area_change_over_window = [&]() {
      const double now = area_history.back().second;
      double change = 0.0;
      for (auto it = area_history.rbegin(); it != area_history.rend(); ++it) {
        change = std::max(change, std::abs(now - it->second) / now);
        if (key.settle_steps - it->first >= options.fixed_point_steps) break;
      }
      return change;
    };
    sim.set_damping_scale(options.settle_damping);
    while (key.settle_steps < options.settle_max_steps) {
      const Eigen::MatrixXd X_check = sim.positions();
      int window = 0;
      for (; window < check_every && key.settle_steps < options.settle_max_steps; ++window, ++key.settle_steps) {
        step(targets);
      }
      key.max_net_speed = (sim.positions() - X_check).rowwise().norm().maxCoeff() / (window * step_time);
      const double stretch = principal_stretches(V_rest, sim.positions(), F_garment).col(0).maxCoeff();
      const bool slow = key.max_net_speed < options.settle_speed;
      const bool steady = std::abs(stretch - previous_stretch) < options.settle_stretch_change;
      const double previous_stretch_at_check = previous_stretch;
      previous_stretch = stretch;
      area_history.emplace_back(key.settle_steps, mesh_area(V_rest, F_garment));
      key.rest_area_change = area_change_over_window();
      const bool fixed = !options.adapt || (key.settle_steps >= options.fixed_point_steps &&
                                            key.rest_area_change < options.fixed_point_area_change);
      if (progress && key.settle_steps % 40 == 0) {
        char line[256];
        std::snprintf(line, sizeof(line),
                      "settling %s: %d steps, max speed %.4f m/s (net %.4f), max stretch %.4f (change %.4f), "
                      "rest area change %.3f%% over the last %d steps",
                      motion.keys[static_cast<size_t>(frame.key)].pose.c_str(), key.settle_steps, sim.max_speed(),
                      key.max_net_speed, stretch, std::abs(stretch - previous_stretch_at_check),
                      100.0 * key.rest_area_change,
                      std::min(key.settle_steps, options.fixed_point_steps));
        progress({line, frame.key, static_cast<int>(motion.keys.size()), i, frames.size(), result.steps,
                  key.settle_steps, false, stretch});
      }
      if (slow && steady && fixed && ramp_done) {
        key.settled = true;
        break;
      }
    }
    sim.set_damping_scale(1.0);
    if (options.settle_max_steps == 0) key.settled = sim.max_speed() < options.settle_speed;
    key.max_speed = sim.max_speed();
    if (options.adapt) adapt_now();  // and at the end of each pose
    result.all_settled = result.all_settled && key.settled;

    key.V_draped = sim.positions();
    key.face_max_stretch = principal_stretches(V_rest, key.V_draped, F_garment).col(0);
    stretch_figures(key.face_max_stretch, face_areas(V_rest, F_garment), limit, key);
    int hint = -1;
    for (int v = 0; v < key.V_draped.rows(); ++v) {
      const collision::Proximity q = collider.query(key.V_draped.row(v).transpose(), hint);
      hint = q.face;
      key.deepest_penetration = std::max(key.deepest_penetration, -q.signed_distance);
    }
    key.crossings = collision::find_crossings(V_body, F_body, key.V_draped, F_garment);
    key.rest_area_growth = mesh_area(V_rest, F_garment) / design_area;
    key.steps = result.steps;
    if (progress) {
      char line[256];
      std::snprintf(line, sizeof(line),
                    "key %d/%zu %s: %ld steps, settled %s after %d, max stretch %.3f, p99 %.3f, "
                    "above %.2f%%, deepest %.2f mm, %ld crossings, rest area x%.4f (change %.3f%% over the last %d "
                    "steps)",
                    frame.key + 1, motion.keys.size(), key.pose.c_str(), result.steps,
                    key.settled ? "yes" : "no", key.settle_steps, key.max_stretch, key.p99_stretch,
                    100.0 * key.area_fraction_above, 1e3 * key.deepest_penetration, key.crossings.crossings(),
                    key.rest_area_growth,
                    100.0 * key.rest_area_change, std::min(key.settle_steps, options.fixed_point_steps));
      progress({line, frame.key, static_cast<int>(motion.keys.size()), i, frames.size(), result.steps,
                key.settle_steps, true, key.max_stretch});
    }
    result.keys.push_back(std::move(key));
  }

  result.V_rest = V_rest;
  const cloth::PhaseTimes& pt = sim.times();
  result.times.forces_assembly = pt.forces_assembly + pt.checks;
  result.times.factorization = pt.factorization;
  result.times.solve = pt.solve;
  result.times.collisions = pt.collisions + collider.stats().rebuild_seconds;
  result.factorizations = sim.counters().factorizations;
  result.cg_iterations = sim.counters().cg_iterations;
  result.rejected_steps = sim.counters().rejected;
  result.accepted_folds = sim.counters().accepted_flips;
  result.contact_constraints = sim.counters().constraints;
  result.contact_releases = sim.counters().released;
  result.pinched_contacts = collider.stats().pinched;
  result.crease_contacts = collider.stats().creases;
  result.body_queries = collider.stats().queries;
  result.body_queries_skipped = collider.stats().skipped;
  result.body_queries_reused = collider.stats().reused;
  result.body_queries_local = collider.stats().local;
  result.contact = contact.stats();
  result.times.total = seconds_since(run_start);
  return result;
}

}  // namespace gp::adapt
