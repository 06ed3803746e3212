#include "garment/make_garment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/stopwatch.h"
#include "garment/surface_path.h"
#include "garment/surface_point.h"
#include "mesh/graph_paths.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {


// CGAL splits above 4/3 and collapses below 4/5 of its target; its edges come
// out somewhat short on average, so it is aimed a little above the target.
constexpr double kCgalLengthFactor = 1.03;
int resolve_vertex(const SpecPoint& p, const Eigen::MatrixXd& V, const SurfaceLocator& body,
                   double snap_tolerance) {
  if (p.is_vertex) {
    if (p.vertex_id >= V.rows())
      throw SpecError("body vertex id " + std::to_string(p.vertex_id) + " is out of range [0, " +
                          std::to_string(V.rows()) + ")",
                      p.where);
    return static_cast<int>(p.vertex_id);
  }
  const SurfaceLocator::Hit hit = body.closest(p.point);
  if (hit.distance > snap_tolerance)
    throw SpecError("point is " + std::to_string(hit.distance) + " m from the body, more than the snap "
                        "tolerance of " + std::to_string(snap_tolerance) + " m",
                    p.where);
  int k = 0;
  hit.at.bary.maxCoeff(&k);
  return body.F()(hit.at.face, k);
}

// Closest point of the closed polyline P (#P by 3) to x: segment i from P[i]
// to P[i+1], parameter t in [0, 1].
struct PolylinePoint {
  int segment = 0;
  double t = 0.0;
  double distance = std::numeric_limits<double>::infinity();
};
PolylinePoint closest_on_polyline(const Eigen::Vector3d& x, const Eigen::MatrixXd& P) {
  PolylinePoint best;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d a = P.row(i), b = P.row((i + 1) % P.rows());
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    const double d = (a + t * ab - x).norm();
    if (d < best.distance) best = {static_cast<int>(i), t, d};
  }
  return best;
}

// The cut region's boundary on the offset (curves: closed polylines, one per
// cut curve), its vertices there in V_cut and marked in cut_fixed: curve
// points follow the binding rule of garment_file.h.
void offset_cut_boundary(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body, const Eigen::MatrixXd& N_body,
                         const RegionCut& cut, double offset, Eigen::MatrixXd& V_cut, std::vector<char>& cut_fixed,
                         std::vector<Eigen::MatrixXd>& curves) {
  for (size_t k = 0; k < cut.curves.size(); ++k) {
    const auto& segments = cut.curves[k].segments;
    const auto& ids = cut.boundary_vertex_ids[k];
    Eigen::MatrixXd P(static_cast<Eigen::Index>(segments.size()), 3);
    for (size_t i = 0; i < segments.size(); ++i) {
      const Eigen::Vector3d x = evaluate_binding(V_body, N_body, F_body, {segments[i].face, segments[i].bary_start}, offset);
      P.row(static_cast<Eigen::Index>(i)) = x.transpose();
      V_cut.row(ids[i]) = x.transpose();
      cut_fixed[ids[i]] = 1;
    }
    curves.push_back(P);
  }
}

// The body vertices whose outer (fillet) surface points are needed: those
// within three times offset + fillet of the cut region; empty without fillet.
std::vector<char> near_cut_region(const Eigen::MatrixXd& V_body, const RegionCut& cut, const GarmentSpec& spec) {
  std::vector<char> near;
  if (!(spec.offset_fillet > 0)) return near;
  near.assign(static_cast<size_t>(V_body.rows()), 0);
  const SurfaceLocator cut_surface(cut.V, cut.F);
  const double reach = 3.0 * (spec.offset + spec.offset_fillet);
  for (Eigen::Index v = 0; v < V_body.rows(); ++v)
    near[static_cast<size_t>(v)] = cut_surface.closest(V_body.row(v).transpose()).distance <= reach;
  return near;
}

