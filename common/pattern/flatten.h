#pragma once
// Flattening of one disk-shaped piece into the plane, in three entry points
// that flatten_piece() chains:
//   lscm_flatten  least-squares conformal map (Levy et al. 2002), free boundary;
//   tutte_flatten Tutte's embedding onto a circle (Floater 2003), flip-free;
//   arap_flatten  local/global iterations (Liu et al. 2008) of an ARAP
//                 energy with cheaper ease, Anderson-accelerated, optionally
//                 flip-free (Smith and Schaefer 2015);
//   injective_flatten  flip-free steps on the symmetric Dirichlet energy
//                 (SLIM, Rabinovich et al. 2017), a barrier to degeneracy.
//
// A triangle's distortion: the singular values s1 >= s2 of its flattening's
// Jacobian; s1 - 1 is ease in the sewn garment, 1 - s2 compression it must
// stretch out, max(|s1 - 1|, |s2 - 1|) the error. Solves use CHOLMOD's
// simplicial factor (no BLAS), so results do not depend on the CPU.
#include <string>
#include <vector>
#include <Eigen/Core>

#include "spec/option_fields.h"

namespace gp {

struct FlattenOptions {
  int max_iterations = 500;          // local/global iterations
  double tolerance = 1e-6;           // stop when the relative energy decrease is below this
  double injective_tolerance = 1e-5;  // the same for the injective iterations (why: pattern README, "Flatten")
  // The same for the output pieces' last iterations (polish_flattening):
  // a piece's flat shape then no longer depends on the last bits of its
  // input (why: pattern README, "Flatten").
  double final_tolerance = 1e-12;
  double line_search_margin = 0.9;   // fraction of the largest flip-free step taken
  // Weight of boundary edges' 3D length against the triangle beside them
  // (seams are sewn edge to edge); 0 lets the boundary float.
  double boundary_weight = 10.0;
  // Cost of ease, ease_weight (s - 1)^2, against compression's (1 - s)^2, in
  // (0, 1]; 1 is ARAP, below it a piece is rather a little larger.
  double ease_weight = 1.0;
  double min_weight_fraction = 0.1;  // a triangle weighs its area, at least this fraction of the mean
  int anderson_window = 6;           // iterates mixed by Anderson acceleration (Peng et al. 2018); 0: none
  bool injective_fallback = true;    // flips left: rerun injectively (false: return them)
  // Limit weighting (limit_weights below): after the plain iterations, up to
  // this many rounds in which every triangle compressed beyond
  // limit_margin * limit_compression (1 - s2) or eased beyond
  // limit_margin * limit_ease (s1 - 1) weighs more, by its excess over that
  // target relative to it, and the iterations resume. 0: off. The cutter
  // sets the two limits from its own (DistortionLimit).
  int limit_rounds = 0;
  double limit_compression = 0.03;   // fraction
  double limit_ease = 0.10;          // fraction
  double limit_margin = 0.8;         // fraction of the limits a triangle is weighed against
  double max_face_weight = 50.0;     // a triangle's weight grows to at most this multiple
  // The rounds' iterations stop at this relative decrease, the kept round's
  // at limit_tolerance (each at most 4 max_iterations; why: pattern README,
  // "The limit weighting").
  double limit_round_tolerance = 1e-8;
  double limit_tolerance = 1e-9;
  // The compression a round may leave in a triangle that the plain
  // flattening compressed less: the sewn garment must stretch a flat
  // triangle compressed by c by 1 / (1 - c) before the motion adds any. A
  // round that compresses any triangle beyond max(this, its plain
  // compression) is not kept, and triangles beyond it are weighed against
  // it. The cutter sets it from the fit's stretch budget
  // (PanelOptions::budget_share * stretch_budget). 0: no budget.
  double compression_budget = 0.0;   // fraction
  int limit_patience = 3;            // rounds without a better admissible one before the weighting stops
};

// The options as a report records them (spec/option_fields.h).
struct FlattenOptionFields {
  template <class Fields>
  void operator()(FlattenOptions& o, Fields& f) const {
    f.integer("max_iterations", o.max_iterations, Range::between(1, 1e9));
    f.number("tolerance", o.tolerance, Range::positive());
    f.number("injective_tolerance", o.injective_tolerance, Range::positive());
    f.number("final_tolerance", o.final_tolerance, Range::positive());
    f.number("line_search_margin", o.line_search_margin, Range::between(0.0, 1.0));
    f.number("boundary_weight", o.boundary_weight, Range::non_negative());
    f.number("ease_weight", o.ease_weight, Range::between(0.0, 1.0));
    f.number("min_weight_fraction", o.min_weight_fraction, Range::between(0.0, 1.0));
    f.integer("anderson_window", o.anderson_window, Range::between(0, 1000));
    f.flag("injective_fallback", o.injective_fallback);
    f.integer("limit_rounds", o.limit_rounds, Range::between(0, 1000));
    f.number("limit_compression", o.limit_compression, Range::positive());
    f.number("limit_ease", o.limit_ease, Range::positive());
    f.number("limit_margin", o.limit_margin, Range::positive());
    f.number("max_face_weight", o.max_face_weight, Range::between(1.0, 1e6));
    f.number("limit_round_tolerance", o.limit_round_tolerance, Range::positive());
    f.number("limit_tolerance", o.limit_tolerance, Range::positive());
    f.number("compression_budget", o.compression_budget, Range::between(0.0, 1.0));
    f.integer("limit_patience", o.limit_patience, Range::between(1, 1000));
  }
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
  // Means over the worst 1 % (compression) and 5 % (ease) of the area, the
  // last element taken in part: continuous, unlike percentiles.
  double worst1_compression = 0.0;
  double worst5_ease = 0.0;
  double mean_error = 0.0;       // area-weighted mean of max(|s1-1|, |s2-1|)
  // The bulk of the piece (the median by area, not its tail): the one-sided
  // energy eases most of a curved piece a little rather than compress any,
  // and that ease is cloth the sewn garment carries (pattern README,
  // "Ease in the bulk").
  double median_ease = 0.0;         // median (by area) of s1 - 1
  double median_compression = 0.0;  // median (by area) of 1 - s2
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
// `face_weight` (#F, optional) multiplies each triangle's weight w_t.
double flattening_energy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& UV,
                         const FlattenOptions& options, Eigen::MatrixXd* gradient = nullptr,
                         const Eigen::VectorXd* face_weight = nullptr);

struct ArapRun {
  int iterations = 0;
  double energy = 0.0;  // sum_t A_t sum_i f(s_i) plus the boundary-length term (m^2)
};

// Local/global iterations from UV (#V by 2, in place). With `injective`, UV
// starts flip-free and each step is cut to 90 % of the largest flip-free one.
// `face_weight` (#F, optional) multiplies each triangle's weight.
ArapRun arap_flatten(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                     const FlattenOptions& options, bool injective, const Eigen::VectorXd* face_weight = nullptr);

// The limit weighting (FlattenOptions::limit_rounds): a least-squares
// energy spreads distortion evenly on average but leaves its tails where the
// surface is most curved, while the cutter's limit bounds the tails (means
// over the worst 1 % and 5 % of the area). Iteratively reweighted least
// squares moves the minimum towards the tails' bound (Lawson's algorithm for
// a min-max fit; the same device as the reweighting of Rabinovich et al.
// 2017, here on the excess over a target): each round multiplies the weight
// of a triangle over its target (limit_margin of the ease limit, or of the
// lower of the compression limit and compression_budget) by 1 + (excess /
// target), capped at max_face_weight, and resumes the plain iterations
// (to limit_round_tolerance) from UV and `face_weight` (#F; empty: all 1).
// A round counts only where no triangle is compressed beyond its ceiling,
// max(compression_budget, its compression in the plain flattening at UV).
// The admissible round whose worse bound (worst1_compression /
// limit_compression, worst5_ease / limit_ease) is lowest is converged to
// limit_tolerance and returned in UV and `face_weight` if it is still
// admissible, flip-free and better than the plain flattening; else UV and
// `face_weight` are left as they were. Stops at a round within both bounds,
// at one that flips a triangle, after limit_patience rounds without
// progress or after limit_rounds. Returns the rounds run.
int limit_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                  Eigen::VectorXd& face_weight, const FlattenOptions& options);

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
  Eigen::VectorXd face_weight; // #F, the limit weighting's multipliers (empty: none)
  int limit_rounds = 0;        // rounds of limit_weights run
  DistortionStats stats;
  bool boundary_overlaps = false;                 // the flat boundary crosses itself
  std::vector<int> overlap_vertex_ids;            // boundary vertices at a crossing
};

