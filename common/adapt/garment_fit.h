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

namespace gp::adapt {

struct FitOptions {
  MotionRunOptions motion;  // the runs' options (with adapt false: one run, verified)
  FitCriteria criteria;     // the verification's bounds
  bool verify = true;       // false: one adaptation cycle, no verification
  int max_cycles = 3;       // adaptation cycles at most
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
