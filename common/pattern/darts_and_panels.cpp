#include "pattern/make_pattern.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <optional>
#include <set>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/stopwatch.h"
#include "mesh/graph_paths.h"
#include "mesh/heat_geodesics.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pattern/dart_placement.h"
#include "pattern/piece_mirror.h"
#include "pattern/piece_names.h"
#include "pattern/cutter_helpers.h"

namespace gp {

double panel_excess(const std::vector<MaterialFace>& faces, const PatternOptions& options) {
  const double c_lim = options.limit.symmetric ? options.limit.max_limit : options.limit.compression_worst1;
  const double e_lim = options.limit.symmetric ? options.limit.max_limit : options.limit.ease_worst5;
  double excess = 0.0;
  for (const MaterialFace& m : faces) {
    const double c = 1.0 - m.stretch[1], e = m.stretch[0] - 1.0;
    excess += m.area * (std::max(0.0, c - c_lim) / c_lim + std::max(0.0, e - e_lim) / e_lim);
  }
  return excess;
}

namespace {

// What a piece was given: its dart tips and the point its panel seam runs
// through, and the names of the cuts.
struct Given {
  std::vector<DartTip> tips;
  std::vector<std::string> darts;
  std::optional<Eigen::Vector3d> centre;
  std::string panel;
  bool cut() const { return !tips.empty() || centre; }
};

// One call of place_darts_and_panels: the cuts chosen so far and the
// budgets they draw on.
class DartPanelPlacer {
 public:
  DartPanelPlacer(Pattern& pattern, const PatternOptions& options, PanelLedger* ledger)
      : pattern_(pattern), options_(options), ledger_(ledger) {
    for (const auto& s : pattern.seams) {
      if (s.kind == "dart") ++darts_;
      if (s.kind == "panel") ++panels_;
    }
    // Panel seams removed again keep their names: new ones are numbered on.
    for (const auto& m : pattern.merged_cuts)
      if (m.rfind("panel", 0) == 0) ++panels_;
    done_.assign(pattern.pieces.size(), 0);
    cut_.assign(pattern.pieces.size(), 0);
    pieces_ = static_cast<int>(pattern.pieces.size());
  }

  // Failing pieces, the largest first: the piece budget goes where the most
  // cloth is. Returns the number of cuts inserted.
  int run() {
    std::vector<size_t> order;
    for (size_t c = 0; c < pattern_.pieces.size(); ++c)
      if (!pattern_.pieces[c].meets_limit) order.push_back(c);
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return pattern_.pieces[a].stats.area_3d > pattern_.pieces[b].stats.area_3d;
    });
    if (order.empty()) return 0;
    // A tailor cuts both sides of the body alike: a piece's mirror image gets
    // the mirror image of its darts and panel seam, whether or not it is over
    // the limit itself.
    if (options_.panels.mirror) mirror_ = mirror_pieces(pattern_, options_.panels.mirror_overlap);
    count_limb_pieces();
    for (size_t c : order) cut_piece_and_image(c);
    if (seams_.empty()) return 0;
    insert_cuts(pattern_, seams_, curves_);
    return static_cast<int>(seams_.size());
  }

 private:
  int partner(size_t c) const { return mirror_.partner.empty() ? -1 : mirror_.partner[c]; }

  // The limb (sleeve) each piece belongs to (most of its area beyond an
  // armhole, as piece_names.h names sleeves), -1 for the body's, and how
  // many pieces each limb has.
  void count_limb_pieces() {
    limb_of_piece_.assign(pattern_.pieces.size(), -1);
    for (size_t c = 0; c < pattern_.pieces.size(); ++c) {
      limb_of_piece_[c] = piece_limb(pattern_, c);
      if (limb_of_piece_[c] >= 0) ++limb_pieces_[limb_of_piece_[c]];
    }
  }

  bool sleeve_full(size_t c) {
    const int limb = limb_of_piece_[c];
    return options_.panels.max_sleeve_pieces > 0 && limb >= 0 && limb_pieces_[limb] >= options_.panels.max_sleeve_pieces;
  }