// Resolution: for a near-equilateral mesh of N vertices (about 2N
// triangles of area sqrt(3)/4 L^2) on area A, L = sqrt(2 A / (sqrt(3) N)).
// A requested vertex count is met by one correction of L from the first
// result, since N scales with 1 / L^2. Sets result.target_edge_length.
void remesh_to_resolution(const Eigen::MatrixXd& V_cut, const GarmentSpec& spec, const std::vector<Eigen::MatrixXd>& curves,
                          const OffsetSurface& surface, MakeGarmentResult& result, Eigen::MatrixXd& V,
                          Eigen::MatrixXi& F) {
  double offset_area = face_areas(V_cut, result.cut.F).sum();
  result.target_edge_length =
      spec.edge_length > 0 ? spec.edge_length
                           : std::sqrt(2.0 * offset_area / (std::sqrt(3.0) * static_cast<double>(spec.vertex_count)));
  RemeshOptions remesh = spec.remesh;
  const PointProjection project_to_offset_surface = [&](const Eigen::Vector3d& x) { return surface.project(x); };
  for (int pass = 0; pass < (spec.edge_length > 0 ? 1 : 2); ++pass) {
    if (pass == 1)
      result.target_edge_length *= std::sqrt(static_cast<double>(V.rows()) / static_cast<double>(spec.vertex_count));
    V = V_cut;
    F = result.cut.F;
    remesh.target_edge_length = kCgalLengthFactor * result.target_edge_length;
    // The first of two passes only measures the vertex count.
    remesh.iterations = pass == 0 && spec.edge_length <= 0 ? std::min(3, spec.remesh.iterations) : spec.remesh.iterations;
    remesh_patch(V, F, curves, remesh, project_to_offset_surface);
  }
}

// Matches each garment boundary to its curve (the closest one) and binds its
// vertices to the body point of the curve under them (moved there, marked in
// on_boundary).
void bind_boundaries(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body, const Eigen::MatrixXd& N_body,
                     const GarmentSpec& spec, const std::vector<std::vector<int>>& boundaries,
                     const std::vector<Eigen::MatrixXd>& curves, MakeGarmentResult& result, Eigen::MatrixXd& V,
                     std::vector<char>& on_boundary) {
  GarmentFile& file = result.file;
  file.loops.resize(spec.loops.size());
  std::vector<char> taken(spec.loops.size(), 0);
  for (const auto& boundary : boundaries) {
    const Eigen::Vector3d x = V.row(boundary.front());
    size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < curves.size(); ++k) {
      const double d = closest_on_polyline(x, curves[k]).distance;
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    if (taken[best])
      throw GeometryError("two garment boundaries follow loop '" + spec.loops[best].name + "'",
                          spec.loops[best].where);
    taken[best] = 1;
    GarmentLoop& loop = file.loops[best];
    loop.name = spec.loops[best].name;
    loop.pinned = spec.loops[best].pinned;
    loop.vertex_ids = boundary;
    const auto& segments = result.cut.curves[best].segments;
    for (int v : boundary) {
      const PolylinePoint at = closest_on_polyline(V.row(v).transpose(), curves[best]);
      result.boundary_curve_error = std::max(result.boundary_curve_error, at.distance);
      const CurveSegment& s = segments[static_cast<size_t>(at.segment)];
      const SurfacePoint bound{s.face, (1.0 - at.t) * s.bary_start + at.t * s.bary_end};
      loop.binding.push_back(bound);
      V.row(v) = evaluate_binding(V_body, N_body, F_body, bound, spec.offset).transpose();
      on_boundary[v] = 1;
    }
    for (const auto& s : segments) loop.curve.push_back({s.face, s.bary_start});
  }
}

// The garment faces (V, F) in a paint or grain region, by the body point
// under each face's centroid.
std::vector<char> faces_in(const PaintRegion& region, const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                           const SurfaceLocator& body, const std::vector<std::vector<int>>& neighbors,
                           const GarmentSpec& spec, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<double> dist;
  std::set<long long> vertex_set;
  if (region.is_disc) {
    const int center = resolve_vertex(region.center, V_body, body, spec.snap_tolerance);
    // The geodesic disc of the region: distances along body edges.
    dist.assign(static_cast<size_t>(V_body.rows()), std::numeric_limits<double>::infinity());
    std::vector<int> reached;
    edge_distances(V_body, neighbors, {center}, 1.5 * region.radius, dist, reached);
  } else {
    for (long long v : region.vertex_ids) {
      if (v >= V_body.rows())
        throw SpecError("body vertex id " + std::to_string(v) + " is out of range", region.where + "/vertices");
      vertex_set.insert(v);
    }
  }
  std::vector<char> inside(static_cast<size_t>(F.rows()), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
    const SurfacePoint at = body.closest(c).at;
    bool in = false;
    if (region.is_disc) {
      double d = 0.0;
      for (int k = 0; k < 3; ++k) d += at.bary[k] * dist[F_body(at.face, k)];
      in = d <= region.radius;
    } else {
      int k = 0;
      at.bary.maxCoeff(&k);
      in = vertex_set.count(F_body(at.face, k)) > 0;
    }
    inside[static_cast<size_t>(f)] = in ? 1 : 0;
  }
  return inside;
}

