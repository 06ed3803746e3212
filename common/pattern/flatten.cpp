#include "pattern/flatten.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/math.h"
#include "linalg/cholmod_solver.h"
#include "mesh/barycentric.h"
#include "mesh/measures.h"
#include "mesh/principal_stretches.h"
#include "mesh/topology.h"
#include "pattern/flatten_common.h"

namespace gp {

using namespace flatten_detail;

Eigen::MatrixXd flattening_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const Eigen::MatrixXd& UV) {
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  Eigen::MatrixXd S(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    const LocalTriangle& t = T[static_cast<size_t>(f)];
    S.row(f) = t.degenerate ? Eigen::RowVector2d(1.0, 1.0)
                            : singular_values_2x2(jacobian(t, UV, F.row(f))).transpose();
  }
  return S;
}

DistortionStats distortion_stats(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                 const Eigen::MatrixXd& UV) {
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  Eigen::VectorXd area(F.rows()), area_2d(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    area[f] = T[static_cast<size_t>(f)].area;
    area_2d[f] = signed_area_2d(UV, F.row(f));
  }
  return distortion_stats(flattening_stretches(V, F, UV), area, area_2d);
}

DistortionStats distortion_stats(const Eigen::MatrixXd& S, const Eigen::VectorXd& area_3d,
                                 const Eigen::VectorXd& area_2d) {
  DistortionStats st;
  const int m = static_cast<int>(S.rows());
  if (m == 0) return st;
  std::vector<double> err(static_cast<size_t>(m)), str(static_cast<size_t>(m)), com(static_cast<size_t>(m));
  st.max_error = st.max_stretch = st.max_compression = -std::numeric_limits<double>::infinity();
  double weighted = 0.0;
  for (int f = 0; f < m; ++f) {
    const size_t i = static_cast<size_t>(f);
    st.area_3d += area_3d[f];
    st.area_2d += area_2d[f];
    if (!(area_2d[f] > 0.0)) ++st.flipped_triangles;
    str[i] = S(f, 0) - 1.0;
    com[i] = 1.0 - S(f, 1);
    err[i] = std::max(std::abs(S(f, 0) - 1.0), std::abs(S(f, 1) - 1.0));
    st.max_error = std::max(st.max_error, err[i]);
    st.max_stretch = std::max(st.max_stretch, str[i]);
    st.max_compression = std::max(st.max_compression, com[i]);
    weighted += area_3d[f] * err[i];
  }
  st.mean_error = st.area_3d > 0.0 ? weighted / st.area_3d : 0.0;
  auto percentile = [&](const std::vector<double>& value, double fraction) {
    return area_weighted_percentile(Eigen::Map<const Eigen::VectorXd>(value.data(), m), area_3d, fraction);
  };
  // Mean of the values over the worst `fraction` of the area.
  auto worst_mean = [&](const std::vector<double>& value, double fraction) {
    std::vector<int> order(static_cast<size_t>(m));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return value[static_cast<size_t>(a)] > value[static_cast<size_t>(b)] ||
             (value[static_cast<size_t>(a)] == value[static_cast<size_t>(b)] && a < b);
    });
    const double want = fraction * st.area_3d;
    double acc = 0.0, sum = 0.0;
    for (int f : order) {
      const double take = std::min(area_3d[f], want - acc);
      if (take <= 0.0) break;
      sum += take * value[static_cast<size_t>(f)];
      acc += take;
    }
    return acc > 0.0 ? sum / acc : 0.0;
  };
  st.worst1_compression = worst_mean(com, 0.01);
  st.worst5_ease = worst_mean(str, 0.05);
  st.p95_error = percentile(err, 0.95);
  st.p95_stretch = percentile(str, 0.95);
  st.p95_compression = percentile(com, 0.95);
  st.p99_compression = percentile(com, 0.99);
  st.median_ease = percentile(str, 0.5);
  st.median_compression = percentile(com, 0.5);
  return st;
}

