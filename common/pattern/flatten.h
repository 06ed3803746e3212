#pragma once
// Flattening of one disk-shaped piece into the plane with low distortion and
// no flipped triangles: least-squares conformal map (LSCM, Levy et al. 2002)
// as initial guess (Tutte's embedding onto a circle when LSCM flips a
// triangle), then as-rigid-as-possible parameterization (Liu et al. 2008,
// local/global iterations) whose global steps are cut short before any
// triangle would flip (the injectivity-preserving line search of Smith and
// Schaefer 2015, "Bijective parameterization with free boundaries").
//
// Distortion of a triangle: the singular values s1 >= s2 of the 2x2 Jacobian
// J of the affine map from the triangle (in an orthonormal frame of its own
// plane) to its flat image. s1 - 1 is its stretch, 1 - s2 its compression;
// its error is max(|s1 - 1|, |s2 - 1|).
#include <string>
#include <vector>
#include <Eigen/Core>

namespace gp {

struct FlattenOptions {
  int max_iterations = 500;          // ARAP local/global iterations
  double tolerance = 1e-6;           // stop when the relative energy decrease is below this
  double line_search_margin = 0.9;   // fraction of the largest flip-free step taken
  // Weight of keeping boundary edges at their 3D length, relative to the ARAP
  // energy of the triangle beside them (dimensionless). Seams are sewn edge to
  // edge, so the two sides of a seam must keep their length; 0 is plain ARAP.
  double boundary_weight = 10.0;
  // When plain ARAP leaves flipped triangles: rerun it injectively (true), or
  // return the flipped result (false; the automatic cuts use it to find where
  // to cut, and flips fail the distortion limit anyway).
  bool injective_fallback = true;
};

// Distortion statistics of a flattening. All area-weighted over 3D area.
struct DistortionStats {
  double p95_error = 0.0;        // 95th percentile (by area) of max(|s1-1|, |s2-1|)
  double max_error = 0.0;        // max over triangles of max(|s1-1|, |s2-1|)
  double max_stretch = 0.0;      // max over triangles of s1 - 1 (may be negative)
  double max_compression = 0.0;  // max over triangles of 1 - s2 (may be negative)
  double p95_stretch = 0.0;      // 95th percentile (by area) of s1 - 1
  double p95_compression = 0.0;  // 95th percentile (by area) of 1 - s2
  double mean_error = 0.0;       // area-weighted mean of max(|s1-1|, |s2-1|)
  double area_3d = 0.0;          // m^2
  double area_2d = 0.0;          // m^2 (signed sum of the flat triangles)
  int flipped_triangles = 0;     // flat triangles with area <= 0
};

// Singular values (s1, s2), s1 >= s2, of the Jacobian of every triangle, #F by 2.
// V is #V by 3 (metres), F is #F by 3, UV is #V by 2 (metres). Degenerate 3D
// triangles (zero area) get (1, 1).
Eigen::MatrixXd principal_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                    const Eigen::MatrixXd& UV);

DistortionStats distortion_stats(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const Eigen::MatrixXd& UV);

struct FlattenResult {
  Eigen::MatrixXd UV;          // #V by 2, metres, counter-clockwise where F is
  std::string initialization;  // "lscm", or "lscm, injective" / "tutte, injective" when plain ARAP flipped triangles
  int iterations = 0;
  double energy = 0.0;         // ARAP energy sum_t A_t |J_t - R_t|^2 plus the boundary-length term (m^2)
  DistortionStats stats;
  bool boundary_overlaps = false;                 // the flat boundary crosses itself
  std::vector<int> overlap_vertex_ids;            // boundary vertices at a crossing
};

// Flattens the piece (V #V by 3, F #F by 3, every vertex used, one connected
// disk: one boundary loop, Euler characteristic 1). With injective_fallback
// (the default) the result has no flipped triangle. Throws GeometryError if
// it is not a disk, NumericalError if a solve fails.
// `material_ids` (#V, optional): the uncut vertex of every piece vertex, for
// the overlap test of the flat outline (see polygon_self_intersects).
FlattenResult flatten_piece(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            const FlattenOptions& options = {}, const Eigen::VectorXi* material_ids = nullptr);

// Whether the closed polygon P (#P by 2) crosses or touches itself; fills
// the indices of the polygon vertices at the start of crossing segments.
// With `material_ids` (one id per polygon vertex), segments that share a
// material id are not tested against each other: the two sides of a cut meet
// at the cut's copies of one vertex (a dart that stays closed near its tip
// has coinciding sides), which is no overlap of the cloth.
bool polygon_self_intersects(const Eigen::MatrixXd& P, std::vector<int>* vertex_ids = nullptr,
                             const std::vector<int>* material_ids = nullptr);

}  // namespace gp
