#include "pattern/layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/math.h"
#include "pattern/piece_names.h"

namespace gp {
namespace {

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Direction of the warp on the flat piece: the area-weighted gradient, on the
// flat triangles, of the rest height y (the body's vertical, the warp of a
// face on the straight grain), turned by the face's grain angle where its
// rest face has one (`grain_angles` per pattern-mesh face, empty: none), as
// the cloth model turns it (cloth::warp_direction: counter-clockwise about
// the face normal, which a flat triangle of positive area keeps).
Eigen::Vector2d grain_direction(const PatternPiece& p, const std::vector<double>& grain_angles, bool& from_vertical,
                                double& mean_turn) {
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  double area = 0.0, turn = 0.0;
  for (int f = 0; f < p.F.rows(); ++f) {
    const Eigen::Vector2d a = p.flat.UV.row(p.F(f, 0)), b = p.flat.UV.row(p.F(f, 1)), c = p.flat.UV.row(p.F(f, 2));
    Eigen::Matrix2d E;
    E.col(0) = b - a;
    E.col(1) = c - a;
    const double det = E.determinant();
    if (!(det > 0.0)) continue;
    const Eigen::Vector2d dh(p.V(p.F(f, 1), 1) - p.V(p.F(f, 0), 1), p.V(p.F(f, 2), 1) - p.V(p.F(f, 0), 1));
    // Skipped at 0 so that a pattern on the straight grain is what it was, bit for bit.
    const double angle = grain_angles.empty() ? 0.0 : grain_angles[static_cast<size_t>(p.face_ids[static_cast<size_t>(f)])];
    if (angle == 0.0) {
      g += 0.5 * det * E.transpose().inverse() * dh;
    } else {
      const Eigen::Vector2d gf = E.transpose().inverse() * dh;
      const double cs = gp::math::cos(angle), sn = gp::math::sin(angle);
      g += 0.5 * det * Eigen::Vector2d(cs * gf.x() - sn * gf.y(), sn * gf.x() + cs * gf.y());
      turn += 0.5 * det * angle;
    }
    area += 0.5 * det;
  }
  mean_turn = area > 0.0 ? turn / area : 0.0;
  if (area > 0.0 && g.norm() > 0.3 * area) {
    from_vertical = true;
    return g.normalized();
  }
  // A horizontal piece (a hat's crown): grain along its longest axis.
  from_vertical = false;
  const Eigen::Vector2d mean = p.flat.UV.colwise().mean();
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (int v = 0; v < p.flat.UV.rows(); ++v) {
    const Eigen::Vector2d d = p.flat.UV.row(v).transpose() - mean;
    C += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
  Eigen::Vector2d axis = eig.eigenvectors().col(1);
  // A deterministic sign.
  if (axis.y() < 0.0 || (axis.y() == 0.0 && axis.x() < 0.0)) axis = -axis;
  return axis;
}

// The outline with every dart bridged at its mouth: the cutting line of a
// tailor's pattern runs across a dart (which is folded and sewn, not cut
// out). A dart shows in the boundary loop as a run
//   m, ..., a, tip, b, ..., m'
// whose entries at equal distances before and after the tip are copies of
// the same rest vertex; it is replaced by the segment m -> m'. Repeated until
// no dart is left (a dart branching off another dart is bridged first).
Polygon2 bridged_outline(const std::vector<int>& loop, const Eigen::VectorXi& rest_ids, const Eigen::MatrixXd& UV) {
  std::vector<int> ids = loop;
  bool changed = true;
  while (changed && ids.size() > 3) {
    changed = false;
    const int n = static_cast<int>(ids.size());
    auto rest = [&](int i) { return rest_ids[ids[static_cast<size_t>(((i % n) + n) % n)]]; };
    for (int i = 0; i < n && !changed; ++i) {
      if (rest(i - 1) != rest(i + 1) || rest(i) == rest(i + 1)) continue;
      int k = 1;
      while (k + 1 < n / 2 && rest(i - k - 1) == rest(i + k + 1)) ++k;
      // Drop the entries strictly between i - k and i + k, and the copy at i + k.
      std::vector<char> drop(static_cast<size_t>(n), 0);
      for (int d = -k + 1; d <= k; ++d) drop[static_cast<size_t>(((i + d) % n + n) % n)] = 1;
      std::vector<int> kept;
      for (int j = 0; j < n; ++j)
        if (!drop[static_cast<size_t>(j)]) kept.push_back(ids[static_cast<size_t>(j)]);
      if (kept.size() < 3) break;
      ids = kept;
      changed = true;
    }
  }
  Polygon2 out;
  for (int v : ids) out.push_back(UV.row(v).transpose());
  return out;
}

bool overlaps(const Box2& a, const Box2& b) {
  return a.lo.x() < b.hi.x() && b.lo.x() < a.hi.x() && a.lo.y() < b.hi.y() && b.lo.y() < a.hi.y();
}

}  // namespace

PieceLabel piece_label(const LaidOutPiece& piece, const std::string& title, const std::string& name,
                       const CutInstruction& cut) {
  PieceLabel l;
  l.line1 = title + " " + name;
  std::string grain = piece.grain_from_body_vertical ? "vertical" : "along the piece";
  // A turned grain (a bias cut): the line drawn is the warp, at this angle to the body's vertical.
  // (A piece holding only slivers of a turned region, where a seam smooths
  // across its border, keeps "vertical": under half a degree.)
  if (piece.grain_from_body_vertical && std::abs(piece.grain_turn) * 180.0 / 3.14159265358979323846 >= 0.5) {
    char turned[64];
    std::snprintf(turned, sizeof(turned), "at %.0f deg to the vertical", piece.grain_turn * 180.0 / 3.14159265358979323846);
    grain = turned;
  }
  l.line2 = cut.text() + ", grain " + grain;
  const double room = 2.0 * 0.8 * piece.label_room;  // usable width across the disc
  const double w1 = 0.6 * static_cast<double>(l.line1.size()), w2 = 0.6 * static_cast<double>(l.line2.size());
  l.size1 = std::max(0.001, std::min({0.01, piece.label_room / 4.0, room / w1}));
  l.size2 = std::max(0.0008, std::min(0.6 * l.size1, room / w2));
  l.line1_at = piece.label_at + Eigen::Vector2d(0.0, 0.2 * l.size1);
  l.line2_at = piece.label_at - Eigen::Vector2d(0.0, 1.2 * l.size2);
  const double half = 0.5 * std::max(w1 * l.size1, w2 * l.size2);
  l.box.lo = piece.label_at + Eigen::Vector2d(-half, -1.5 * l.size2);
  l.box.hi = piece.label_at + Eigen::Vector2d(half, 1.1 * l.size1);
  return l;
}

Box2 seam_label_box(const Eigen::Vector2d& at, size_t characters) {
  // 3 mm text centred on `at`.
  const double width = 0.6 * 0.003 * static_cast<double>(characters);
  Box2 b;
  b.lo = at - Eigen::Vector2d(0.5 * width, 0.0005);
  b.hi = at + Eigen::Vector2d(0.5 * width, 0.003);
  return b;
}

namespace {

// The grain of every pattern-mesh face: its rest face's (empty: none given).
std::vector<double> pattern_face_grain(const Pattern& pattern, const std::vector<double>& rest_grain_angles) {
  std::vector<double> grain_angles;
  if (rest_grain_angles.empty()) return grain_angles;
  if (rest_grain_angles.size() != static_cast<size_t>(pattern.mesh.rest_F.rows()))
    throw UsageError("grain angles must be one per rest face (" + std::to_string(rest_grain_angles.size()) + " for " +
                     std::to_string(pattern.mesh.rest_F.rows()) + ")");
  grain_angles.resize(pattern.mesh.rest_face.size());
  for (size_t f = 0; f < grain_angles.size(); ++f)
    grain_angles[f] = rest_grain_angles[static_cast<size_t>(pattern.mesh.rest_face[f])];
  return grain_angles;
}

// Piece i turned so that its grain runs along +y, its outline and seam
// allowance; lo and hi: the bounding box of both.
LaidOutPiece orient_piece(const PatternPiece& p, const LayoutOptions& options, const std::vector<double>& grain_angles,
                          Eigen::Vector2d& lo, Eigen::Vector2d& hi) {
  LaidOutPiece out;
  const Eigen::Vector2d g = grain_direction(p, grain_angles, out.grain_from_body_vertical, out.grain_turn);
  // Rotate g onto +y.
  out.rotation = gp::math::atan2(g.x(), g.y());
  Eigen::Matrix2d R;
  R << gp::math::cos(out.rotation), -gp::math::sin(out.rotation), gp::math::sin(out.rotation), gp::math::cos(out.rotation);
  out.UV = p.flat.UV * R.transpose();
  for (int v : p.boundary) out.outline.push_back(out.UV.row(v).transpose());
  const std::string what = "piece " + p.name;
  if (options.seam_allowance > 0.0)
    out.allowance = offset_polygon(bridged_outline(p.boundary, p.mesh_vertex_ids, out.UV), options.seam_allowance,
                                   options.simplify_tolerance, what);
  lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const auto& q : out.outline) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  for (const auto& poly : out.allowance)
    for (const auto& q : poly) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  return out;
}

// Shelf packing, tallest groups first (ties by piece order), where a
// group is a piece or a mirrored pair ("left X" and "right X"), laid side
// by side: the body's right first, as a tailor sees the garment from the front.
// Returns each piece's shift; sets the layout's width and height.
std::vector<Eigen::Vector2d> shelf_pack(const Pattern& pattern, const LayoutOptions& options,
                                        const std::vector<Eigen::Vector2d>& lo, const std::vector<Eigen::Vector2d>& hi,
                                        Layout& layout) {
  const size_t count = pattern.pieces.size();
  std::vector<std::vector<size_t>> groups;
  std::vector<char> grouped(count, 0);
  for (size_t i = 0; i < count; ++i) {
    if (grouped[i]) continue;
    grouped[i] = 1;
    std::vector<size_t> g{i};
    const std::string mirrored = mirror_name(pattern.pieces[i].name);
    if (mirrored != pattern.pieces[i].name)
      for (size_t j = 0; j < count; ++j)
        if (!grouped[j] && pattern.pieces[j].name == mirrored) {
          grouped[j] = 1;
          g.push_back(j);
          break;
        }
    if (g.size() == 2 && is_left(pattern.pieces[g[0]].name)) std::swap(g[0], g[1]);
    groups.push_back(g);
  }
  auto height = [&](const std::vector<size_t>& g) {
    double h = 0.0;
    for (size_t i : g) h = std::max(h, hi[i].y() - lo[i].y());
    return h;
  };
  std::stable_sort(groups.begin(), groups.end(),
                   [&](const std::vector<size_t>& a, const std::vector<size_t>& b) { return height(a) > height(b); });
  std::vector<size_t> order;
  for (const auto& g : groups) order.insert(order.end(), g.begin(), g.end());
  double x = options.margin, y = options.margin, row_height = 0.0, width = 0.0;
  std::vector<Eigen::Vector2d> shift(count);
  for (size_t k = 0; k < order.size(); ++k) {
    const size_t i = order[k];
    Eigen::Vector2d size = hi[i] - lo[i];
    // A pair starts a new shelf when both do not fit on this one.
    double need = size.x();
    for (const auto& g : groups)
      if (g.size() == 2 && g[0] == i) need += options.gap + (hi[g[1]] - lo[g[1]]).x();
    if (x > options.margin && x + need > options.sheet_width - options.margin) {
      x = options.margin;
      y += row_height + options.gap;
      row_height = 0.0;
    }
    shift[i] = Eigen::Vector2d(x, y) - lo[i];
    x += size.x() + options.gap;
    width = std::max(width, x - options.gap + options.margin);
    row_height = std::max(row_height, size.y());
  }
  layout.width = std::max(width, 2.0 * options.margin);
  layout.height = y + row_height + options.margin;
  return shift;
}

// The piece moved by `shift`, with its label and grain line around the
// vertex deepest inside the outline: a disc of radius `label_room` around it
// lies inside the piece.
void place_piece(const PatternPiece& p, const Eigen::Vector2d& shift, LaidOutPiece& out) {
  out.UV.rowwise() += shift.transpose();
  for (auto& q : out.outline) q += shift;
  for (auto& poly : out.allowance)
    for (auto& q : poly) q += shift;
  int best = p.boundary.front();
  double best_d = -1.0;
  for (int v = 0; v < out.UV.rows(); ++v) {
    const Eigen::Vector2d q = out.UV.row(v);
    double d = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < out.outline.size() && d > best_d; ++k)
      d = std::min(d, segment_distance(q, out.outline[k], out.outline[(k + 1) % out.outline.size()]));
    if (d > best_d) best_d = d, best = v;
  }
  out.label_at = out.UV.row(best);
  out.label_room = std::max(best_d, 0.0);
  const double half = 0.8 * out.label_room;
  out.grain_from = out.label_at - Eigen::Vector2d(0.0, half);
  out.grain_to = out.label_at + Eigen::Vector2d(0.0, half);
}

// The notches of seam s at the 3D arc lengths `at` (both sides of every cut
// edge of it), its label candidates at the middle, a third and two thirds of
// [start, end], and a dart's mouth and tip (mark.piece stays -1 otherwise).
void seam_points(const Pattern& pattern, const LayoutOptions& options, size_t s, double start, double end,
                 const std::vector<double>& at, Layout& layout, std::vector<SeamLabel> (&candidates)[3],
                 DartMark& mark) {
  const bool dart = pattern.seams[s].kind == "dart";
  const double label_at[3] = {0.5, 1.0 / 3.0, 2.0 / 3.0};
  for (const CutEdge& e : pattern.cut.edges) {
    if (e.seam != static_cast<int>(s)) continue;
    for (int side = 0; side < 2; ++side) {
      const int face = side == 0 ? e.left_face : e.right_face;
      const int piece = pattern.piece_of_face[static_cast<size_t>(face)];
      const LaidOutPiece& lp = layout.pieces[static_cast<size_t>(piece)];
      const int a = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_a : e.right_a)];
      const int b = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_b : e.right_b)];
      const Eigen::Vector2d pa = lp.UV.row(a), pb = lp.UV.row(b);
      // The face lies left of a -> b on the left side and left of b -> a on
      // the right side; outward is to the right of the face's direction.
      const Eigen::Vector2d d = side == 0 ? Eigen::Vector2d(pb - pa) : Eigen::Vector2d(pa - pb);
      Eigen::Vector2d outward(d.y(), -d.x());
      if (outward.norm() > 0.0) outward.normalize();
      const double e0 = e.arc_start, e1 = e.arc_start + e.length;
      for (double s_at : at) {
        const bool inside = (s_at >= e0 && s_at < e1) || (s_at == end && e1 == end);
        if (!inside) continue;
        const double t = e.length > 0.0 ? (s_at - e0) / e.length : 0.0;
        const Eigen::Vector2d q = pa + t * (pb - pa);
        layout.notches.push_back({static_cast<int>(s), piece, q, outward, q + options.notch_length * outward, s_at, side, "", 0.0});
      }
      for (int c = 0; c < 3; ++c) {
        const double m = start + label_at[c] * (end - start);
        if (m >= e0 && m < e1) {
          const double t = e.length > 0.0 ? (m - e0) / e.length : 0.0;
          candidates[c].push_back({static_cast<int>(s), piece, side, pa + t * (pb - pa) - 0.008 * outward});
        }
      }
      if (dart) {
        mark.seam = static_cast<int>(s);
        mark.piece = piece;
        if (e.arc_start == start) (side == 0 ? mark.mouth_left : mark.mouth_right) = pa;
        if (e1 >= end) mark.tip = pb;
      }
    }
  }
}