  // Mirror images are judged and removed together (review_panels,
  // merge_small_pieces).
  void pair_mirrors(PatternSeam& seam, const std::string& image) {
    if (image.empty()) return;
    seam.mirror = image;
    for (PatternSeam& s : seams_)
      if (s.name == image) s.mirror = seam.name;
  }

  // Piece c, then its mirror image the same way where it has one and c was cut.
  void cut_piece_and_image(size_t c) {
    if (done_[c]) return;
    done_[c] = 1;
    const Given given = place(c, nullptr, c);
    cut_[c] = given.cut();
    const int d = partner(c);
    if (d < 0 || d == static_cast<int>(c) || cut_[static_cast<size_t>(d)]) return;
    if (!cut_[c]) return;  // the mirror image decides for itself
    done_[static_cast<size_t>(d)] = 1;
    const Given image = place(static_cast<size_t>(d), &given, c);
    cut_[static_cast<size_t>(d)] = image.cut();
    // A panel seam whose mirror image has no room is not cut either, and the
    // piece gets no other: one side split and the other not is no pattern.
    if (!given.panel.empty() && image.panel.empty()) withdraw_panel(given.panel, c, static_cast<size_t>(d));
  }

  void withdraw_panel(const std::string& panel, size_t c, size_t d) {
    for (size_t i = 0; i < seams_.size(); ++i)
      if (seams_[i].name == panel) {
        seams_.erase(seams_.begin() + static_cast<long>(i));
        curves_.erase(curves_.begin() + static_cast<long>(i));
        break;
      }
    if (ledger_) {
      auto& trials = ledger_->trials;
      trials.erase(std::remove_if(trials.begin(), trials.end(), [&](const PanelTrial& t) { return t.seam == panel; }),
                   trials.end());
      ledger_->refused.insert(piece_rest_faces(pattern_, c));
    }
    --panels_;
    --pieces_;
    pattern_.notes.push_back("piece " + pattern_.pieces[c].name + ": no panel seam, as its mirror image " +
                             pattern_.pieces[d].name + " has no room for one");
  }

  // Darts, else a panel seam, for piece c: its own (source null) or the
  // mirror images of what `source` (piece source_piece) was given.
  Given place(size_t c, const Given* source, size_t source_piece) {
    Given given;
    const PatternPiece& p = pattern_.pieces[c];
    const std::string over =
        source ? "piece " + p.name + " is cut as its mirror image " + pattern_.pieces[source_piece].name + " is: "
               : "piece " + p.name + " exceeds the limit (compression " + percent(p.stats.worst1_compression) +
                     " over its worst 1 %, ease " + percent(p.stats.worst5_ease) + " over its worst 5 %): ";
    Eigen::MatrixXd chart;
    try {
      chart = conformal_chart(p);
    } catch (const NumericalError&) {
      pattern_.notes.push_back("piece " + p.name + ": no conformal chart to place a dart or seam in");
      return given;
    }
    place_darts(c, source, over, chart, given);
    const std::vector<int> rest_faces = piece_rest_faces(pattern_, c);
    // A piece whose mirror image's panel seam did not pay is refused too.
    const int d = partner(c);
    const bool refused =
        ledger_ && (ledger_->refused.count(rest_faces) ||
                    (d >= 0 && d != static_cast<int>(c) &&
                     ledger_->refused.count(piece_rest_faces(pattern_, static_cast<size_t>(d)))));
    // A piece and its mirror image take two pieces from the budget together.
    const int cost = !source && d >= 0 && d != static_cast<int>(c) && !cut_[static_cast<size_t>(d)] ? 2 : 1;
    if (given.tips.empty() && pieces_ + cost <= options_.panels.max_pieces && !refused && !sleeve_full(c) &&
        (!source || source->centre))
      place_panel(c, source, over, chart, rest_faces, given);
    if (given.tips.empty() && !given.centre) {
      if (source)
        pattern_.notes.push_back(over + "no dart or panel seam fits where its mirror image has one");
      else
        pattern_.notes.push_back(over + "no further dart or panel seam fits" +
                                 (refused ? " (a panel seam did not relieve it)"
                                  : sleeve_full(c)
                                      ? " (its sleeve has its most pieces, " + std::to_string(options_.panels.max_sleeve_pieces) +
                                            ": darts only)"
                                  : pieces_ + cost > options_.panels.max_pieces ? " (the pattern has its most pieces)"
                                                                         : ""));
    }
    return given;
  }