bool polygon_self_intersects(const Eigen::MatrixXd& P, std::vector<int>* vertex_ids,
                             const std::vector<int>* material_ids) {
  const int n = static_cast<int>(P.rows());
  if (n < 4) return false;
  auto orient = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    const double v = orient_2d(a, b, c);
    return (v > 0.0) - (v < 0.0);
  };
  auto on_segment = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return std::min(a.x(), b.x()) <= c.x() && c.x() <= std::max(a.x(), b.x()) &&
           std::min(a.y(), b.y()) <= c.y() && c.y() <= std::max(a.y(), b.y());
  };
  // Sweep over segments sorted by their left end: only segments whose x
  // ranges overlap are tested.
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  auto xmin = [&](int i) { return std::min(P(i, 0), P((i + 1) % n, 0)); };
  auto xmax = [&](int i) { return std::max(P(i, 0), P((i + 1) % n, 0)); };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return xmin(a) < xmin(b) || (xmin(a) == xmin(b) && a < b); });
  bool found = false;
  for (size_t ia = 0; ia < order.size(); ++ia) {
    const int i = order[ia];
    const Eigen::Vector2d a = P.row(i), b = P.row((i + 1) % n);
    for (size_t ib = ia + 1; ib < order.size() && xmin(order[ib]) <= xmax(i); ++ib) {
      const int j = order[ib];
      if (j == (i + 1) % n || i == (j + 1) % n) continue;
      if (material_ids) {
        const auto& m = *material_ids;
        const int mi0 = m[static_cast<size_t>(i)], mi1 = m[static_cast<size_t>((i + 1) % n)];
        const int mj0 = m[static_cast<size_t>(j)], mj1 = m[static_cast<size_t>((j + 1) % n)];
        if (mi0 == mj0 || mi0 == mj1 || mi1 == mj0 || mi1 == mj1) continue;
      }
      const Eigen::Vector2d c = P.row(j), d = P.row((j + 1) % n);
      const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
      bool hit = (o1 != o2 && o3 != o4);
      if (!hit)
        hit = (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
              (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
      if (hit) {
        found = true;
        if (!vertex_ids) return true;
        vertex_ids->push_back(std::min(i, j));
        vertex_ids->push_back(std::max(i, j));
      }
    }
  }
  if (vertex_ids) {
    std::sort(vertex_ids->begin(), vertex_ids->end());
    vertex_ids->erase(std::unique(vertex_ids->begin(), vertex_ids->end()), vertex_ids->end());
  }
  return found;
}

namespace {

// The result's distortion figures and the overlaps of its outline.
void measure_result(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& loop,
                    const Eigen::VectorXi* material_ids, FlattenResult& result) {
  result.stats = distortion_stats(V, F, result.UV);
  Eigen::MatrixXd P(static_cast<int>(loop.size()), 2);
  for (size_t k = 0; k < loop.size(); ++k) P.row(static_cast<int>(k)) = result.UV.row(loop[k]);
  std::vector<int> at, material;
  if (material_ids)
    for (int v : loop) material.push_back((*material_ids)[v]);
  result.overlap_vertex_ids.clear();
  result.boundary_overlaps = polygon_self_intersects(P, &at, material_ids ? &material : nullptr);
  for (int k : at) result.overlap_vertex_ids.push_back(loop[static_cast<size_t>(k)]);
}

// Compression a kept round may leave beyond a triangle's ceiling (a tenth
// of a percent): the converged round's rounding, not cloth to stretch out.
constexpr double kCeilingTolerance = 1e-3;

}  // namespace

int limit_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::MatrixXd& UV,
                  Eigen::VectorXd& face_weight, const FlattenOptions& options) {
  const Eigen::VectorXd given = face_weight;
  if (face_weight.size() != F.rows()) face_weight = Eigen::VectorXd::Ones(F.rows());
  const double budget = options.compression_budget > 0.0 ? options.compression_budget
                                                         : std::numeric_limits<double>::infinity();
  // Compression is weighed against the limit's target or the budget,
  // whichever is lower: a least-squares energy whose eased triangles weigh
  // more pushes their cloth into the compression of the triangles around
  // them, and those must not end beyond what the sewn garment can stretch.
  const double tc = options.limit_margin * std::min(options.limit_compression, budget);
  const double te = options.limit_margin * options.limit_ease;
  const std::vector<LocalTriangle> T = local_triangles(V, F);
  Eigen::VectorXd area(F.rows()), area_2d(F.rows());
  for (int f = 0; f < F.rows(); ++f) area[f] = T[static_cast<size_t>(f)].area;
  // The worse of the two bounds at X, whose stretches are S.
  auto ratio = [&](const Eigen::MatrixXd& X, const Eigen::MatrixXd& S) {
    for (int f = 0; f < F.rows(); ++f) area_2d[f] = signed_area_2d(X, F.row(f));
    const DistortionStats s = distortion_stats(S, area, area_2d);
    return std::max(s.worst1_compression / options.limit_compression, s.worst5_ease / options.limit_ease);
  };
  // Each triangle's ceiling: the budget, or its plain compression where
  // that was beyond it (the weighting may leave it there, not add to it).
  const Eigen::MatrixXd S0 = flattening_stretches(V, F, UV);
  Eigen::VectorXd ceiling(F.rows());
  for (int f = 0; f < F.rows(); ++f) ceiling[f] = std::max(budget, 1.0 - S0(f, 1)) + kCeilingTolerance;
  // The compression beyond the ceilings, summed over the triangles (3D area
  // times excess): 0 where a round is admissible.
  auto violation = [&](const Eigen::MatrixXd& S) {
    double sum = 0.0;
    for (int f = 0; f < F.rows(); ++f) sum += area[f] * std::max(0.0, 1.0 - S(f, 1) - ceiling[f]);
    return sum;
  };
  double least_violation = std::numeric_limits<double>::infinity();
  const Eigen::MatrixXd plain_UV = UV;
  const double plain = ratio(UV, S0);
  double best = plain;
  Eigen::MatrixXd best_UV = UV;
  Eigen::VectorXd best_weight = face_weight;
  bool improved = false;
  int rounds = 0, stalled = 0;
  Eigen::MatrixXd S = S0;
  // The plain iterations run further than the cutter's own: to `tolerance`,
  // for at most 4 max_iterations.
  auto converging_to = [&](double tolerance) {
    FlattenOptions o = options;
    o.tolerance = std::min(options.tolerance, tolerance);
    o.max_iterations = 4 * options.max_iterations;
    return o;
  };
  // Each round is warm-started from the one before and stops at
  // limit_round_tolerance; only the kept one is converged further (below).
  const FlattenOptions round = converging_to(options.limit_round_tolerance);
  for (int r = 0; r < options.limit_rounds && best > 1.0 && stalled < options.limit_patience; ++r) {
    bool any = false;
    for (int f = 0; f < F.rows(); ++f) {
      const double excess = std::max(0.0, (1.0 - S(f, 1)) / tc - 1.0) + std::max(0.0, (S(f, 0) - 1.0) / te - 1.0);
      if (excess <= 0.0) continue;
      face_weight[f] = std::min(options.max_face_weight, face_weight[f] * (1.0 + excess));
      any = true;
    }
    if (!any) break;
    arap_flatten(V, F, UV, round, false, &face_weight);
    ++rounds;
    if (!UV.allFinite() || count_flips(UV, F) > 0) break;
    S = flattening_stretches(V, F, UV);
    const double now = ratio(UV, S);
    // A round makes progress where it is better and admissible, or, not
    // admissible, less beyond the ceilings than any round before: the
    // compression weights catch up with the ease weights over a few rounds.
    const double over = violation(S);
    if (over <= 0.0 && now < best - 1e-4) {
      best = now;
      best_UV = UV;
      best_weight = face_weight;
      improved = true;
      stalled = 0;
    } else if (over > 0.0 && over < 0.9 * least_violation) {
      least_violation = over;
      stalled = 0;
    } else {
      ++stalled;
    }
  }
  UV = plain_UV;
  face_weight = given;
  if (!improved) return rounds;
  // The kept round converged: stopped early, a reweighted piece sits where
  // the polish (to final_tolerance, with the same weights) would not leave
  // it (on the demo's front, rounds stopped at 1e-6 measured 3.2 % of
  // compression and polished 5.6 %). Kept only where converged it is still
  // better than the plain flattening and within the ceilings.
  Eigen::MatrixXd X = best_UV;
  arap_flatten(V, F, X, converging_to(options.limit_tolerance), false, &best_weight);
  if (!X.allFinite() || count_flips(X, F) > 0) return rounds;
  const Eigen::MatrixXd SX = flattening_stretches(V, F, X);
  if (!(ratio(X, SX) < plain) || violation(SX) > 0.0) return rounds;
  UV = X;
  face_weight = best_weight;
  return rounds;
}

