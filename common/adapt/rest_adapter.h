#pragma once
// Rest-shape adaptation (Wolff et al. 2023, sec. 5, appendices A-B): the
// stretch of every simulated triangle clipped into per-triangle rest targets
// (stretch_clip.h) and stitched into one rest mesh (arap_stitch.h). With no
// triangle beyond the limit and no paint, the targets are the current rest
// triangles and the rest shape comes back unchanged: a settled garment is a
// fixed point.
#include <vector>

#include <Eigen/Core>

#include "adapt/arap_stitch.h"
#include "adapt/stretch_clip.h"
#include "garment/garment_file.h"

namespace gp::adapt {

struct AdaptOptions {
  double delta = 0.1;  // stretch limit 1 + delta of the fit (paper value)
  // A face beyond 1 + delta - margin has its stretches above 1 + delta -
  // margin - hysteresis clipped to that (both 0: the paper's rule). The
  // margin is room for a fresh drape; the hysteresis stops a face held
  // stretched from adapting at every hair (README.md).
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
  // A fabric's own stretch limits along warp and weft (stretch ratios; both
  // 0: 1 + delta in every direction, the paper's rule). With them, each
  // direction is clipped at its own limit less the margin (GrainClip,
  // stretch_clip.h); the warp is material_direction turned by grain_angles,
  // as the cloth model lays it.
  double limit_warp = 0.0;
  double limit_weft = 0.0;
  Eigen::Vector3d material_direction = Eigen::Vector3d::UnitY();
  std::vector<double> grain_angles;  // per face, radians; empty: none
  // A face's target area stays within this multiple of its design area:
  // where the body holds the cloth, growth relieves nothing and would balloon
  // (README.md); the verification still sees that stretch.
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

// `options` with the garment fabric's limits (Material::stretch_limit_*), or
// as they are for a material without limits of its own (the paper's), and
// its grain per face where a face is turned (Material::grain_angles).
AdaptOptions with_fabric_limits(AdaptOptions options, const Material& material);

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