  // Darts first (a tailor darts before adding a seam): every tip strong
  // enough at once, up to the piece's budget.
  void place_darts(size_t c, const Given* source, const std::string& over, const Eigen::MatrixXd& chart, Given& given) {
    const PatternPiece& p = pattern_.pieces[c];
    const int left = options_.darts.max_darts - static_cast<int>(p.dart_seams.size());
    if (left <= 0) return;
    // Darts already in the piece and those placed now, as chart polylines:
    // a new dart must not cross one (their curves would cross in a face).
    std::vector<Eigen::MatrixXd> drawn;
    {
      std::map<int, int> local;
      for (int v = 0; v < p.V.rows(); ++v) local[p.mesh_vertex_ids[v]] = v;
      for (int d : p.dart_seams) {
        std::vector<Eigen::Vector2d> pts;
        const auto& ids = pattern_.seams[static_cast<size_t>(d)].vertex_ids;
        for (int v : ids) {
          const auto it = local.find(v);
          if (it != local.end()) pts.push_back(chart.row(it->second).transpose());
        }
        Eigen::MatrixXd P(static_cast<int>(pts.size()), 2);
        for (size_t i = 0; i < pts.size(); ++i) P.row(static_cast<int>(i)) = pts[i].transpose();
        drawn.push_back(P);
      }
    }
    auto add_dart = [&](const DartTip& tip, const std::string& how, const std::string& mirror_of) {
      if (static_cast<int>(given.tips.size()) >= left) return;
      const auto curve = dart_curve(p, chart, tip, options_, drawn);
      if (!curve) return;
      drawn.push_back(curve_positions(chart, p.F, *curve));
      char deg[32];
      std::snprintf(deg, sizeof(deg), "%.1f", tip.curvature * 180.0 / M_PI);
      PatternSeam seam{"dart" + std::to_string(++darts_), "dart", "", {}, false, true, {}};
      pair_mirrors(seam, mirror_of);
      seam.reason = over + how + " (" + deg + " degrees within " + metres(options_.darts.kernel_radius) + "), " +
                    metres(curve_length(p.V, p.F, *curve)) + " long";
      given.tips.push_back(tip);
      given.darts.push_back(seam.name);
      seams_.push_back(seam);
      curves_.push_back(piece_to_mesh(p, *curve));
    };
    const std::string mode = std::string("dart to the mode of its ") +
                             (options_.darts.dart_placement == PatternOptions::DartPlacement::conformal
                                  ? "log conformal factor"
                                  : "Gaussian curvature");
    if (source) {
      for (size_t i = 0; i < source->tips.size(); ++i)
        if (const auto tip = dart_tip_near(pattern_, c, mirror_.reflect(source->tips[i].point), options_.darts.min_dart_angle,
                                           options_))
          add_dart(*tip, "the mirror image of " + source->darts[i], source->darts[i]);
    } else {
      for (const DartTip& tip : dart_tips(pattern_, c, options_, left)) add_dart(tip, mode, "");
    }
  }

