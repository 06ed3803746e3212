#include "pattern/export_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "mesh/topology.h"

#include "pattern/svg_writer.h"

namespace gp {
namespace {

std::string g17(double x) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

}  // namespace

std::vector<SeamMeasure> measure_seams(const Pattern& pattern, const Layout& layout, const SeamTolerance& tol) {
  std::vector<SeamMeasure> m(pattern.seams.size());
  std::vector<std::set<int>> left(pattern.seams.size()), right(pattern.seams.size());
  for (const CutEdge& e : pattern.cut.edges) {
    SeamMeasure& s = m[static_cast<size_t>(e.seam)];
    s.length_3d += e.length;
    for (int side = 0; side < 2; ++side) {
      const int face = side == 0 ? e.left_face : e.right_face;
      const int piece = pattern.piece_of_face[static_cast<size_t>(face)];
      const auto& UV = layout.pieces[static_cast<size_t>(piece)].UV;
      const int a = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_a : e.right_a)];
      const int b = pattern.local_vertex[static_cast<size_t>(side == 0 ? e.left_b : e.right_b)];
      (side == 0 ? s.left_2d : s.right_2d) += (UV.row(a) - UV.row(b)).norm();
      (side == 0 ? left : right)[static_cast<size_t>(e.seam)].insert(piece);
    }
  }
  for (size_t i = 0; i < m.size(); ++i) {
    m[i].mismatch = std::abs(m[i].left_2d - m[i].right_2d);
    m[i].ok = m[i].mismatch <= std::max(tol.absolute, tol.relative * m[i].length_3d);
    for (int p : left[i]) m[i].left_pieces.push_back(pattern.pieces[static_cast<size_t>(p)].name);
    for (int p : right[i]) m[i].right_pieces.push_back(pattern.pieces[static_cast<size_t>(p)].name);
  }
  return m;
}

Mesh flat_pieces_mesh(const Pattern& pattern, const Layout& layout) {
  int nv = 0, nf = 0;
  for (const auto& p : pattern.pieces) nv += static_cast<int>(p.V.rows()), nf += static_cast<int>(p.F.rows());
  Mesh mesh;
  mesh.V.setZero(nv, 3);
  mesh.F.resize(nf, 3);
  Eigen::VectorXd piece_field(nv), rest_field(nv), mesh_field(nv);
  int vo = 0, fo = 0;
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const PatternPiece& p = pattern.pieces[i];
    const auto& UV = layout.pieces[i].UV;
    for (int v = 0; v < p.V.rows(); ++v) {
      mesh.V(vo + v, 0) = UV(v, 0);
      mesh.V(vo + v, 1) = UV(v, 1);
      const int m = p.mesh_vertex_ids[v];
      rest_field[vo + v] = m < pattern.mesh.rest_vertex_count ? m : -1;
      mesh_field[vo + v] = m;
      piece_field[vo + v] = static_cast<double>(i);
    }
    for (int f = 0; f < p.F.rows(); ++f) {
      mesh.F.row(fo + f) = p.F.row(f).array() + vo;
    }
    vo += static_cast<int>(p.V.rows());
    fo += static_cast<int>(p.F.rows());
  }
  // Vertex fields only: meshio (the project's check scripts) cannot read
  // PLY face properties besides the vertex index list.
  mesh.vertex_fields.push_back({"piece", piece_field});
  mesh.vertex_fields.push_back({"rest_vertex", rest_field});
  mesh.vertex_fields.push_back({"pattern_vertex", mesh_field});
  return mesh;
}

void write_pieces_obj(std::ostream& out, const Pattern& pattern, const Layout& layout) {
  out << "# export-rest: pattern pieces in 3D (metres), texture coordinates = flat sheet positions (metres)\n";
  int vo = 1;
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const PatternPiece& p = pattern.pieces[i];
    const auto& UV = layout.pieces[i].UV;
    out << "o " << p.name << "\n";
    for (int v = 0; v < p.V.rows(); ++v)
      out << "v " << g17(p.V(v, 0)) << " " << g17(p.V(v, 1)) << " " << g17(p.V(v, 2)) << "\n";
    for (int v = 0; v < p.V.rows(); ++v) out << "vt " << g17(UV(v, 0)) << " " << g17(UV(v, 1)) << "\n";
    for (int f = 0; f < p.F.rows(); ++f) {
      out << "f";
      for (int k = 0; k < 3; ++k) out << " " << p.F(f, k) + vo << "/" << p.F(f, k) + vo;
      out << "\n";
    }
    vo += static_cast<int>(p.V.rows());
  }
}