// Labels and flat arc lengths of seam s's notches: the k-th notch point
// along the seam on both sides; the flat arc summed over the side's flat
// edges up to it.
void name_notches(const Pattern& pattern, size_t s, const std::vector<double>& at, Layout& layout) {
  for (Notch& n : layout.notches) {
    if (n.seam != static_cast<int>(s)) continue;
    const size_t k = static_cast<size_t>(std::lower_bound(at.begin(), at.end(), n.arc) - at.begin());
    n.label = pattern.seams[s].name + " " + std::to_string(k + 1);
    double flat = 0.0;
    for (const CutEdge& e : pattern.cut.edges) {
      if (e.seam != static_cast<int>(s) || e.arc_start >= n.arc) continue;
      const int face = n.side == 0 ? e.left_face : e.right_face;
      const LaidOutPiece& lp = layout.pieces[static_cast<size_t>(pattern.piece_of_face[static_cast<size_t>(face)])];
      const int a = pattern.local_vertex[static_cast<size_t>(n.side == 0 ? e.left_a : e.right_a)];
      const int b = pattern.local_vertex[static_cast<size_t>(n.side == 0 ? e.left_b : e.right_b)];
      const double len = (lp.UV.row(a) - lp.UV.row(b)).norm();
      const double t = e.length > 0.0 ? std::min(1.0, (n.arc - e.arc_start) / e.length) : 1.0;
      flat += t * len;
    }
    n.flat_arc = flat;
  }
}