  // A panel seam through the piece (a centre seam for a piece across the
  // plane of symmetry), or the mirror image of `source`'s.
  void place_panel(size_t c, const Given* source, const std::string& over, const Eigen::MatrixXd& chart,
                   const std::vector<int>& rest_faces, Given& given) {
    const PatternPiece& p = pattern_.pieces[c];
    std::optional<Eigen::Vector3d> centre =
        source ? std::optional<Eigen::Vector3d>(mirror_.reflect(*source->centre)) : panel_centre(p, options_);
    // A piece across the plane is split as a tailor splits a front or a
    // back: by a centre seam (two mirrored seams were tried; README.md,
    // "Both sides cut alike").
    std::string how;
    if (centre && !source && partner(c) == static_cast<int>(c)) {
      centre = centre_seam_point(p, mirror_.plane_x, *centre);
      how = "centre seam along the grain at the middle of the body, at the height of the centroid of its conformal "
            "distortion energy";
    }
    std::string where;
    std::optional<SurfaceCurve> curve;
    // The centre seam follows the body's middle (the plane section); a
    // straight chart line along the grain where that does not fit.
    if (centre && !how.empty()) {
      curve = centre_seam_curve(pattern_, c, mirror_.plane_x, *centre, options_);
      if (curve) how = "centre seam along the middle of the body (where the plane of symmetry cuts the piece), "
                       "through its point nearest to the centroid of its conformal distortion energy";
    }
    if (!curve && centre) curve = panel_curve(pattern_, c, chart, *centre, options_, &where);
    if (source) where = "the mirror image of " + source->panel;
    if (source && !curve) {
      // No room where the image falls (the two sides of a scanned body
      // differ): the piece's own panel seam, so that both sides are split.
      centre = panel_centre(p, options_);
      curve = centre ? panel_curve(pattern_, c, chart, *centre, options_) : std::nullopt;
      where += ", through its own centroid (the mirrored point leaves no room)";
    }
    if (!curve) return;
    if (!how.empty()) where = how;
    PatternSeam seam{"panel" + std::to_string(++panels_), "panel", "", {}, false, true, {}};
    if (source) pair_mirrors(seam, source->panel);
    seam.reason = over + where + ", " + metres(curve_length(p.V, p.F, *curve)) + " long";
    seams_.push_back(seam);
    curves_.push_back(piece_to_mesh(p, *curve));
    if (ledger_)
      ledger_->trials.push_back(
          {seam.name, rest_faces, panel_excess(material_faces(pattern_, c), options_), p.stats.worst1_compression});
    ++pieces_;
    given.centre = centre;
    given.panel = seam.name;
  }

  Pattern& pattern_;
  const PatternOptions& options_;
  PanelLedger* ledger_;
  std::vector<PatternSeam> seams_;
  std::vector<SurfaceCurve> curves_;
  int darts_ = 0, panels_ = 0;
  PieceMirror mirror_;
  std::vector<int> limb_of_piece_;
  std::map<int, int> limb_pieces_;
  std::vector<char> done_;
  // Pieces given a cut this round (a piece's mirror image that was given
  // none, on its own, still takes the mirror image of the piece's).
  std::vector<char> cut_;
  int pieces_ = 0;
};

}  // namespace

int place_darts_and_panels(Pattern& pattern, const PatternOptions& options, PanelLedger* ledger) {
  return DartPanelPlacer(pattern, options, ledger).run();
}

namespace {

// Takes the seams at `indices` out of the pattern (pieces not reassembled);
// a cut whose mirror image goes loses its pairing.
void erase_seams(Pattern& pattern, std::vector<size_t> indices) {
  std::sort(indices.rbegin(), indices.rend());
  std::set<std::string> gone;
  for (size_t i : indices) {
    gone.insert(pattern.seams[i].name);
    pattern.seams.erase(pattern.seams.begin() + static_cast<long>(i));
  }
  for (PatternSeam& s : pattern.seams)
    if (gone.count(s.mirror)) s.mirror.clear();
}

// Where a panel seam runs on the pattern as it is.
struct PanelSides {
  size_t seam = 0;       // index in pattern.seams
  std::set<int> pieces;  // the pieces on either side: the parts of the piece it split
  double length = 0.0;   // metres
};

std::optional<PanelSides> panel_sides(const Pattern& pattern, const std::string& name) {
  PanelSides j;
  j.seam = pattern.seams.size();
  for (size_t i = 0; i < pattern.seams.size(); ++i)
    if (pattern.seams[i].name == name) j.seam = i;
  if (j.seam >= pattern.seams.size()) return std::nullopt;
  for (const CutEdge& e : pattern.cut.edges)
    if (static_cast<size_t>(e.seam) == j.seam) {
      j.pieces.insert(pattern.piece_of_face[static_cast<size_t>(e.left_face)]);
      j.pieces.insert(pattern.piece_of_face[static_cast<size_t>(e.right_face)]);
      j.length += e.length;
    }
  return j;
}

}  // namespace

