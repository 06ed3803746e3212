#pragma once
// Flattening of one disk-shaped piece into the plane, in three entry points
// that flatten_piece() chains:
//   lscm_flatten  least-squares conformal map (Levy et al. 2002), free boundary;
//   tutte_flatten Tutte's embedding onto a circle (Floater 2003), flip-free;
//   arap_flatten  local/global iterations from a start (Liu et al. 2008) of
//                 an ARAP energy whose ease may cost less than compression
//                 (ease_weight), accelerated (Anderson; Peng et al. 2018),
//                 optionally with every step cut short before a triangle
//                 would flip (Smith and Schaefer 2015);
//   injective_flatten  flip-free steps on the symmetric Dirichlet energy
//                 (SLIM, Rabinovich et al. 2017), a barrier that keeps every
//                 triangle open where flips must be undone.
//
// Distortion of a triangle: the singular values s1 >= s2 of the 2x2 Jacobian
// J of the affine map from the triangle (in an orthonormal frame of its own
// plane) to its flat image. s1 - 1 is its stretch, 1 - s2 its compression;
// its error is max(|s1 - 1|, |s2 - 1|). A flat piece larger than its 3D
// triangle (s > 1) is ease in the sewn garment; a smaller one (s < 1) must be
// stretched to reach the rest shape.
//
// Linear solves use CHOLMOD's simplicial factorization, which calls no BLAS:
// the flattening is bitwise the same whichever BLAS kernels the CPU selects.
#include <string>
#include <vector>
#include <Eigen/Core>

namespace gp {

struct FlattenOptions {
  int max_iterations = 500;          // local/global iterations
  double tolerance = 1e-6;           // stop when the relative energy decrease is below this
  double line_search_margin = 0.9;   // fraction of the largest flip-free step taken
  // Weight of keeping boundary edges at their 3D length, relative to the
  // distortion energy of the triangle beside them (dimensionless). Seams are
  // sewn edge to edge, so the two sides of a seam must keep their length; 0
  // lets the boundary float.
  double boundary_weight = 10.0;
  // Cost of ease (a singular value s > 1 of a triangle's Jacobian costs
  // ease_weight (s - 1)^2) relative to compression (s < 1 costs (1 - s)^2),
  // in (0, 1]. 1 is ARAP; below 1 the flattening prefers a flat piece a
  // little larger than the rest shape (ease) to a smaller one (compression,
  // which the sewn cloth would have to stretch to make up).
  double ease_weight = 1.0;
  // A triangle's weight in the energy is its area, but at least this
  // fraction of the mean area: thin triangles along a cut resist turning over.
  double min_weight_fraction = 0.1;
  // Iterates of the local/global steps mixed by Anderson acceleration
  // (Peng et al. 2018); 0: plain local/global steps.
  int anderson_window = 6;
  // When plain iterations leave flipped triangles: rerun injectively (true),
  // or return the flipped result (false).
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
  double p99_compression = 0.0;  // 99th percentile (by area) of 1 - s2
  // Means over the worst part of the area (the last element taken in part,
  // so that they change continuously): 1 - s2 over the worst 1 %, s1 - 1
  // over the worst 5 %. Averages, unlike percentiles, do not jump from one
  // triangle's value to the next when a thin triangle comes or goes.
  double worst1_compression = 0.0;
  double worst5_ease = 0.0;
  double mean_error = 0.0;       // area-weighted mean of max(|s1-1|, |s2-1|)
  double area_3d = 0.0;          // m^2
  double area_2d = 0.0;          // m^2 (signed sum of the flat triangles)
  int flipped_triangles = 0;     // flat triangles with area <= 0
};

// Principal stretches (s1 >= s2) of the flattening of every triangle, #F by
// 2 (mesh/principal_stretches.h). V is #V by 3 (metres), F is #F by 3, UV is
// #V by 2 (metres). Degenerate 3D triangles (zero area) get (1, 1).
Eigen::MatrixXd flattening_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const Eigen::MatrixXd& UV);

