#include "pattern/layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/math.h"

namespace gp {
namespace {

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Direction of the body's vertical on the flat piece: the area-weighted
// gradient, on the flat triangles, of the rest height y.
Eigen::Vector2d grain_direction(const PatternPiece& p, bool& from_vertical) {
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  double area = 0.0;
  for (int f = 0; f < p.F.rows(); ++f) {
    const Eigen::Vector2d a = p.flat.UV.row(p.F(f, 0)), b = p.flat.UV.row(p.F(f, 1)), c = p.flat.UV.row(p.F(f, 2));
    Eigen::Matrix2d E;
    E.col(0) = b - a;
    E.col(1) = c - a;
    const double det = E.determinant();
    if (!(det > 0.0)) continue;
    const Eigen::Vector2d dh(p.V(p.F(f, 1), 1) - p.V(p.F(f, 0), 1), p.V(p.F(f, 2), 1) - p.V(p.F(f, 0), 1));
    g += 0.5 * det * E.transpose().inverse() * dh;
    area += 0.5 * det;
  }
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

}  // namespace

Layout layout_pattern(const Pattern& pattern, const LayoutOptions& options) {
  Layout layout;
  const size_t count = pattern.pieces.size();
  layout.pieces.resize(count);
  std::vector<Eigen::Vector2d> lo(count), hi(count);
  for (size_t i = 0; i < count; ++i) {
    const PatternPiece& p = pattern.pieces[i];
    LaidOutPiece& out = layout.pieces[i];
    const Eigen::Vector2d g = grain_direction(p, out.grain_from_body_vertical);
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
    lo[i] = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    hi[i] = -lo[i];
    for (const auto& q : out.outline) lo[i] = lo[i].cwiseMin(q), hi[i] = hi[i].cwiseMax(q);
    for (const auto& poly : out.allowance)
      for (const auto& q : poly) lo[i] = lo[i].cwiseMin(q), hi[i] = hi[i].cwiseMax(q);
  }

  // Shelf packing, tallest pieces first (ties by piece order).
  std::vector<size_t> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return (hi[a].y() - lo[a].y()) > (hi[b].y() - lo[b].y());
  });
  double x = options.margin, y = options.margin, row_height = 0.0, width = 0.0;
  std::vector<Eigen::Vector2d> shift(count);
  for (size_t i : order) {
    const Eigen::Vector2d size = hi[i] - lo[i];
    if (x > options.margin && x + size.x() > options.sheet_width - options.margin) {
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

  for (size_t i = 0; i < count; ++i) {
    const PatternPiece& p = pattern.pieces[i];
    LaidOutPiece& out = layout.pieces[i];
    out.UV.rowwise() += shift[i].transpose();
    for (auto& q : out.outline) q += shift[i];
    for (auto& poly : out.allowance)
      for (auto& q : poly) q += shift[i];
    // Label and grain line around the vertex deepest inside the outline: a
    // disc of radius `label_room` around it lies inside the piece.
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

  // Notches and seam labels, from the cut edges: both sides of an edge are
  // the same material edge, so a notch at 3D arc length s lies at the same
  // point of the seam on both partners.
  std::vector<double> seam_length(pattern.seams.size(), 0.0);
  for (const CutEdge& e : pattern.cut.edges)
    seam_length[static_cast<size_t>(e.seam)] = std::max(seam_length[static_cast<size_t>(e.seam)], e.arc_start + e.length);
  std::vector<double> seam_start(pattern.seams.size(), std::numeric_limits<double>::infinity());
  for (const CutEdge& e : pattern.cut.edges)
    seam_start[static_cast<size_t>(e.seam)] = std::min(seam_start[static_cast<size_t>(e.seam)], e.arc_start);
  for (size_t s = 0; s < pattern.seams.size(); ++s) {
    const double start = seam_start[s], end = seam_length[s];
    if (!(end > start)) continue;
    std::vector<double> at;
    for (double a = start; a < end - 0.25 * options.notch_spacing; a += options.notch_spacing) at.push_back(a);
    at.push_back(end);
    const double middle = 0.5 * (start + end);
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
          layout.notches.push_back({static_cast<int>(s), piece, q, outward, q + options.notch_length * outward, s_at, side});
        }
        if (middle >= e0 && middle < e1) {
          const double t = e.length > 0.0 ? (middle - e0) / e.length : 0.0;
          layout.seam_labels.push_back({static_cast<int>(s), piece, side, pa + t * (pb - pa) - 0.008 * outward});
        }
      }
    }
  }
  return layout;
}

}  // namespace gp
