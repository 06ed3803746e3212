#pragma once
// A garment fitted to a motion: the rest shape adapted through the motion in
// cycles until the verification pass (fit_verification.h) holds at every key
// pose, or a cycle cap.
//
// One pass of adaptation is not enough: a rest shape grown for a later pose
// changes how the cloth falls into an earlier one (more cloth pinched in an
// A-pose armpit after growth for arms up), so the final rest shape can fail a
// pose it fitted when it was adapted there. Each further cycle starts again
// from the garment as designed, with the rest shape so far, and adapts where
// the fresh run still stretches. The result also depends less on the order of
// the poses and on the time step, since every pose is met by the same final
// rest shape.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapt/fit_verification.h"
#include "adapt/garment_motion.h"
#include "spec/option_fields.h"

namespace gp::adapt {

struct FitOptions {
  MotionRunOptions motion;  // the runs' options (with adapt false: one run, verified)
  FitCriteria criteria;     // the verification's bounds
  bool verify = true;       // false: one adaptation cycle, no verification
  int max_cycles = 3;       // adaptation cycles at most
  // The verification also solves every frame_stride-th in-between frame of each transition to its
  // static equilibrium and judges it by the key poses' bounds (MotionRunOptions::schedule.frame_stride): a
  // garment must allow the movement, not only its key poses. A further cycle adapts at the frames
  // that failed (MotionRunOptions::adaptation.frames). 0: the key poses only.
  int frame_stride = 0;
  // The stage's own admission rule, recorded with the fit: the pose set's
  // design pose may be another body than the garment was designed on (the
  // garment is carried to it before the fit); refused otherwise.
  bool other_body = false;
};

// The fit's options as its report records them and the sewn-fit check reads
// them back (spec/option_fields.h): one flat list, keys with their units.
// motion.schedule.threads is left out, since it changes no result.
struct FitOptionFields {
  template <class Fields>
  void operator()(FitOptions& o, Fields& f) const {
    MotionRunOptions& m = o.motion;
    AdaptOptions& a = m.adaptation.adapter;
    cloth::SimulatorOptions& s = m.solver;
    f.flag("adapt", m.adaptation.enabled);
    f.flag("other_body", o.other_body);
    f.number("dt_s", s.dt, Range::positive());
    f.integer("substeps", m.schedule.substeps, Range::between(1, 1000));
    f.integer("adapt_every", m.adaptation.every, Range::between(1, 100000));
    f.integer("adaptation_lag", m.schedule.adaptation_lag, Range::between(0, 99999));
    f.number("delta", a.delta, Range::between(0.0, 10.0));
    f.number("margin", a.margin, Range::between(0.0, 1.0));
    f.number("hysteresis", a.hysteresis, Range::between(0.0, 1.0));
    f.number("smoothing_length_m", a.smoothing_length, Range::non_negative());
    f.integer("adapt_rounds", a.rounds, Range::between(1, 100));
    f.flag("adapt_during_transitions", m.adaptation.during_transitions);
    f.number("adapt_speed_m_per_s", m.adaptation.speed, Range::positive());
    f.number("max_area_growth", m.adaptation.max_area_growth, Range::between(1.0, 1000.0));
    f.number("max_face_growth", a.max_face_growth, Range::between(1.0, 1000.0));
    f.flag("verify", o.verify);
    f.integer("max_cycles", o.max_cycles, Range::between(1, 100));
    f.integer("verify_frame_stride", o.frame_stride, Range::between(0, 1e6));
    f.number("arap_tolerance", a.arap.tolerance, Range::positive());
    f.number("arap_stretch_tolerance", a.arap.stretch_tolerance, Range::non_negative());
    f.integer("arap_max_iterations", a.arap.max_iterations, Range::between(1, 1e9));
    f.choice("equilibrium", m.settle.equilibrium, equilibrium_names());
    f.number("static_tolerance", m.settle.statics.tolerance, Range::positive());
    f.integer("static_max_iterations", m.settle.statics.max_iterations, Range::between(1, 1e7));
    f.number("static_adapt_displacement_m", m.settle.statics.adapt_displacement, Range::positive());
    f.integer("static_held_iterations", m.settle.statics.held_iterations, Range::between(1, 1e7));
    f.number("barrier_pressure_pa", m.settle.statics.barrier_pressure, Range::positive());
    f.number("barrier_band_m", m.settle.statics.barrier_band, Range::positive());
    f.number("static_max_displacement_m", m.settle.statics.max_displacement, Range::positive());
    // Recorded only where it is not the barrier, so that reports from before the choice read alike.
    f.optional_choice("static_contact", m.settle.statics.contact, cloth::static_contact_names(),
                      cloth::StaticContact::barrier);
    if (m.settle.statics.contact == cloth::StaticContact::active_set) {
      f.number("static_release_force", m.settle.statics.release_force, Range::non_negative());
    }
    f.number("settle_speed_m_per_s", m.settle.speed, Range::positive());
    f.number("settle_stretch_change", m.settle.stretch_change, Range::non_negative());
    f.integer("settle_max_steps", m.settle.max_steps, Range::between(0, 1e7));
    f.number("settle_damping", m.settle.damping, Range::between(0.0, 1.0));
    f.integer("held_steps", m.settle.held_steps, Range::between(0, 1e7));
    f.number("held_stretch", m.settle.held_stretch, Range::between(1.0, 100.0));
    f.number("held_improvement", m.settle.held_improvement, Range::between(0.0, 1.0));
    f.integer("fixed_point_steps", m.settle.fixed_point_steps, Range::between(1, 1e9));
    f.number("fixed_point_area_change", m.settle.fixed_point_area_change, Range::non_negative());
    f.number("reach_m", m.contact.reach, Range::non_negative());
    f.names("contact", m.contact.velocity_constraints, "velocity", "projection");
    f.number("contact_band_m", m.contact.band, Range::non_negative());
    f.names("pinch_gaps", m.contact.facing_gaps, "facing", "ray");
    f.names("continuous_contact", m.contact.continuous, "on", "off");
    f.number("contact_thickness_m", m.contact.sweep.thickness, Range::positive());
    f.number("pin_clearance", m.contact.pin_clearance, Range::between(0.0, 1.0));
    f.names("hand_hulls", m.contact.surface.hulls, "on", "off");
    f.number("hull_thin_m", m.contact.surface.thin, Range::positive());
    f.number("hull_min_extent_m", m.contact.surface.min_extent, Range::non_negative());
    f.number("initial_push_speed_m_per_s", m.contact.initial_push_speed, Range::positive());
    f.number("contact_release_fraction", s.contact_release_fraction, Range::non_negative());
    f.choice("solver", s.strategy, cloth::solver_strategy_names());
    f.number("cg_tolerance", s.cg_tolerance, Range::positive());
    f.integer("cg_max_iterations", s.cg_max_iterations, Range::between(1, 1e9));
    f.integer("fresh_factor_max_iterations", s.fresh_factor_max_iterations, Range::between(1, 1e9));
    f.number("factorization_cost", s.factorization_cost, Range::non_negative());
    f.flag("warp_preconditioner", s.warp_preconditioner);
  }
};

struct FitCycle {
  long steps = 0;                 // simulation steps of the adaptation cycle
  int adaptations = 0;            // of which changed the rest shape
  double rest_area_growth = 1.0;  // rest area / design area after the cycle
  bool verified = false;          // the verification after this cycle held
};

struct FitResult {
  MotionRunResult run;                        // the last adaptation cycle; run.V_rest is the fit
  std::vector<FitCycle> cycles;               // one per adaptation cycle
  std::optional<FitVerification> verification;  // of run.V_rest, when verified
  std::string cycle_error;  // a further cycle's numerical failure, after which the previous cycle's fit stands
};

// V_garment, F: the garment as designed (#V by 3, #F by 3). `progress`
// receives every run's progress, verification runs included. Throws as
// run_garment_motion.
FitResult fit_garment(PoseInterpolator& interpolator, const MotionSpec& motion, const Eigen::MatrixXd& V_garment,
                      const Eigen::MatrixXi& F, const GarmentFile& garment, const FitOptions& options,
                      const ProgressCallback& progress = {});

}  // namespace gp::adapt