// Notches, drill hole and labels of seam s (3D arc lengths [start, end]).
// Seam labels are placed at the middle of their seam, else at a third or two
// thirds of it, wherever their text box overlaps no box in `taken` (other
// labels, the pieces' own); a seam whose label fits nowhere has none.
void mark_seam(const Pattern& pattern, const LayoutOptions& options, size_t s, double start, double end,
               std::vector<Box2>& taken, Layout& layout) {
  const bool dart = pattern.seams[s].kind == "dart";
  std::vector<double> at;
  if (dart) {
    at.push_back(start);  // a dart is notched at its mouth only; its tip gets a drill hole
  } else {
    for (double a = start; a < end - 0.25 * options.notch_spacing; a += options.notch_spacing) at.push_back(a);
    at.push_back(end);
  }
  std::vector<SeamLabel> candidates[3];
  DartMark mark;
  seam_points(pattern, options, s, start, end, at, layout, candidates, mark);
  name_notches(pattern, s, at, layout);
  if (dart && mark.piece >= 0) {
    // The drill hole: a centimetre short of the tip, on the fold line.
    const Eigen::Vector2d mouth = 0.5 * (mark.mouth_left + mark.mouth_right);
    const Eigen::Vector2d along = mark.tip - mouth;
    const double length = along.norm();
    mark.drill = length > 0.02 ? Eigen::Vector2d(mark.tip - 0.01 * along / length) : Eigen::Vector2d(mark.tip);
    layout.darts.push_back(mark);
  }
  // One label per side of the seam, each at the first place that is free.
  for (int side = 0; side < 2; ++side)
    for (int c = 0; c < 3; ++c) {
      const auto it = std::find_if(candidates[c].begin(), candidates[c].end(),
                                   [&](const SeamLabel& l) { return l.side == side; });
      if (it == candidates[c].end()) continue;
      const Box2 box = seam_label_box(it->at, pattern.seams[s].name.size());
      if (std::any_of(taken.begin(), taken.end(), [&](const Box2& o) { return overlaps(box, o); })) continue;
      taken.push_back(box);
      layout.seam_labels.push_back(*it);
      break;
    }
}

}  // namespace