int review_panels(Pattern& pattern, const PatternOptions& options, FlattenCache& cache, PanelLedger& ledger) {
  int removed = 0;
  // In the order they were placed, each judged on the pattern as the
  // removals before it left it (a removal changes no other piece); a seam
  // and its mirror image together.
  const std::vector<PanelTrial> trials = std::move(ledger.trials);
  ledger.trials.clear();
  std::set<std::string> judged;
  for (const PanelTrial& first : trials) {
    if (judged.count(first.seam)) continue;
    std::vector<const PanelTrial*> group{&first};
    judged.insert(first.seam);
    const auto j0 = panel_sides(pattern, first.seam);
    if (!j0) continue;
    const std::string& image = pattern.seams[j0->seam].mirror;
    for (const PanelTrial& t : trials)
      if (!image.empty() && t.seam == image && !judged.count(t.seam)) {
        group.push_back(&t);
        judged.insert(t.seam);
      }
    // Judged together: the cloth beyond the limit in the pieces they split
    // against that in all their parts, and their whole length.
    std::vector<PanelSides> js;
    std::set<int> parts;
    double length = 0.0, before = 0.0, compression = 0.0;
    bool tight = false;
    for (const PanelTrial* t : group) {
      const auto j = panel_sides(pattern, t->seam);
      if (!j) continue;
      js.push_back(*j);
      parts.insert(j->pieces.begin(), j->pieces.end());
      length += j->length;
      before += t->excess_before;
      compression = std::max(compression, t->compression_before);
      tight = tight || t->compression_before > options.panels.budget_share * options.panels.stretch_budget;
    }
    double after = 0.0;
    bool within = true;
    for (int c : parts) {
      after += panel_excess(material_faces(pattern, static_cast<size_t>(c)), options);
      within = within && pattern.pieces[static_cast<size_t>(c)].meets_limit;
    }
    const double relief = before - after;
    char buf[220];
    std::snprintf(buf, sizeof(buf), "%.1f of the %s %.1f cm^2 of cloth beyond the limit (%.0f cm^2 per metre of seam)",
                  1e4 * relief, js.size() > 1 ? "two mirrored pieces'" : "piece's", 1e4 * before,
                  length > 0.0 ? 1e4 * relief / length : 0.0);
    // A seam that brings both its pieces within the limit does what the
    // cutter is for, however little cloth that took, where the compression
    // it relieved ate much of the fit's stretch budget.
    // And the cutter stops adding pieces only when the limit is met (issue
    // 49): a seam that took away most of its piece's cloth beyond the limit
    // (min_relief_share) stays, however long, while that piece was over it.
    const bool most = options.panels.min_relief_share > 0.0 && before > 0.0 && relief >= options.panels.min_relief_share * before;
    if (relief >= options.panels.min_panel_relief * length || (within && tight) || most) {
      char budget[180] = "";
      if (relief < options.panels.min_panel_relief * length && within && tight)
        std::snprintf(budget, sizeof(budget),
                      ", and both its pieces meet the limit (the piece was compressed by %.2f %%, more than %.0f %% of "
                      "the stretch budget %.3f)",
                      100.0 * compression, 100.0 * options.panels.budget_share, options.panels.stretch_budget);
      else if (relief < options.panels.min_panel_relief * length)
        std::snprintf(budget, sizeof(budget), ", at least %.0f %% of it (min_relief_share)",
                      100.0 * options.panels.min_relief_share);
      for (const PanelSides& j : js) pattern.seams[j.seam].reason += std::string("; it relieved ") + buf + budget;
      continue;
    }
    Pattern without = pattern;
    std::vector<size_t> gone;
    std::vector<std::string> names;
    for (const PanelSides& j : js) {
      gone.push_back(j.seam);
      names.push_back(pattern.seams[j.seam].name);
    }
    erase_seams(without, gone);
    assemble_pieces(without);
    if (!std::all_of(without.pieces.begin(), without.pieces.end(), [](const PatternPiece& p) { return is_disk(p); }))
      continue;
    flatten_pieces(without, options, cache, true);
    for (const std::string& name : names) {
      without.merged_cuts.push_back(name);
      without.notes.push_back(name + " removed: " + (js.size() > 1 ? "with its mirror image it" : "it") +
                              " relieved only " + buf);
    }
    for (const PanelTrial* t : group) ledger.refused.insert(t->rest_faces);
    pattern = std::move(without);
    removed += static_cast<int>(names.size());
  }
  return removed;
}

