#include "pattern/seam_spec.h"

#include <algorithm>
#include <limits>
#include <map>
#include <set>

#include "core/error.h"
#include "garment/surface_path.h"
#include "garment/surface_point.h"
#include "io/mesh_io.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pose/pose_set.h"
#include "spec/spec_object.h"

namespace gp {
namespace {

SeamSpecPoint read_point(const Json& j, const std::string& where) {
  return read_clicked_point(j, where, "vertex");
}

// The spec's names of the surfaces, in the order of SeamSurface.
const std::vector<std::string> kSurfaceNames{"rest", "design", "body"};

}  // namespace

SeamSpec parse_seam_spec(const Json& j, const std::string& file) {
  check_schema(j, "seam-spec", {1}, file);
  const SpecObject root(j, file);
  root.allow("schema");
  SeamSpec s;
  s.file = file;
  s.snap_tolerance = root.number("snap_tolerance", s.snap_tolerance, Range::positive());
  const SpecArray seams = root.array("seams");
  std::set<std::string> names;
  for (size_t i = 0; i < seams.size(); ++i) {
    const SpecObject o = seams.object(i);
    SeamSpecSeam seam;
    seam.where = o.where();
    seam.name = o.required_string("name");
    if (seam.name.empty() || !names.insert(seam.name).second)
      throw SpecError("seam names must be unique and not empty", o.where("name"));
    const std::string on = o.choice("on", kSurfaceNames.front(), kSurfaceNames);
    seam.on = static_cast<SeamSurface>(std::find(kSurfaceNames.begin(), kSurfaceNames.end(), on) - kSurfaceNames.begin());
    seam.closed = o.boolean("closed", false);
    const Json* points = o.raw("points");
    if (!points) throw SpecError("missing required field 'points'", o.where("points"));
    if (!points->is_array()) throw SpecError("expected an array of points", o.where("points"));
    for (size_t k = 0; k < points->size(); ++k)
      seam.points.push_back(read_point((*points)[k], o.where("points") + "/" + std::to_string(k)));
    if (seam.points.size() < (seam.closed ? 3u : 2u))
      throw SpecError("seam '" + seam.name + "' needs at least " + (seam.closed ? "three" : "two") + " points",
                      o.where("points"));
    o.finish();
    s.seams.push_back(seam);
  }
  root.finish();
  return s;
}

SeamSpec read_seam_spec(const std::filesystem::path& path) {
  return parse_seam_spec(read_json_file(path), path.string());
}

OrderedJson to_json(const SeamSpec& spec) {
  OrderedJson j;
  j["schema"] = schema_tag("seam-spec", 1);
  j["snap_tolerance"] = spec.snap_tolerance;
  j["seams"] = OrderedJson::array();
  for (const auto& s : spec.seams) {
    OrderedJson points = OrderedJson::array();
    for (const auto& p : s.points)
      points.push_back(p.is_vertex ? OrderedJson(p.vertex_id)
                                   : OrderedJson::array({p.point[0], p.point[1], p.point[2]}));
    j["seams"].push_back({{"name", s.name}, {"on", kSurfaceNames[static_cast<size_t>(s.on)]}, {"points", points},
                          {"closed", s.closed}});
  }
  return j;
}

namespace {

// Each seam cuts the rest shape: it runs off its boundary somewhere, and an open seam reaches the
// boundary or another seam at one of its ends at least (a slit inside the shape opens nothing).
void check_seams_cut(const Eigen::MatrixXi& F, int n, const std::vector<SeamPath>& paths) {
  // Boundary edges and vertices of the rest shape.
  std::set<std::pair<int, int>> boundary_edges;
  std::vector<char> on_boundary(static_cast<size_t>(n), 0);
  for (const auto& loop : boundary_loops(F))
    for (size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      boundary_edges.insert({std::min(a, b), std::max(a, b)});
      on_boundary[static_cast<size_t>(a)] = 1;
    }
  std::map<int, std::set<size_t>> seams_at;  // vertex -> seams through it
  for (size_t i = 0; i < paths.size(); ++i)
    for (int v : paths[i].vertex_ids) seams_at[v].insert(i);
  for (size_t i = 0; i < paths.size(); ++i) {
    const SeamPath& p = paths[i];
    const size_t edges = p.closed ? p.vertex_ids.size() : p.vertex_ids.size() - 1;
    bool cuts = false;
    for (size_t k = 0; k < edges; ++k) {
      const int a = p.vertex_ids[k], b = p.vertex_ids[(k + 1) % p.vertex_ids.size()];
      if (!boundary_edges.count({std::min(a, b), std::max(a, b)})) cuts = true;
    }
    if (!cuts)
      throw GeometryError("seam '" + p.name + "' runs only along the boundary of the rest shape and cuts nothing",
                          p.where + "/points");
    if (p.closed) continue;
    auto reaches = [&](int v) { return on_boundary[static_cast<size_t>(v)] || seams_at[v].size() > 1; };
    if (!reaches(p.vertex_ids.front()) && !reaches(p.vertex_ids.back()))
      throw GeometryError("seam '" + p.name +
                              "' does not reach the boundary or another seam (both of its ends lie inside the "
                              "rest shape); start or end it on an edge of the garment or on another seam",
                          p.where + "/points");
  }
}

}  // namespace

std::vector<SeamPath> resolve_seams(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                    const SeamSpec& spec, const GarmentFile* garment,
                                    const DesignBody* body, const Eigen::MatrixXd* V_design) {
  const int n = static_cast<int>(V_rest.rows());
  const auto neighbors = vertex_neighbors(F, n);
  std::vector<char> used(static_cast<size_t>(n), 0);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<size_t>(F(f, k))] = 1;

