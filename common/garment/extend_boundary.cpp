#include "garment/extend_boundary.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Geometry>

#include "collision/contact_surface.h"
#include "collision/crossings.h"
#include "core/error.h"
#include "garment/remesh.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {

// Arc-length parameters in [0, 1) of the vertices of the closed polyline P.
std::vector<double> arc_parameters(const Eigen::MatrixXd& P, double& length) {
  std::vector<double> u(static_cast<size_t>(P.rows()), 0.0);
  length = 0.0;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    u[static_cast<size_t>(i)] = length;
    length += (P.row((i + 1) % P.rows()) - P.row(i)).norm();
  }
  for (double& x : u) x /= length;
  return u;
}

// Point at arc-length parameter s in [0, 1] of the closed polyline P.
Eigen::Vector3d point_at(const Eigen::MatrixXd& P, const std::vector<double>& u, double s) {
  const Eigen::Index n = P.rows();
  s -= std::floor(s);
  size_t i = static_cast<size_t>(std::upper_bound(u.begin(), u.end(), s) - u.begin()) - 1;
  const double u0 = u[i], u1 = i + 1 < u.size() ? u[i + 1] : 1.0;
  const double t = u1 > u0 ? (s - u0) / (u1 - u0) : 0.0;
  const Eigen::Index a = static_cast<Eigen::Index>(i), b = (a + 1) % n;
  return ((1.0 - t) * P.row(a) + t * P.row(b)).transpose();
}

double polygon_length(const std::vector<Eigen::Vector3d>& Q) {
  double length = 0.0;
  for (size_t i = 0; i < Q.size(); ++i) length += (Q[(i + 1) % Q.size()] - Q[i]).norm();
  return length;
}

}  // namespace

ExtendSpec parse_extend_spec(const Json& j, const std::string& file) {
  check_schema(j, "extend-spec", {1}, file);
  const SpecObject root(j, file);
  root.allow("schema");
  ExtendSpec s;
  s.file = file;
  s.loop = root.required_string("loop");
  const SpecObject target = root.object("target");
  const bool by_point = target.has("point"), by_distance = target.has("distance");
  if (by_point == by_distance) throw SpecError("give exactly one of 'point' and 'distance'", target.where());
  if (by_point) {
    const auto p = target.numbers("point", 3);
    s.has_point = true;
    s.point = {p[0], p[1], p[2]};
  } else {
    const Json* d = target.raw("distance");
    if (!d->is_number()) throw SpecError("expected a number", target.where("distance"));
    s.distance = d->get<double>();
    if (!(s.distance > 0))
      throw SpecError("the distance along the loop axis must be positive (a target behind the loop "
                      "would fold the band back over the garment)",
                      target.where("distance"));
  }
  target.finish();
  if (root.has("scale") && root.has("girth"))
    throw SpecError("give at most one of 'scale' and 'girth'", root.where("girth"));
  if (root.has("scale")) {
    const Json* v = root.raw("scale");
    if (!v->is_number()) throw SpecError("expected a number", root.where("scale"));
    s.scale = v->get<double>();
    if (!(s.scale > 0) || !std::isfinite(s.scale))
      throw SpecError("the scale must be positive (a zero scale collapses the loop)", root.where("scale"));
  }
  if (root.has("girth")) s.girth = root.required_number("girth", Range::between(1e-3, 100.0));
  // The band's grain, degrees from the body's vertical as the garment
  // spec's "grain" (a bias-cut skirt: 45).
  if (root.has("grain")) s.grain_angle = root.required_number("grain", Range::between(-90.0, 90.0)) * kRadiansPerDegree;
  if (const auto remesh = root.optional_object("remesh")) {
    s.remesh_iterations = static_cast<int>(remesh->integer("iterations", s.remesh_iterations, Range::between(1, 50)));
    remesh->finish();
  }
  root.finish();
  return s;
}

ExtendSpec read_extend_spec(const std::filesystem::path& path) {
  return parse_extend_spec(read_json_file(path), path.string());
}

OrderedJson to_json(const ExtendSpec& s) {
  OrderedJson j;
  j["schema"] = schema_tag("extend-spec", 1);
  j["loop"] = s.loop;
  if (s.has_point) j["target"] = {{"point", {s.point[0], s.point[1], s.point[2]}}};
  else j["target"] = {{"distance", s.distance}};
  if (s.girth > 0) j["girth"] = s.girth;
  else j["scale"] = s.scale;
  if (s.grain_angle != 0.0) j["grain"] = s.grain_angle / kRadiansPerDegree;
  j["remesh"] = {{"iterations", s.remesh_iterations}};
  return j;
}