FlattenResult flatten_piece(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            const FlattenOptions& options, const Eigen::VectorXi* material_ids) {
  const auto loops = boundary_loops(F);
  if (loops.size() != 1 || euler_characteristic(F) != 1)
    throw GeometryError("a piece to flatten must be a disk (one boundary loop, Euler characteristic 1); it has " +
                        std::to_string(loops.size()) + " boundary loops and Euler characteristic " +
                        std::to_string(euler_characteristic(F)));
  if (!V.allFinite()) throw GeometryError("the piece has non-finite vertex coordinates");
  const std::vector<int>& loop = loops.front();

  FlattenResult result;
  Eigen::MatrixXd UV_lscm;
  bool lscm_solved = false;
  try {
    UV_lscm = lscm_flatten(V, F, loop, options.min_weight_fraction);
    lscm_solved = UV_lscm.allFinite();
  } catch (const NumericalError&) {
    lscm_solved = false;
  }
  // Plain iterations from LSCM first (fastest to converge). Flipped
  // triangles they leave are untangled locally and the iterations resumed
  // injectively from there; if that fails, injective iterations from a
  // flip-free start (LSCM when it has no flips, else Tutte's embedding)
  // guarantee a flip-free result.
  bool done = false;
  if (lscm_solved) {
    result.UV = UV_lscm;
    result.initialization = "lscm";
    const ArapRun run = arap_flatten(V, F, result.UV, options, false);
    result.iterations = run.iterations;
    result.energy = run.energy;
    done = result.UV.allFinite() && (count_flips(result.UV, F) == 0 || !options.injective_fallback);
    if (!done && result.UV.allFinite()) {
      Eigen::MatrixXd repaired = result.UV;
      if (repair_flips(F, vertex_neighbors(F, static_cast<int>(V.rows())), loop, repaired)) {
        // Plain iterations again from the untangled map (they often settle
        // without the flips now); injective ones where they do not.
        Eigen::MatrixXd again = repaired;
        const ArapRun plain = arap_flatten(V, F, again, options, false);
        result.iterations += plain.iterations;
        if (again.allFinite() && count_flips(again, F) == 0) {
          result.UV = again;
          result.initialization = "lscm, untangled";
          result.energy = plain.energy;
          done = true;
        } else {
          result.UV = repaired;
          result.initialization = "lscm, untangled, injective";
          FlattenOptions longer = options;
          longer.max_iterations = 4 * options.max_iterations;
          const ArapRun more = injective_flatten(V, F, result.UV, longer);
          result.iterations += more.iterations;
          result.energy = more.energy;
          done = count_flips(result.UV, F) == 0;
        }
      }
    }
  }
  if (!done) {
    const FlattenResult plain = result;
    bool start = true;
    if (lscm_solved && count_flips(UV_lscm, F) == 0) {
      result.UV = UV_lscm;
      result.initialization = "lscm, injective";
    } else {
      result.UV = tutte_flatten(V, F, loop);
      result.initialization = "tutte, injective";
      // A piece that is not 3-connected (a vertex whose neighbours all lie
      // on the outline) can fold even in Tutte's embedding.
      start = count_flips(result.UV, F) == 0;
    }
    if (start) {
      const ArapRun run = injective_flatten(V, F, result.UV, options);
      result.iterations += run.iterations;
      result.energy = run.energy;
    } else if (plain.UV.size() > 0 && plain.UV.allFinite()) {
      // No flip-free start: the plain flattening with its flips (reported).
      result = plain;
      result.initialization += ", flips kept";
    } else {
      // Nor a plain one (LSCM failed): plain iterations from Tutte's folded embedding.
      const ArapRun run = arap_flatten(V, F, result.UV, options, false);
      result.initialization = "tutte, flips kept";
      result.iterations = run.iterations;
      result.energy = run.energy;
    }
  }
  if (!result.UV.allFinite()) throw NumericalError("the flattening produced non-finite coordinates");
  // The tails of a plain flip-free flattening weighed towards the limit.
  if (options.limit_rounds > 0 && result.initialization.find("injective") == std::string::npos &&
      result.initialization.find("flips kept") == std::string::npos && count_flips(result.UV, F) == 0) {
    result.limit_rounds = limit_weights(V, F, result.UV, result.face_weight, options);
    result.energy = flattening_energy(V, F, result.UV, options, nullptr, &result.face_weight);
  }
  measure_result(V, F, loop, material_ids, result);
  return result;
}

void polish_flattening(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, FlattenResult& result,
                       const FlattenOptions& options, const Eigen::VectorXi* material_ids) {
  // Injective results minimise another energy, and a piece that kept its
  // flips has no flip-free start.
  if (result.initialization.find("injective") != std::string::npos || count_flips(result.UV, F) > 0) return;
  FlattenOptions tight = options;
  tight.tolerance = options.final_tolerance;
  tight.max_iterations = 20 * options.max_iterations;
  Eigen::MatrixXd UV = result.UV;
  // Plain steps (the line search would only shorten them); a polish that
  // folds the piece is not taken.
  const Eigen::VectorXd* weight = result.face_weight.size() == F.rows() ? &result.face_weight : nullptr;
  const ArapRun run = arap_flatten(V, F, UV, tight, false, weight);
  if (!UV.allFinite() || count_flips(UV, F) > 0 || !(run.energy <= result.energy)) return;
  result.UV = UV;
  result.iterations += run.iterations;
  result.energy = run.energy;
  measure_result(V, F, boundary_loops(F).front(), material_ids, result);
}

}  // namespace gp