void merge_small_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  std::set<std::string> tried;
  for (;;) {
    // The smallest piece below the area bordering an added cut.
    size_t best_seam = pattern.seams.size();
    double best_area = options.panels.min_piece_area;
    for (const CutEdge& e : pattern.cut.edges) {
      const PatternSeam& s = pattern.seams[static_cast<size_t>(e.seam)];
      // User seams and armholes are structure, darts lie inside one piece.
      if (s.kind == "user" || s.kind == "armhole" || s.kind == "dart" || tried.count(s.name)) continue;
      const int l = pattern.piece_of_face[static_cast<size_t>(e.left_face)];
      const int r = pattern.piece_of_face[static_cast<size_t>(e.right_face)];
      if (l == r) continue;
      const double a = std::min(pattern.pieces[static_cast<size_t>(l)].stats.area_3d,
                                pattern.pieces[static_cast<size_t>(r)].stats.area_3d);
      if (a < best_area || (a == best_area && static_cast<size_t>(e.seam) < best_seam))
        best_area = a, best_seam = static_cast<size_t>(e.seam);
    }
    if (best_seam >= pattern.seams.size()) return;
    // The cut goes with its mirror image, as both sides are cut alike.
    std::vector<size_t> gone{best_seam};
    for (size_t i = 0; i < pattern.seams.size(); ++i)
      if (!pattern.seams[best_seam].mirror.empty() && pattern.seams[i].name == pattern.seams[best_seam].mirror)
        gone.push_back(i);
    for (size_t i : gone) tried.insert(pattern.seams[i].name);
    Pattern trial = pattern;
    erase_seams(trial, gone);
    assemble_pieces(trial);
    if (!std::all_of(trial.pieces.begin(), trial.pieces.end(), [](const PatternPiece& p) { return is_disk(p); }))
      continue;
    flatten_pieces(trial, options, cache, true);
    for (size_t i : gone) trial.merged_cuts.push_back(pattern.seams[i].name);
    pattern = std::move(trial);
  }
}

void remove_overlapping_darts(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  auto overlaps = [](const Pattern& x) {
    int n = 0;
    for (const PatternPiece& p : x.pieces) n += p.flat.boundary_overlaps ? 1 : 0;
    return n;
  };
  for (;;) {
    // Of the darts in pieces whose outline overlaps itself, the one whose
    // removal removes an overlap, adds none and leaves the least cloth
    // beyond the limit (panel_excess): with two darts in a piece, the one
    // whose sides crossed, which had too little curvature to take in.
    const int before = overlaps(pattern);
    if (before == 0) return;
    std::optional<Pattern> best;
    double best_excess = std::numeric_limits<double>::infinity();
    std::string best_name;
    for (const PatternPiece& p : pattern.pieces) {
      if (!p.flat.boundary_overlaps) continue;
      for (int d : p.dart_seams) {
        Pattern trial = pattern;
        erase_seams(trial, {static_cast<size_t>(d)});
        assemble_pieces(trial);
        if (!std::all_of(trial.pieces.begin(), trial.pieces.end(), [](const PatternPiece& q) { return is_disk(q); }))
          continue;
        flatten_pieces(trial, options, cache, true);
        if (overlaps(trial) >= before) continue;
        double excess = 0.0;
        for (size_t c = 0; c < trial.pieces.size(); ++c) excess += panel_excess(material_faces(trial, c), options);
        if (excess < best_excess) {
          best_excess = excess;
          best_name = pattern.seams[static_cast<size_t>(d)].name;
          best = std::move(trial);
        }
      }
    }
    if (!best) return;
    best->merged_cuts.push_back(best_name);
    best->notes.push_back(best_name + " removed: its sides crossed in the flat piece, which overlapped itself");
    pattern = std::move(*best);
  }
}