namespace {

// The loop's centroid (arc-length weighted) and axis: the vector area
// (1/2 sum p_i x p_{i+1} about the centroid), as in the paper's extension
// tool, pointed away from the garment (from the ring of inner neighbours of
// the loop towards the loop). P: the loop's points, old_length its length.
void loop_axis(const Mesh& garment, const GarmentLoop& loop, const Eigen::MatrixXd& P, double old_length,
               const ExtendSpec& spec, Eigen::Vector3d& centroid, Eigen::Vector3d& axis) {
  const Eigen::Index m = P.rows();
  centroid = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < m; ++i) {
    const double w = (P.row((i + 1) % m) - P.row(i)).norm();
    centroid += 0.5 * w * (P.row(i) + P.row((i + 1) % m)).transpose();
  }
  centroid /= old_length;
  Eigen::Vector3d area = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < m; ++i)
    area += 0.5 * Eigen::Vector3d(P.row(i).transpose() - centroid)
                      .cross(Eigen::Vector3d(P.row((i + 1) % m).transpose() - centroid));
  if (!(area.norm() > 1e-6 * old_length * old_length))
    throw GeometryError("loop '" + spec.loop + "' encloses no area, so it has no axis to extend along",
                        spec.file + ": /loop");
  axis = area.normalized();
  const auto neighbors = vertex_neighbors(garment.F, static_cast<int>(garment.V.rows()));
  const std::set<int> on_loop(loop.vertex_ids.begin(), loop.vertex_ids.end());
  Eigen::Vector3d inner = Eigen::Vector3d::Zero();
  int inner_count = 0;
  for (int v : loop.vertex_ids)
    for (int w : neighbors[v])
      if (!on_loop.count(w)) {
        inner += garment.V.row(w).transpose();
        ++inner_count;
      }
  if (inner_count > 0 && (centroid - inner / inner_count).dot(axis) < 0) axis = -axis;
}

// Zips consecutive rings (vertex ids and arc-length parameters) by parameter;
// the garment runs along the old loop in its boundary direction, so the band
// runs against it.
std::vector<Eigen::Vector3i> zip_rings(const std::vector<std::vector<int>>& ring_ids,
                                       const std::vector<std::vector<double>>& ring_u) {
  std::vector<Eigen::Vector3i> band;
  const int rows = static_cast<int>(ring_ids.size()) - 1;
  for (int r = 0; r < rows; ++r) {
    const auto &A = ring_ids[static_cast<size_t>(r)], &B = ring_ids[static_cast<size_t>(r + 1)];
    const auto &ua = ring_u[static_cast<size_t>(r)], &ub = ring_u[static_cast<size_t>(r + 1)];
    const size_t na = A.size(), nb = B.size();
    size_t i = 0, j = 0;
    while (i < na || j < nb) {
      const double a_next = i + 1 < na ? ua[i + 1] : 1.0, b_next = j + 1 < nb ? ub[j + 1] : 1.0;
      if (j == nb || (i < na && a_next <= b_next)) {
        band.push_back({A[(i + 1) % na], A[i % na], B[j % nb]});
        ++i;
      } else {
        band.push_back({A[i % na], B[j % nb], B[(j + 1) % nb]});
        ++j;
      }
    }
  }
  return band;
}

// The band may pass through the body (a skirt cone through the hips or the
// hands): pushed clear of it, bound loops held (new_id: the remeshed id of
// each vertex before the remeshing, -1).
void clear_of_body(const DesignBody& body, const GarmentFile& file, int loop_index, const std::vector<int>& new_id,
                   Eigen::MatrixXd& V, const Eigen::MatrixXi& F, ExtendResult& result) {
  std::vector<char> fixed(static_cast<size_t>(V.rows()), 0);
  for (size_t k = 0; k < file.loops.size(); ++k) {
    if (static_cast<int>(k) == loop_index || file.loops[k].binding.empty()) continue;
    for (int v : file.loops[k].vertex_ids) {
      const int moved_id = new_id[static_cast<size_t>(v)];
      if (moved_id >= 0) fixed[static_cast<size_t>(moved_id)] = 1;
    }
  }
  BodyClearanceOptions clearance;
  clearance.offset = file.offset;
  result.clearance = clear_body(V, F, body.V, body.F, fixed, clearance);
  // Then of the hand hulls the simulation collides with (contact_surface.h),
  // which its intersection-free contact needs the garment to start outside
  // of. After the body, since a hull and the hand under it are two parts
  // for clear_body, which could send them to two sides.
  const collision::ContactSurface surface = collision::contact_surface(body.V, body.F);
  const Eigen::MatrixXd V_surface = surface.positions(body.V);
  if (surface.hull_count > 0 && result.clearance.clear() &&
      !collision::find_crossings(V_surface, surface.F, V, F).intersection_free()) {
    result.clearance = clear_body(V, F, V_surface, surface.F, fixed, clearance);
  }
}