  std::unique_ptr<SurfaceLocator> rest_locator;
  std::unique_ptr<SurfaceLocator> body_locator;
  Eigen::MatrixXd N_body;
  // Body points of the bound boundary vertices, for the binding-exact mapping.
  std::vector<std::pair<int, Eigen::Vector3d>> bound;

  // Nearest vertex of the rest shape (or of the design shape, which shares its
  // connectivity) to the surface point closest to x.
  std::unique_ptr<SurfaceLocator> design_locator;
  auto nearest_vertex = [&](const Eigen::MatrixXd& V, std::unique_ptr<SurfaceLocator>& locator,
                            const char* shape, const Eigen::Vector3d& x, const std::string& seam,
                            const std::string& where) {
    if (!locator) locator = std::make_unique<SurfaceLocator>(V, F);
    const auto hit = locator->closest(x);
    if (hit.distance > spec.snap_tolerance)
      throw SpecError("seam '" + seam + "': the point is " + std::to_string(hit.distance) + " m from the " +
                          shape + " (snap tolerance " + std::to_string(spec.snap_tolerance) +
                          " m): the path would leave the mesh",
                      where);
    int best = F(hit.at.face, 0);
    for (int k = 1; k < 3; ++k)
      if ((V.row(F(hit.at.face, k)).transpose() - hit.point).squaredNorm() <
          (V.row(best).transpose() - hit.point).squaredNorm())
        best = F(hit.at.face, k);
    return best;
  };
  auto nearest_rest_vertex = [&](const Eigen::Vector3d& x, const std::string& seam, const std::string& where) {
    return nearest_vertex(V_rest, rest_locator, "rest shape", x, seam, where);
  };