void write_seams_obj(std::ostream& out, const Pattern& pattern) {
  out << "# export-rest: the seams as polylines on the rest shape (metres)\n";
  int vo = 1;
  for (const PatternSeam& s : pattern.seams) {
    std::string name = s.name;
    std::replace(name.begin(), name.end(), ' ', '_');
    out << "o " << name << "\n";
    for (int v : s.vertex_ids)
      out << "v " << g17(pattern.mesh.V(v, 0)) << " " << g17(pattern.mesh.V(v, 1)) << " " << g17(pattern.mesh.V(v, 2)) << "\n";
    out << "l";
    for (size_t i = 0; i < s.vertex_ids.size(); ++i) out << " " << vo + static_cast<int>(i);
    if (s.closed && !s.vertex_ids.empty()) out << " " << vo;
    out << "\n";
    vo += static_cast<int>(s.vertex_ids.size());
  }
}

Eigen::Vector3d worst_region_centroid(const std::vector<MaterialFace>& faces, double fraction, bool compression,
                                      double radius) {
  std::vector<const MaterialFace*> order;
  double total = 0.0;
  for (const MaterialFace& m : faces) {
    order.push_back(&m);
    total += m.area;
  }
  // Worst first; ties by centroid (deterministic whatever the face order).
  auto value = [compression](const MaterialFace* m) { return compression ? 1.0 - m->stretch[1] : m->stretch[0] - 1.0; };
  std::stable_sort(order.begin(), order.end(),
                   [&](const MaterialFace* a, const MaterialFace* b) { return value(a) > value(b); });
  std::vector<std::pair<const MaterialFace*, double>> region;  // face, its weight
  double taken = 0.0;
  for (const MaterialFace* m : order) {
    const double w = std::min(m->area, fraction * total - taken);
    if (w <= 0.0) break;
    region.emplace_back(m, w);
    taken += w;
  }
  if (!(taken > 0.0)) return Eigen::Vector3d::Zero();
  // The densest spot: the region's face with the most of the region within
  // `radius` (the first such in the worst-first order on ties).
  size_t best = 0;
  double most = -1.0;
  for (size_t i = 0; i < region.size(); ++i) {
    double near = 0.0;
    for (const auto& [m, w] : region)
      if ((m->centroid - region[i].first->centroid).norm() <= radius) near += w;
    if (near > most) most = near, best = i;
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double weight = 0.0;
  for (const auto& [m, w] : region)
    if ((m->centroid - region[best].first->centroid).norm() <= radius) {
      sum += w * m->centroid;
      weight += w;
    }
  return sum / weight;
}

namespace {

// The whole pattern's figures: sums and worsts over its pieces and seams.
OrderedJson pattern_summary(const Pattern& pattern, const Layout& layout, const std::vector<SeamMeasure>& seams) {
  double area_3d = 0.0, area_2d = 0.0, worst_p95 = 0.0, worst_max = 0.0, seam_length = 0.0, added_length = 0.0;
  double worst_compression_p99 = 0.0, worst_compression = 0.0, worst_ease_p95 = 0.0, worst_ease = 0.0;
  double worst_median_ease = 0.0;
  double worst1_compression = 0.0, worst5_ease = 0.0;
  double smallest = std::numeric_limits<double>::infinity();
  int flipped = 0, overlapping = 0, seams_ok = 0, most_darts = 0;
  for (const auto& p : pattern.pieces) {
    const DistortionStats& st = p.stats;
    area_3d += st.area_3d;
    area_2d += st.area_2d;
    worst_p95 = std::max(worst_p95, st.p95_error);
    worst_max = std::max(worst_max, st.max_error);
    worst_compression_p99 = std::max(worst_compression_p99, st.p99_compression);
    worst1_compression = std::max(worst1_compression, st.worst1_compression);
    worst5_ease = std::max(worst5_ease, st.worst5_ease);
    worst_compression = std::max(worst_compression, st.max_compression);
    worst_ease_p95 = std::max(worst_ease_p95, st.p95_stretch);
    worst_median_ease = std::max(worst_median_ease, st.median_ease);
    worst_ease = std::max(worst_ease, st.max_stretch);
    smallest = std::min(smallest, st.area_3d);
    flipped += p.flat.stats.flipped_triangles;
    overlapping += p.flat.boundary_overlaps ? 1 : 0;
    most_darts = std::max(most_darts, static_cast<int>(p.dart_seams.size()));
  }
  int darts = 0;
  for (size_t i = 0; i < seams.size(); ++i) {
    seam_length += seams[i].length_3d;
    if (pattern.seams[i].kind != "user") added_length += seams[i].length_3d;
    if (pattern.seams[i].kind == "dart") ++darts;
    seams_ok += seams[i].ok ? 1 : 0;
  }
  // The garment's own boundary (hems, neck, cuffs): edges of the pattern
  // mesh used by one face.
  double boundary_length = 0.0;
  for (const auto& loop : boundary_loops(pattern.mesh.F))
    for (size_t k = 0; k < loop.size(); ++k)
      boundary_length += (pattern.mesh.V.row(loop[k]) - pattern.mesh.V.row(loop[(k + 1) % loop.size()])).norm();
  return {{"pieces", pattern.pieces.size()},
          {"seams", pattern.seams.size()},
          {"darts", darts},
          {"most_darts_in_a_piece", most_darts},
          {"added_cuts", std::count_if(pattern.seams.begin(), pattern.seams.end(),
                                       [](const PatternSeam& s) { return s.kind != "user"; })},
          {"total_seam_length", seam_length},
          {"added_seam_length", added_length},
          {"user_seam_length", seam_length - added_length},
          {"boundary_length", boundary_length},
          {"smallest_piece_area", pattern.pieces.empty() ? 0.0 : smallest},
          {"area_3d", area_3d},
          {"area_2d", area_2d},
          {"worst_compression", worst1_compression},
          {"worst_ease", worst5_ease},
          {"worst_compression_p99", worst_compression_p99},
          {"worst_compression_max", worst_compression},
          {"worst_ease_p95", worst_ease_p95},
          {"worst_ease_max", worst_ease},
          {"worst_median_ease", worst_median_ease},
          {"worst_p95_error", worst_p95},
          {"worst_max_error", worst_max},
          {"meets_distortion_limit", pattern.meets_limit},
          {"flipped_triangles", flipped},
          {"overlapping_pieces", overlapping},
          {"seams_within_tolerance", seams_ok == static_cast<int>(seams.size())},
          {"seams_matched_1mm", std::count_if(seams.begin(), seams.end(),
                                              [](const SeamMeasure& m) { return m.mismatch <= kSeamMatch; })},
          {"worst_seam_mismatch", std::accumulate(seams.begin(), seams.end(), 0.0,
                                                  [](double w, const SeamMeasure& m) { return std::max(w, m.mismatch); })},
          {"merged_cuts", pattern.merged_cuts.size()},
          {"flatten_rounds", pattern.rounds},
          {"flattenings", pattern.flattenings},
          {"sheet_width", layout.width},
          {"sheet_height", layout.height}};
}

// Which bound each piece exceeds: under the one-sided limit a piece over
// it is over on compression (cloth that the sewn garment must stretch) or
// on ease (cloth to spare), and the two mean different things for the fit.
std::vector<std::string> bounds_exceeded(const PatternPiece& p, const PatternOptions& options) {
  std::vector<std::string> over;
  const DistortionStats& s = p.stats;
  if (options.limit.symmetric) {
    if (s.p95_error > options.limit.p95_limit) over.push_back("p95_error");
    if (s.max_error > options.limit.max_limit) over.push_back("max_error");
  } else {
    if (s.worst1_compression > options.limit.compression_worst1) over.push_back("compression");
    if (s.worst5_ease > options.limit.ease_worst5) over.push_back("ease");
  }
  if (p.flat.stats.flipped_triangles > 0) over.push_back("flips");
  if (p.flat.boundary_overlaps) over.push_back("overlap");
  return over;
}

// Per bound of the limit in force, the names of the pieces over it.
OrderedJson pieces_over_limit(const Pattern& pattern, const PatternOptions& options) {
  OrderedJson over_limit = OrderedJson::object();
  for (const char* b : {"compression", "ease", "p95_error", "max_error", "flips", "overlap"}) {
    if (options.limit.symmetric ? (std::string(b) == "compression" || std::string(b) == "ease")
                          : (std::string(b) == "p95_error" || std::string(b) == "max_error"))
      continue;
    over_limit[b] = OrderedJson::array();
  }
  for (const PatternPiece& p : pattern.pieces)
    for (const std::string& b : bounds_exceeded(p, options)) over_limit[b].push_back(p.name);
  return over_limit;
}

// Piece i: its size, distortion, where it is worst, and its place on the sheet.
OrderedJson piece_json(const Pattern& pattern, const Layout& layout, const PatternOptions& options, size_t i) {
  const PatternPiece& p = pattern.pieces[i];
  const DistortionStats& s = p.stats;
  const LaidOutPiece& lp = layout.pieces[i];
  std::vector<std::string> darts_here;
  for (int d : p.dart_seams) darts_here.push_back(pattern.seams[static_cast<size_t>(d)].name);
  // Where the piece is most compressed and most eased: where a dart or a
  // seam would go.
  const std::vector<MaterialFace> faces = material_faces(pattern, i);
  auto at = [](const Eigen::Vector3d& x) { return OrderedJson::array({x.x(), x.y(), x.z()}); };
  const OrderedJson worst_at = {{"compression_worst1_m", at(worst_region_centroid(faces, 0.01, true, options.darts.kernel_radius))},
                                {"ease_worst5_m", at(worst_region_centroid(faces, 0.05, false, options.darts.kernel_radius))}};
  return {{"name", p.name},
          {"vertices", p.V.rows()},
          {"faces", p.F.rows()},
          {"area_3d", s.area_3d},
          {"area_2d", s.area_2d},
          {"outline_length", polygon_perimeter(lp.outline)},
          {"cutting_line_length", lp.allowance.empty() ? 0.0 : polygon_perimeter(lp.allowance.front())},
          {"darts", darts_here},
          {"distortion",
           {{"compression_worst1", s.worst1_compression},
            {"ease_worst5", s.worst5_ease},
            {"p99_compression", s.p99_compression},
            {"max_compression", s.max_compression},
            {"p95_ease", s.p95_stretch},
            {"max_ease", s.max_stretch},
            {"p95_error", s.p95_error},
            {"max_error", s.max_error},
            {"mean_error", s.mean_error},
            {"p95_compression", s.p95_compression},
            {"median_ease", s.median_ease},
            {"median_compression", s.median_compression}}},
          {"meets_limit", p.meets_limit},
          {"over_limit", bounds_exceeded(p, options)},
          {"worst_at", worst_at},
          {"flipped_triangles", p.flat.stats.flipped_triangles},
          {"boundary_overlaps", p.flat.boundary_overlaps},
          {"initialization", p.flat.initialization},
          {"arap_iterations", p.flat.iterations},
          {"rotation_rad", lp.rotation},
          {"grain", lp.grain_from_body_vertical ? "body vertical" : "longest axis"}};
}

// Each notch pair of a seam: its label, the 3D arc length, the flat arc on
// each side and their difference (what a sewer matching the notches eases in).
OrderedJson notch_pairs(const Layout& layout, size_t seam) {
  OrderedJson pairs = OrderedJson::array();
  std::map<std::string, std::pair<const Notch*, const Notch*>> by_label;
  std::vector<std::string> order;
  for (const Notch& n : layout.notches) {
    if (n.seam != static_cast<int>(seam)) continue;
    auto& pr = by_label[n.label];
    if (!pr.first && !pr.second) order.push_back(n.label);
    (n.side == 0 ? pr.first : pr.second) = &n;
  }
  for (const std::string& label : order) {
    const auto& [l, r] = by_label[label];
    OrderedJson p = {{"label", label}, {"arc_3d", (l ? l : r)->arc}};
    p["left_flat_arc"] = l ? OrderedJson(l->flat_arc) : OrderedJson();
    p["right_flat_arc"] = r ? OrderedJson(r->flat_arc) : OrderedJson();
    p["difference"] = l && r ? OrderedJson(std::abs(l->flat_arc - r->flat_arc)) : OrderedJson();
    pairs.push_back(p);
  }
  return pairs;
}

// Seam i: its lengths on each side, their mismatch, its notches and ends.
OrderedJson seam_json(const Pattern& pattern, const Layout& layout, const SeamMeasure& m, size_t i) {
  auto point = [&](int v) {
    OrderedJson xyz = OrderedJson::array();
    for (int k = 0; k < 3; ++k) xyz.push_back(pattern.mesh.V(v, k));
    return xyz;
  };
  const PatternSeam& s = pattern.seams[i];
  int notches = 0;
  for (const auto& n : layout.notches)
    if (n.seam == static_cast<int>(i)) ++notches;
  return {{"name", s.name},
          {"kind", s.kind},
          {"length_3d", m.length_3d},
          {"left", {{"pieces", m.left_pieces}, {"length_2d", m.left_2d}}},
          {"right", {{"pieces", m.right_pieces}, {"length_2d", m.right_2d}}},
          {"mismatch", m.mismatch},
          {"mismatch_relative", m.length_3d > 0.0 ? m.mismatch / m.length_3d : 0.0},
          {"within_tolerance", m.ok},
          {"matched_1mm", m.mismatch <= kSeamMatch},
          {"intended_ease", 0.0},
          {"notches", notches},
          {"notch_pairs", notch_pairs(layout, i)},
          {"smoothed", s.smoothed},
          {"from", point(s.vertex_ids.front())},
          {"to", point(s.closed ? s.vertex_ids.front() : s.vertex_ids.back())}};
}

// The cuts the cutter added (not the user's seams), with their reasons.
OrderedJson added_cuts(const Pattern& pattern, const std::vector<SeamMeasure>& seams) {
  OrderedJson added = OrderedJson::array();
  for (size_t i = 0; i < pattern.seams.size(); ++i)
    if (pattern.seams[i].kind != "user")
      added.push_back({{"name", pattern.seams[i].name},
                       {"kind", pattern.seams[i].kind},
                       {"length_3d", seams[i].length_3d},
                       {"mirror", pattern.seams[i].mirror.empty() ? OrderedJson() : OrderedJson(pattern.seams[i].mirror)},
                       {"reason", pattern.seams[i].reason}});
  return added;
}

OrderedJson limit_json(const PatternOptions& options) {
  if (options.limit.symmetric)
    return {{"kind", "symmetric"}, {"p95_error", options.limit.p95_limit}, {"max_error", options.limit.max_limit}};
  return {{"kind", "one-sided"},
          {"compression_worst1", options.limit.compression_worst1},
          {"ease_worst5", options.limit.ease_worst5}};
}

}  // namespace

OrderedJson pattern_report(const Pattern& pattern, const Layout& layout, const PatternOptions& options,
                           const SeamTolerance& tol) {
  OrderedJson j;
  const std::vector<SeamMeasure> seams = measure_seams(pattern, layout, tol);
  j["summary"] = pattern_summary(pattern, layout, seams);
  j["summary"]["pieces_over_limit"] = pieces_over_limit(pattern, options);
  OrderedJson pieces = OrderedJson::array();
  for (size_t i = 0; i < pattern.pieces.size(); ++i) pieces.push_back(piece_json(pattern, layout, options, i));
  j["pieces"] = pieces;
  OrderedJson seam_list = OrderedJson::array();
  for (size_t i = 0; i < seams.size(); ++i) seam_list.push_back(seam_json(pattern, layout, seams[i], i));
  j["seams"] = seam_list;
  j["added_cuts"] = added_cuts(pattern, seams);
  j["merged_cuts"] = pattern.merged_cuts;
  j["notes"] = pattern.notes;
  j["summary"]["limit"] = limit_json(options);
  return j;
}

}  // namespace gp