// Band faces come after the garment's nF faces, which keep their order: how
// many of them have a normal that faces the axis.
int inward_band_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Eigen::Index nF,
                      const Eigen::Vector3d& centroid, const Eigen::Vector3d& axis) {
  const Eigen::MatrixXd N = face_normals(V, F);
  int flipped = 0;
  for (Eigen::Index f = nF; f < F.rows(); ++f) {
    const Eigen::Vector3d c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
    Eigen::Vector3d radial = c - centroid;
    radial -= radial.dot(axis) * axis;
    if (N.row(f).dot(radial) <= 0) ++flipped;
  }
  return flipped;
}

}  // namespace

ExtendResult extend_boundary(const Mesh& garment, const GarmentFile& file, const ExtendSpec& spec,
                             const DesignBody* body) {
  const int loop_index = file.find_loop(spec.loop);
  if (loop_index < 0) throw SpecError("the garment has no loop called '" + spec.loop + "'", spec.file + ": /loop");
  if (garment.V.rows() != file.vertex_count || garment.F.rows() != file.face_count)
    throw InputError("the garment mesh does not match its garment file (vertex or face count differs)");
  const GarmentLoop& loop = file.loops[static_cast<size_t>(loop_index)];
  const double L = file.target_edge_length;
  const Eigen::Index nG = garment.V.rows();

  ExtendResult result;
  const Eigen::Index m = static_cast<Eigen::Index>(loop.vertex_ids.size());
  Eigen::MatrixXd P(m, 3);
  for (Eigen::Index i = 0; i < m; ++i) P.row(i) = garment.V.row(loop.vertex_ids[static_cast<size_t>(i)]);

  double old_length = 0.0;
  const std::vector<double> u_old = arc_parameters(P, old_length);
  Eigen::Vector3d centroid, axis;
  loop_axis(garment, loop, P, old_length, spec, centroid, axis);

  double distance = spec.distance;
  if (spec.has_point) {
    distance = (spec.point - centroid).dot(axis);
    if (!(distance > 1e-6))
      throw SpecError("the target point lies " + std::to_string(-distance) +
                          " m behind loop '" + spec.loop + "' (the axis points away from the garment)",
                      spec.file + ": /target/point");
  }
  double scale = spec.girth > 0 ? spec.girth / old_length : spec.scale;

  // The new loop: the old one moved and scaled, resampled at the garment's
  // edge length; for a girth target its length is then made exact.
  const Eigen::Vector3d new_centroid = centroid + distance * axis;
  const int n_new = std::max(3, static_cast<int>(std::lround(scale * old_length / L)));
  auto new_curve = [&](double s) {
    return Eigen::Vector3d(new_centroid + scale * (point_at(P, u_old, s) - centroid));
  };
  std::vector<Eigen::Vector3d> Q(static_cast<size_t>(n_new));
  for (int j = 0; j < n_new; ++j) Q[static_cast<size_t>(j)] = new_curve(static_cast<double>(j) / n_new);
  if (spec.girth > 0) {
    const double correction = spec.girth / polygon_length(Q);
    scale *= correction;
    for (int j = 0; j < n_new; ++j) Q[static_cast<size_t>(j)] = new_curve(static_cast<double>(j) / n_new);
  }

  // Rings between the loops at about the edge length; ring r blends the old
  // and the new loop at the same arc-length parameter.
  double gap = 0.0;
  for (int j = 0; j < 16; ++j) gap += (new_curve(j / 16.0) - point_at(P, u_old, j / 16.0)).norm() / 16.0;
  const int rows = std::max(1, static_cast<int>(std::lround(gap / L)));
  std::vector<Eigen::Vector3d> added;
  std::vector<std::vector<int>> ring_ids(static_cast<size_t>(rows + 1));
  std::vector<std::vector<double>> ring_u(static_cast<size_t>(rows + 1));
  ring_ids[0] = loop.vertex_ids;
  ring_u[0] = u_old;
  for (int r = 1; r <= rows; ++r) {
    const double w = static_cast<double>(r) / rows;
    const int count = r == rows ? n_new : std::max(3, static_cast<int>(std::lround((1 - w) * m + w * n_new)));
    for (int j = 0; j < count; ++j) {
      const double s = static_cast<double>(j) / count;
      const Eigen::Vector3d x = r == rows ? Q[static_cast<size_t>(j)]
                                          : Eigen::Vector3d((1 - w) * point_at(P, u_old, s) + w * new_curve(s));
      ring_ids[static_cast<size_t>(r)].push_back(static_cast<int>(nG + static_cast<Eigen::Index>(added.size())));
      ring_u[static_cast<size_t>(r)].push_back(s);
      added.push_back(x);
    }
  }
  const std::vector<Eigen::Vector3i> band = zip_rings(ring_ids, ring_u);

  Eigen::MatrixXd V(nG + static_cast<Eigen::Index>(added.size()), 3);
  V.topRows(nG) = garment.V;
  for (size_t i = 0; i < added.size(); ++i) V.row(nG + static_cast<Eigen::Index>(i)) = added[i].transpose();
  const Eigen::Index nF = garment.F.rows();
  Eigen::MatrixXi F(nF + static_cast<Eigen::Index>(band.size()), 3);
  F.topRows(nF) = garment.F;
  for (size_t i = 0; i < band.size(); ++i) F.row(nF + static_cast<Eigen::Index>(i)) = band[i].transpose();
  std::vector<char> selected(static_cast<size_t>(F.rows()), 0);
  std::fill(selected.begin() + nF, selected.end(), 1);
  // Each face's garment face before the band (-1: a band face), carried
  // through the remeshing, so that paint and grain follow their faces.
  Eigen::VectorXd face_origin(F.rows());
  for (Eigen::Index f = 0; f < nF; ++f) face_origin[f] = static_cast<double>(f);
  face_origin.tail(static_cast<Eigen::Index>(band.size())).setConstant(-1.0);

  RemeshOptions remesh;
  remesh.target_edge_length = L;
  remesh.iterations = spec.remesh_iterations;
  const std::vector<int> origin = remesh_selected_faces(V, F, selected, remesh, face_origin, -1.0);
  Eigen::VectorXd paint = Eigen::VectorXd::Ones(F.rows());
  const bool painted = file.paint.size() == static_cast<size_t>(nF);
  const bool grained = file.material.grain_angles.size() == static_cast<size_t>(nF);
  std::vector<double> grain;
  if (grained || spec.grain_angle != 0.0) grain.assign(static_cast<size_t>(F.rows()), spec.grain_angle);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const long old = std::lround(face_origin[f]);
    if (old < 0) continue;  // a band face: the extension's grain
    if (painted) paint[f] = file.paint[static_cast<size_t>(old)];
    if (!grain.empty()) grain[static_cast<size_t>(f)] = grained ? file.material.grain_angles[static_cast<size_t>(old)] : 0.0;
  }
  std::vector<int> new_id(static_cast<size_t>(nG + static_cast<Eigen::Index>(added.size())), -1);
  for (size_t i = 0; i < origin.size(); ++i)
    if (origin[i] >= 0) new_id[static_cast<size_t>(origin[i])] = static_cast<int>(i);

  if (body) {
    clear_of_body(*body, file, loop_index, new_id, V, F, result);
    result.body_checked = true;
  }

  result.band_faces = static_cast<int>(F.rows() - nF);
  result.band_flipped_faces = inward_band_faces(V, F, nF, centroid, axis);

  GarmentFile out = file;
  for (auto& l : out.loops)
    for (int& v : l.vertex_ids) v = new_id[static_cast<size_t>(v)];
  GarmentLoop& extended = out.loops[static_cast<size_t>(loop_index)];
  extended.vertex_ids.clear();
  const std::set<int> new_loop(ring_ids.back().begin(), ring_ids.back().end());
  for (const auto& boundary : boundary_loops(F)) {
    if (boundary.empty() || origin[static_cast<size_t>(boundary.front())] < 0 ||
        !new_loop.count(origin[static_cast<size_t>(boundary.front())]))
      continue;
    extended.vertex_ids = boundary;
  }
  if (extended.vertex_ids.empty()) throw GeometryError("the extended loop was lost in remeshing", spec.file + ": /loop");
  extended.binding.clear();
  extended.curve.clear();
  result.unpinned = extended.pinned;
  extended.pinned = false;
  out.vertex_count = V.rows();
  out.face_count = F.rows();
  out.paint.assign(paint.data(), paint.data() + paint.size());
  out.material.grain_angles = grain;

  result.centroid = centroid;
  result.axis = axis;
  result.distance = distance;
  result.scale = scale;
  result.old_girth = old_length;
  std::vector<Eigen::Vector3d> final_loop;
  for (int v : extended.vertex_ids) final_loop.push_back(V.row(v).transpose());
  result.new_girth = polygon_length(final_loop);
  out.extensions.push_back({spec.loop, distance, scale, result.new_girth});
  result.file = out;
  result.mesh.V = V;
  result.mesh.F = F;
  return result;
}

}  // namespace gp