  auto body_to_rest = [&](const SeamSpecPoint& p, const std::string& seam) {
    if (!garment || !body)
      throw SpecError("seam '" + seam + "' has points on the body, but no body is available", p.where);
    if (!body_locator) {
      body_locator = std::make_unique<SurfaceLocator>(body->V, body->F);
      N_body = vertex_normals(body->V, body->F);
      for (const auto& loop : garment->loops)
        for (size_t k = 0; k < loop.binding.size() && k < loop.vertex_ids.size(); ++k)
          bound.emplace_back(loop.vertex_ids[k], evaluate(body->V, body->F, loop.binding[k]));
    }
    SurfacePoint at;
    if (p.is_vertex) {
      if (p.vertex_id >= body->V.rows())
        throw SpecError("seam '" + seam + "': body vertex id " + std::to_string(p.vertex_id) +
                            " out of range (the body has " + std::to_string(body->V.rows()) + " vertices)",
                        p.where);
      at = body_locator->closest(body->V.row(p.vertex_id).transpose()).at;
    } else {
      const auto hit = body_locator->closest(p.point);
      if (hit.distance > spec.snap_tolerance)
        throw SpecError("seam '" + seam + "': the point is " + std::to_string(hit.distance) +
                            " m from the body (snap tolerance " + std::to_string(spec.snap_tolerance) + " m)",
                        p.where);
      at = hit.at;
    }
    const Eigen::Vector3d x = evaluate(body->V, body->F, at);
    int best = -1;
    double best_d = spec.snap_tolerance;
    for (const auto& [v, y] : bound) {
      const double d = (y - x).norm();
      if (d <= best_d && (best < 0 || d < best_d || v < best)) best = v, best_d = d;
    }
    if (best >= 0) return best;
    const Eigen::Vector3d target = x + garment->offset * evaluate_normal(N_body, body->F, at);
    if (V_design) return nearest_vertex(*V_design, design_locator, "garment as designed", target, seam, p.where);
    return nearest_rest_vertex(target, seam, p.where);
  };

  std::vector<SeamPath> paths;
  for (const auto& s : spec.seams) {
    std::vector<int> clicks;
    for (const auto& p : s.points) {
      int v = -1;
      if (s.on == SeamSurface::body) {
        v = body_to_rest(p, s.name);
      } else if (p.is_vertex) {
        if (p.vertex_id >= n || !used[static_cast<size_t>(p.vertex_id)])
          throw SpecError("seam '" + s.name + "': vertex id " + std::to_string(p.vertex_id) +
                              " is not a vertex of the rest shape (" + std::to_string(n) + " vertices)",
                          p.where);
        v = static_cast<int>(p.vertex_id);
      } else if (s.on == SeamSurface::design) {
        if (!V_design)
          throw SpecError("seam '" + s.name + "' has points on the garment as designed, but that mesh is not available",
                          p.where);
        v = nearest_vertex(*V_design, design_locator, "garment as designed", p.point, s.name, p.where);
      } else {
        v = nearest_rest_vertex(p.point, s.name, p.where);
      }
      if (clicks.empty() || clicks.back() != v) clicks.push_back(v);
    }
    if (s.closed && clicks.size() > 1 && clicks.back() == clicks.front()) clicks.pop_back();
    if (clicks.size() < (s.closed ? 3u : 2u))
      throw SpecError("seam '" + s.name + "': its points snap to fewer than " + (s.closed ? "three" : "two") +
                          " distinct vertices",
                      s.where + "/points");
    SeamPath path;
    path.name = s.name;
    path.closed = s.closed;
    path.where = s.where;
    path.click_ids = clicks;
    const size_t legs = s.closed ? clicks.size() : clicks.size() - 1;
    for (size_t i = 0; i < legs; ++i) {
      const int a = clicks[i], b = clicks[(i + 1) % clicks.size()];
      const std::vector<int> leg = shortest_edge_path(V_rest, neighbors, a, b);
      if (leg.empty())
        throw GeometryError("seam '" + s.name + "': points " + std::to_string(i) + " and " +
                                std::to_string((i + 1) % clicks.size()) +
                                " lie on different connected components: the path would leave the mesh",
                            s.where + "/points");
      path.vertex_ids.insert(path.vertex_ids.end(), leg.begin(), leg.end() - 1);
    }
    if (!s.closed) path.vertex_ids.push_back(clicks.back());
    std::vector<int> sorted = path.vertex_ids;
    std::sort(sorted.begin(), sorted.end());
    const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    if (dup != sorted.end())
      throw GeometryError("seam '" + s.name + "' crosses or touches itself at vertex " + std::to_string(*dup),
                          s.where + "/points");
    paths.push_back(path);
  }

  check_seams_cut(F, n, paths);
  return paths;
}

}  // namespace gp