namespace {

// The shortest path through piece p (3D edge lengths, inner vertices only
// between its ends) from outline vertex `from` to an outline vertex whose
// distance round the outline from it lies within `window` of half the
// outline's length (either way), so that the cut parts the outline into
// two runs of about half its length each and so halves its winding;
// nullopt when none runs inside. The path may be a single inner edge
// between two outline vertices (a rung of a narrow strip).
// A piece's vertex graph for its halving cuts: one ring per vertex, and
// which vertices lie on its outline.
struct PieceGraph {
  std::vector<std::vector<int>> neighbors;
  std::vector<char> on_outline;
};

PieceGraph piece_graph(const PatternPiece& p) {
  return {vertex_neighbors(p.F, static_cast<int>(p.V.rows())), boundary_flags(p)};
}

std::optional<SurfaceCurve> halving_cut(const PatternPiece& p, const PieceGraph& graph, int from, double window) {
  const std::vector<int>& loop = p.boundary;
  const size_t nb = loop.size();
  const auto start = std::find(loop.begin(), loop.end(), from);
  if (start == loop.end() || nb < 4) return std::nullopt;
  const size_t i0 = static_cast<size_t>(start - loop.begin());
  std::vector<double> along(nb + 1, 0.0);
  for (size_t k = 0; k < nb; ++k)
    along[k + 1] = along[k] + (p.V.row(loop[(i0 + k) % nb]) - p.V.row(loop[(i0 + k + 1) % nb])).norm();
  const double length = along[nb];
  // The outline vertex nearest half way round is always a target.
  size_t half = 1;
  while (half + 1 < nb && along[half] < 0.5 * length) ++half;
  std::vector<char> is_target(static_cast<size_t>(p.V.rows()), 0);
  is_target[static_cast<size_t>(loop[(i0 + half) % nb])] = 1;
  for (size_t k = 2; window > 0.0 && k + 1 < nb; ++k) {
    if (std::abs(along[k] - 0.5 * length) <= window * length) is_target[static_cast<size_t>(loop[(i0 + k) % nb])] = 1;
  }
  const std::vector<std::vector<int>>& neighbors = graph.neighbors;
  const std::vector<char>& on_outline = graph.on_outline;
  const double inf = std::numeric_limits<double>::infinity();
  GraphSearch<double> search = graph_search(neighbors.size(), inf, true);
  int reached = -1;
  dijkstra(
      neighbors, {from},
      [&](int v, int w) {
        // Onto the outline only at a far end, and never along an outline
        // edge (no cut; the targets are not `from`'s outline neighbours).
        if (on_outline[static_cast<size_t>(w)] && !is_target[static_cast<size_t>(w)]) return inf;
        if (v == from && on_outline[static_cast<size_t>(w)]) {
          const size_t k = static_cast<size_t>(std::find(loop.begin(), loop.end(), w) - loop.begin());
          if (loop[(k + 1) % nb] == v || loop[(k + nb - 1) % nb] == v) return inf;
        }
        return (p.V.row(v) - p.V.row(w)).norm();
      },
      inf,
      [&](int v) {
        if (!is_target[static_cast<size_t>(v)]) return false;
        reached = v;
        return true;
      },
      search);
  if (reached < 0) return std::nullopt;
  SurfaceCurve cut;
  for (int v : trace_parents(search.parent, reached)) cut.push_back(CurvePoint::at_vertex(v));
  if (cut.size() < 2) return std::nullopt;
  return cut;
}

// The shortest of the halving cuts from every outline vertex (within a
// tenth of half way round): where no cut from the crossing runs inside, as
// in a strip that winds past a full turn, whose crossing lies at its ends
// and whose halving cut is a rung near its middle.
std::optional<SurfaceCurve> shortest_halving_cut(const PatternPiece& p, const PieceGraph& graph) {
  std::optional<SurfaceCurve> best;
  double best_length = std::numeric_limits<double>::infinity();
  for (int from : p.boundary) {
    std::optional<SurfaceCurve> cut = halving_cut(p, graph, from, 0.1);
    if (!cut) continue;
    const double length = curve_length(p.V, p.F, *cut);
    if (length < best_length) {
      best_length = length;
      best = std::move(cut);
    }
  }
  return best;
}

}  // namespace