// T3: paint factors per garment triangle, and the grain per face (common/
// garment/README.md, "Grain"; none without grain regions, so that such a
// garment's file is what it was), and a knit's negative ease: the rest shape
// starts smaller in every direction by 1 + ease, through the paint (an area
// factor, applied at the first adaptation); the fit grows it back only where
// a pose needs more than the knit's limits give.
void paint_and_grain(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body, const SurfaceLocator& body,
                     const std::vector<std::vector<int>>& neighbors, const GarmentSpec& spec, const Eigen::MatrixXd& V,
                     const Eigen::MatrixXi& F, GarmentFile& file) {
  auto region_faces = [&](const PaintRegion& region) {
    return faces_in(region, V_body, F_body, body, neighbors, spec, V, F);
  };
  file.paint.assign(static_cast<size_t>(F.rows()), 1.0);
  for (const auto& region : spec.paint) {
    const std::vector<char> inside = region_faces(region);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      if (inside[static_cast<size_t>(f)]) file.paint[static_cast<size_t>(f)] *= region.factor;
  }
  if (!spec.grain.empty()) {
    file.material.grain_angles.assign(static_cast<size_t>(F.rows()), 0.0);
    for (const auto& region : spec.grain) {
      const std::vector<char> inside = region_faces(region.on);
      for (Eigen::Index f = 0; f < F.rows(); ++f)
        if (inside[static_cast<size_t>(f)]) file.material.grain_angles[static_cast<size_t>(f)] = region.angle;
    }
  }
  if (spec.ease < 0.0) {
    for (double& p : file.paint) p *= (1.0 + spec.ease) * (1.0 + spec.ease);
  }
  file.ease = spec.ease;
}

}  // namespace

