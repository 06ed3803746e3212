#pragma once
// Rest-shape adaptation (Wolff et al. 2023, sec. 5 and appendices A-B): clip the
// stretch of every simulated triangle at 1 + delta into per-triangle rest targets
// (stretch_clip.h) and stitch them into one rest mesh by ARAP (arap_stitch.h),
// whose global matrix is factored once per connectivity and reused by every call.
//
// When no triangle is stretched beyond 1 + delta and no paint is applied, the
// targets are exactly the current rest triangles, which the current rest mesh
// already stitches with zero misfit: the rest shape is returned unchanged (zero
// iterations). This is what makes a settled garment a fixed point.
#include <Eigen/Core>

#include "adapt/arap_stitch.h"
#include "adapt/stretch_clip.h"

namespace gp::adapt {

struct AdaptOptions {
  double delta = 0.1;  // stretch limit 1 + delta of the fit (paper value)
  // The adaptation's own limit is 1 + delta - margin: a face stretched beyond
  // it has its principal stretches above 1 + delta - margin - hysteresis
  // clipped to that value (margin and hysteresis 0: the paper's rule). The
  // margin is room for the drape of a fresh simulation of the rest shape,
  // which differs from the adapting run's; the hysteresis keeps a face that
  // the body holds stretched from being adapted again by every hair it
  // creeps back over the limit (see README.md).
  double margin = 0.02;
  double hysteresis = 0.01;
  // m: the stitching resists changes of the rest shape's form shorter than
  // this (a bilaplacian term, see arap_stitch.h), so that growth makes smooth
  // bulges instead of tucks; 0: plain ARAP (the paper).
  double smoothing_length = 0.01;
  // Clip-and-stitch rounds per adaptation against the same simulated
  // positions, until no triangle is clipped: the smoothing lets one stitching
  // meet its targets only in part.
  int rounds = 4;
  // A face's target area is kept within this multiple of its design area.
  // Where the body holds the cloth (a skirt caught on a hand), no growth
  // relieves the stretch, and without a bound those faces grow every
  // adaptation into a balloon (the shared-body dress: x1.92 at its own design
  // pose). The verification still sees the stretch that remains there.
  double max_face_growth = 4.0;
  ArapOptions arap;    // stitching tolerance and iteration cap
};

struct AdaptReport {
  ClipStats clip;            // before the adaptation
  ArapReport arap;           // stitching (iterations 0 when nothing changed)
  double area_before = 0.0;  // rest area [m^2]
  double area_after = 0.0;
  bool changed = false;      // false when the rest shape was left as it was
  int rounds = 0;            // clip-and-stitch rounds done
  int capped_faces = 0;      // faces whose target was held at max_face_growth (last round)
};

class RestShapeAdapter {
 public:
  // V_reference: the design rest shape (#V by 3, metres) whose triangles fix the
  // ARAP weights and the smoothing; F: #F by 3. Factors the ARAP matrix once.
  RestShapeAdapter(const Eigen::MatrixXd& V_reference, const Eigen::MatrixXi& F, AdaptOptions options = {});

  // Adapts V_rest (in/out) to the simulated positions V_sim (#V by 3), in up
  // to options().rounds clip-and-stitch rounds.
  // area_factors (#F, optional) scale the target areas (paint); pass them once,
  // e.g. at the first adaptation, since the rest shape keeps them afterwards.
  AdaptReport adapt(const Eigen::MatrixXd& V_sim, Eigen::MatrixXd& V_rest,
                    const Eigen::VectorXd* area_factors = nullptr) const;

  const AdaptOptions& options() const { return options_; }
  const ArapStitcher& stitcher() const { return stitcher_; }

 private:
  Eigen::MatrixXi F_;
  AdaptOptions options_;
  ArapStitcher stitcher_;
  Eigen::VectorXd reference_areas_;  // design face areas [m^2]
};

}  // namespace gp::adapt