// LSCM, then arap_flatten; flips left (with injective_fallback) are
// untangled locally and arap_flatten resumed, else flattened injectively from
// a flip-free start (LSCM, else Tutte; a piece that is not 3-connected may
// keep its flips). V #V by 3, F #F by 3: one disk, else GeometryError;
// NumericalError if a solve fails. `material_ids` (#V, optional): each
// vertex's uncut vertex, for the outline's overlap test.
FlattenResult flatten_piece(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            const FlattenOptions& options = {}, const Eigen::VectorXi* material_ids = nullptr);

// Resumes a plain (not injective) flip-free flattening of flatten_piece
// until its energy falls by less than final_tolerance in an iteration (at
// most 20 max_iterations), and measures it again; `result` is left as it was
// where that folds a triangle or does not lower the energy.
void polish_flattening(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FlattenResult& result,
                       const FlattenOptions& options, const Eigen::VectorXi* material_ids = nullptr);

// Whether the closed polygon P (#P by 2) crosses or touches itself, with the
// vertices starting crossing segments. Segments sharing a `material_ids` id
// are not tested (a closed dart's sides meet, which is no overlap).
bool polygon_self_intersects(const Eigen::MatrixXd& P, std::vector<int>* vertex_ids = nullptr,
                             const std::vector<int>* material_ids = nullptr);

}  // namespace gp