DistortionStats distortion_stats(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const Eigen::MatrixXd& UV);

// The same figures from given singular values S (#items by 2, s1 >= s2),
// 3D areas (#items) and 2D areas (#items; <= 0 counts as flipped).
DistortionStats distortion_stats(const Eigen::MatrixXd& S, const Eigen::VectorXd& area_3d,
                                 const Eigen::VectorXd& area_2d);

// Least-squares conformal map of a disk (V #V by 3, F #F by 3, `loop` its
// boundary loop), two far boundary vertices pinned at their 3D distance;
// #V by 2, counter-clockwise where F is. Triangles weigh their area, but at
// least min_weight_fraction of the mean. Throws NumericalError if the solve fails.
Eigen::MatrixXd lscm_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop,
                             double min_weight_fraction = 0.0);

// Tutte's embedding (uniform weights) with the boundary on a circle spaced by
// 3D arc length: flip-free for any 3-connected disk; #V by 2, counter-clockwise.
Eigen::MatrixXd tutte_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop);

// The energy arap_flatten minimizes at UV (#V by 2): sum over triangles of
// w_t sum_i f(s_i) (w_t the area, at least min_weight_fraction of the mean;
// f(s) = (1 - s)^2 below 1, ease_weight (s - 1)^2 above; a flipped triangle
// costs |J - R|^2, R its closest rotation) plus the boundary-length term
// sum_e w_e (|u_i - u_j| - l_e)^2. With `gradient`, its gradient (#V by 2).
double flattening_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& UV,
                         const FlattenOptions& options, Eigen::MatrixXd* gradient = nullptr);

struct ArapRun {
  int iterations = 0;
  double energy = 0.0;  // sum_t A_t sum_i f(s_i) plus the boundary-length term (m^2)
};

// Local/global iterations from UV (#V by 2, in place) with the options'
// ease weight and boundary weight. With `injective`, UV must start
// without flipped triangles and every global step is shortened to 90 % of the
// largest flip-free step: the result has no flipped triangle.
ArapRun arap_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                     const FlattenOptions& options, bool injective);

// sum_t w_t (|J|^2 + |J^-1|^2 - 4) at UV (#V by 2; w_t as in
// flattening_energy); infinite if a triangle is flipped or degenerate.
double symmetric_dirichlet_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& UV,
                                  const FlattenOptions& options);

// Flip-free iterations from UV (#V by 2, in place, no flip; else
// GeometryError) on symmetric_dirichlet_energy plus the boundary-length
// term; ease_weight is not used. The result has no flipped or degenerate triangle.
ArapRun injective_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                          const FlattenOptions& options);

struct FlattenResult {
  Eigen::MatrixXd UV;          // #V by 2, metres, counter-clockwise where F is
  std::string initialization;  // "lscm"; "lscm, untangled, injective", "lscm, injective" or "tutte, injective" after flips
  int iterations = 0;
  double energy = 0.0;         // final energy of arap_flatten (m^2)
  DistortionStats stats;
  bool boundary_overlaps = false;                 // the flat boundary crosses itself
  std::vector<int> overlap_vertex_ids;            // boundary vertices at a crossing
};

// LSCM, then arap_flatten; if that leaves flipped triangles and
// injective_fallback is set, they are untangled locally (their vertices moved
// to their neighbours' mean) and arap_flatten resumed, or, where that fails,
// run injectively from a flip-free start (LSCM if it has no flip, else
// Tutte). A piece that is not 3-connected may have no flip-free start: its
// plain flattening is returned with its flips (stats.flipped_triangles).
// The piece (V #V by 3, F #F by 3, every vertex used) must be one connected
// disk: one boundary loop, Euler characteristic 1. Throws GeometryError if it is not, NumericalError if a
// solve fails. `material_ids` (#V, optional): the uncut vertex of every piece
// vertex, for the overlap test of the flat outline (see polygon_self_intersects).
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