MakeGarmentResult make_garment(const Eigen::MatrixXd& V_body, const Eigen::MatrixXi& F_body,
                               const GarmentSpec& spec) {
  if (V_body.rows() == 0 || F_body.rows() == 0) throw GeometryError("the body mesh is empty");
  if (!V_body.allFinite()) throw GeometryError("the body mesh has non-finite coordinates");
  if (F_body.minCoeff() < 0 || F_body.maxCoeff() >= V_body.rows())
    throw GeometryError("the body mesh has face indices out of range");

  MakeGarmentResult result;
  auto t0 = Clock::now();
  const SurfaceLocator body(V_body, F_body);
  const auto neighbors = vertex_neighbors(F_body, static_cast<int>(V_body.rows()));

  // T1: clicks -> closed edge paths.
  std::vector<LoopPath> paths;
  for (const auto& loop : spec.loops) {
    std::vector<int> clicks;
    for (const auto& p : loop.points) clicks.push_back(resolve_vertex(p, V_body, body, spec.snap_tolerance));
    paths.push_back({loop.name, closed_edge_path(V_body, neighbors, clicks, loop.where + "/points"),
                     loop.where});
  }
  const int region_vertex = resolve_vertex(spec.region, V_body, body, spec.snap_tolerance);
  result.timing["paths"] = seconds_since(t0);

  // T1: smoothed curves and the exact cut.
  t0 = Clock::now();
  result.cut = cut_region(V_body, F_body, paths, region_vertex, spec.region.where, spec.smoothing);
  result.timing["cut"] = seconds_since(t0);

  // T4 first: the cut region is pushed off the body before remeshing, so that
  // the even triangles are made on the offset surface (on a forearm a 1.5 cm
  // offset would otherwise stretch them by 40 %). Curve points follow the
  // binding rule of garment_file.h, interior points the offset surface.
  t0 = Clock::now();
  const Eigen::MatrixXd N_body = vertex_normals(V_body, F_body);
  Eigen::MatrixXd V_cut = result.cut.V;
  std::vector<char> cut_fixed(static_cast<size_t>(V_cut.rows()), 0);
  std::vector<Eigen::MatrixXd> curves;  // offset curves, closed polylines
  offset_cut_boundary(V_body, F_body, N_body, result.cut, spec.offset, V_cut, cut_fixed, curves);
  // The target surface: the offset surface with its creases rounded, so that
  // the body inside a pinch (an armpit) keeps an image, in order, instead of
  // collapsing onto the crease. Every cut vertex goes to the point over it.
  ComfortOffsetOptions offset_options;
  offset_options.offset = spec.offset;
  // The outer surface of the fillet is needed near the cut region only.
  const std::vector<char> near = near_cut_region(V_body, result.cut, spec);
  const OffsetSurface surface(body, N_body, spec.offset, spec.offset_fillet, offset_options, near);
  if (spec.offset_fillet > 0) {
    for (Eigen::Index v = 0; v < V_cut.rows(); ++v)
      if (!cut_fixed[static_cast<size_t>(v)]) V_cut.row(v) = surface.project(V_cut.row(v).transpose()).transpose();
  } else {
    apply_comfort_offset(V_cut, body, N_body, offset_options, cut_fixed);
  }
  result.timing["offset_region"] = seconds_since(t0);

  t0 = Clock::now();
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  remesh_to_resolution(V_cut, spec, curves, surface, result, V, F);
  result.timing["remesh"] = seconds_since(t0);

  t0 = Clock::now();
  const auto boundaries = boundary_loops(F);
  result.boundary_loop_count = static_cast<int>(boundaries.size());
  result.euler_characteristic = euler_characteristic(F);
  Eigen::VectorXi component;
  result.component_count = face_components(F, component);
  if (boundaries.size() != spec.loops.size())
    throw GeometryError("the remeshed garment has " + std::to_string(boundaries.size()) +
                            " boundary loops instead of " + std::to_string(spec.loops.size()) +
                            "; loops are too close together for the target resolution",
                        spec.file + ": /resolution");
  GarmentFile& file = result.file;
  file.name = spec.name;
  std::vector<char> on_boundary(static_cast<size_t>(V.rows()), 0);
  bind_boundaries(V_body, F_body, N_body, spec, boundaries, curves, result, V, on_boundary);
  paint_and_grain(V_body, F_body, body, neighbors, spec, V, F, file);
  result.timing["bind_paint"] = seconds_since(t0);

  // Remeshing moved interior vertices on the dense offset surface; they are
  // put exactly on it from where they are (on the exact surface: by
  // closest-point corrections). Boundary vertices start at their
  // binding-rule position and get the same projection: in concave places
  // (armpits) the normal offset of the rule can come closer to another body
  // part than the offset; the deviation from the rule is reported.
  t0 = Clock::now();
  Eigen::MatrixXd V_rule = V;
  if (spec.offset_fillet > 0) {
    for (Eigen::Index v = 0; v < V.rows(); ++v) V.row(v) = surface.project(V.row(v).transpose()).transpose();
    result.offset_error = measure_offset(V, body, spec.offset);
  } else {
    offset_options.start_along_normal = false;
    result.offset_error = apply_comfort_offset(V, body, N_body, offset_options);
  }
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (on_boundary[static_cast<size_t>(v)])
      result.binding_max_deviation = std::max(result.binding_max_deviation, (V.row(v) - V_rule.row(v)).norm());
  // The offset keeps every vertex outside the body; triangles between them
  // can still cut a convex body part or a crease (and in a pinch no position
  // has the full offset): cleared of the body, bound boundary vertices held.
  BodyClearanceOptions clearance;
  clearance.offset = spec.offset;
  clearance.improve_clear = false;
  result.clearance = clear_body(V, F, V_body, F_body, on_boundary, clearance);
  result.quality = measure_quality(V, F, result.target_edge_length);
  result.timing["offset"] = seconds_since(t0);

  file.target_edge_length = result.target_edge_length;
  file.offset = spec.offset;
  std::vector<double> grain_angles = std::move(file.material.grain_angles);
  file.material = spec.material;
  file.material.grain_angles = std::move(grain_angles);
  file.vertex_count = V.rows();
  file.face_count = F.rows();
  result.mesh.V = V;
  result.mesh.F = F;
  // Paint lives in the garment file only: meshio (used by the check scripts)
  // cannot read binary PLY faces that carry extra properties.
  return result;
}

}  // namespace gp