int split_overlapping_pieces(Pattern& pattern, const PatternOptions& options, FlattenCache& cache) {
  int added = 0;
  int panels = 0;
  for (const auto& s : pattern.seams)
    if (s.kind == "panel") ++panels;
  for (const auto& m : pattern.merged_cuts)
    if (m.rfind("panel", 0) == 0) ++panels;
  // Each round splits every piece still overlapping once, then flattens:
  // a piece's two parts are each smaller than the outline that crossed
  // itself, and a part that still overlaps is split again.
  for (int round = 0; round < options.panels.max_overlap_splits; ++round) {
    std::vector<PatternSeam> seams;
    std::vector<SurfaceCurve> curves;
    for (size_t c = 0; c < pattern.pieces.size(); ++c) {
      const PatternPiece& p = pattern.pieces[c];
      if (!p.flat.boundary_overlaps) continue;
      Eigen::MatrixXd chart;
      try {
        chart = conformal_chart(p);
      } catch (const NumericalError&) {
        continue;
      }
      // Through the crossing: the outline vertices there, halfway to the
      // piece's centroid (a grain line through an outline point itself may
      // only graze the piece).
      Eigen::Vector3d at = Eigen::Vector3d::Zero();
      for (int v : p.flat.overlap_vertex_ids) at += p.V.row(v).transpose();
      if (!p.flat.overlap_vertex_ids.empty()) at /= static_cast<double>(p.flat.overlap_vertex_ids.size());
      const Eigen::Vector3d centroid = p.V.colwise().mean().transpose();
      std::string where;
      std::optional<SurfaceCurve> curve;
      for (const Eigen::Vector3d& x : {Eigen::Vector3d(0.5 * (at + centroid)), at, centroid}) {
        curve = panel_curve(pattern, c, chart, x, options, &where);
        if (curve) break;
      }
      // The grain line needs a chart to run straight in, and the chart of a
      // piece that winds past a full turn overlaps too: else the shortest
      // path through the piece from the crossing to the outline point
      // halfway round from it, which halves the outline's winding.
      const PieceGraph graph = curve ? PieceGraph{} : piece_graph(p);
      for (size_t i = 0; !curve && i < p.flat.overlap_vertex_ids.size(); ++i) {
        curve = halving_cut(p, graph, p.flat.overlap_vertex_ids[i], 0.0);
        where = "the shortest path through it from the crossing to the outline point halfway round";
      }
      if (!curve) {
        curve = shortest_halving_cut(p, graph);
        where = "the shortest cut through it that halves its outline";
      }
      if (!curve) continue;
      PatternSeam seam{"panel" + std::to_string(++panels), "panel", "", {}, false, true, {}};
      seam.reason = "piece " + p.name + " overlapped itself in the flat near (" + metres(at.x()) + ", " +
                    metres(at.y()) + ", " + metres(at.z()) + "): " + where + ", " +
                    metres(curve_length(p.V, p.F, *curve)) + " long";
      seams.push_back(seam);
      curves.push_back(piece_to_mesh(p, *curve));
    }
    if (seams.empty()) break;
    added += static_cast<int>(seams.size());
    insert_cuts(pattern, seams, curves);
    flatten_pieces(pattern, options, cache, true);
    while (match_seams(pattern, options, cache)) flatten_pieces(pattern, options, cache, true);
  }
  return added;
}

}  // namespace gp