Layout layout_pattern(const Pattern& pattern, const LayoutOptions& options, const std::vector<double>& rest_grain_angles) {
  Layout layout;
  const std::vector<double> grain_angles = pattern_face_grain(pattern, rest_grain_angles);
  const size_t count = pattern.pieces.size();
  layout.pieces.resize(count);
  std::vector<Eigen::Vector2d> lo(count), hi(count);
  for (size_t i = 0; i < count; ++i) layout.pieces[i] = orient_piece(pattern.pieces[i], options, grain_angles, lo[i], hi[i]);
  const std::vector<Eigen::Vector2d> shift = shelf_pack(pattern, options, lo, hi, layout);
  for (size_t i = 0; i < count; ++i) place_piece(pattern.pieces[i], shift[i], layout.pieces[i]);

  // Notches and seam labels, from the cut edges: both sides of an edge are
  // the same material edge, so a notch at 3D arc length s lies at the same
  // point of the seam on both partners.
  std::vector<double> seam_length(pattern.seams.size(), 0.0);
  for (const CutEdge& e : pattern.cut.edges)
    seam_length[static_cast<size_t>(e.seam)] = std::max(seam_length[static_cast<size_t>(e.seam)], e.arc_start + e.length);
  std::vector<double> seam_start(pattern.seams.size(), std::numeric_limits<double>::infinity());
  for (const CutEdge& e : pattern.cut.edges)
    seam_start[static_cast<size_t>(e.seam)] = std::min(seam_start[static_cast<size_t>(e.seam)], e.arc_start);
  std::vector<Box2> taken;
  const std::vector<CutInstruction> cut = cut_instructions(pattern);
  for (size_t i = 0; i < count; ++i)
    taken.push_back(piece_label(layout.pieces[i], options.title, pattern.pieces[i].name, cut[i]).box);
  for (size_t s = 0; s < pattern.seams.size(); ++s) {
    if (!(seam_length[s] > seam_start[s])) continue;
    mark_seam(pattern, options, s, seam_start[s], seam_length[s], taken, layout);
  }
  return layout;
}

}  // namespace gp
