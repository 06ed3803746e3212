#include "registration/register_check.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <thread>

#include "core/stopwatch.h"
#include "io/mesh_io.h"
#include "mesh/topology.h"
#include "pose/pose_set.h"

namespace fs = std::filesystem;

namespace gp {
namespace {

std::string join_ids(const std::vector<int>& ids, size_t most = 5) {
  std::string s;
  for (size_t i = 0; i < ids.size() && i < most; ++i) s += (s.empty() ? "" : ", ") + std::to_string(ids[i]);
  return s;
}

// The first few pairs for a message (the report lists more).
std::string join_pairs(const std::vector<std::pair<int, int>>& pairs, size_t most = 5) {
  std::string s;
  for (size_t i = 0; i < pairs.size() && i < most; ++i)
    s += (s.empty() ? "" : ", ") + std::to_string(pairs[i].first) + "-" + std::to_string(pairs[i].second);
  return s;
}

std::string format_double(double x, int precision = 4) {
  std::ostringstream s;
  s.precision(precision);
  s << x;
  return s.str();
}

// Runs f(i) for i in [0, n) on up to `threads` threads. Each i writes only
// its own slot, so the result does not depend on the thread count.
template <class Fn>
void parallel_for(int n, int threads, Fn f) {
  threads = std::max(1, std::min(threads, n));
  if (threads == 1) {
    for (int i = 0; i < n; ++i) f(i);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> errors(static_cast<size_t>(threads));
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      try {
        for (int i = t; i < n; i += threads) f(i);
      } catch (...) {
        errors[t] = std::current_exception();
      }
    });
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

void add(RegisterCheckResult& r, Severity s, ExitCode c, const std::string& pose, const std::string& msg) {
  r.findings.push_back({s, c, pose, msg});
}

// Findings from one pose's own mesh checks; returns false if the pose is not
// usable for the correspondence and geometry steps.
bool report_mesh_findings(RegisterCheckResult& r, const PoseCheck& p, const RegisterCheckOptions& o) {
  const MeshCheckResult& m = p.mesh;
  const std::string where = " (" + p.file + ")";
  bool usable = true;
  if (m.nonfinite_vertices > 0) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        std::to_string(m.nonfinite_vertices) + " vertices have NaN or infinite coordinates, e.g. vertex " +
            join_ids(m.nonfinite_vertex_ids) + where);
    usable = false;
  }
  if (m.nonmanifold_edges > 0) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        "non-manifold: " + std::to_string(m.nonmanifold_edges) +
            " edges are shared by more than two faces, e.g. edge " +
            join_pairs(m.nonmanifold_edge_examples) + where);
    usable = false;
  }
  if (m.nonmanifold_vertices > 0) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        "non-manifold: " + std::to_string(m.nonmanifold_vertices) +
            " vertices join separate fans of faces, e.g. vertex " + join_ids(m.nonmanifold_vertex_ids) +
            where);
    usable = false;
  }
  if (m.inconsistent_orientation_edges > 0) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        "inconsistent orientation: " + std::to_string(m.inconsistent_orientation_edges) +
            " edges are run the same way by both their faces (a flipped face), e.g. edge " +
            join_pairs(m.inconsistent_edge_examples) + where);
    usable = false;
  }
  if (!m.boundary_loop_sizes.empty()) {
    std::string sizes;
    for (size_t i = 0; i < m.boundary_loop_sizes.size(); ++i)
      sizes += (i ? ", " : "") + std::to_string(m.boundary_loop_sizes[i]) + " vertices from vertex " +
               std::to_string(m.boundary_loop_first_vertex[i]);
    const std::string msg = std::to_string(m.boundary_loop_sizes.size()) +
                            " holes (boundary loops: " + sizes + ")" + where;
    if (o.allow_open) add(r, Severity::warning, ExitCode::ok, p.name, msg);
    else add(r, Severity::error, ExitCode::geometry, p.name,
             "not closed: " + msg + "; a body must be watertight (pass --allow-open to accept)");
  }
  if (m.degenerate_faces > 0) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        std::to_string(m.degenerate_faces) + " degenerate (zero-area) triangles, e.g. face " +
            join_ids(m.degenerate_face_ids) + where);
    usable = false;
  }
  if (m.components > 1)
    add(r, Severity::warning, ExitCode::ok, p.name,
        std::to_string(m.components) + " connected components (a body is usually one)" + where);
  if (m.needle_faces > 0)
    add(r, Severity::warning, ExitCode::ok, p.name,
        std::to_string(m.needle_faces) + " needle triangles (smallest angle under " +
            format_double(o.mesh.needle_angle_degrees) + " degrees), e.g. face " +
            join_ids(m.needle_face_ids) + where);
  if (m.duplicate_vertices > 0)
    add(r, Severity::warning, ExitCode::ok, p.name,
        std::to_string(m.duplicate_vertices) + " duplicate vertices (same position), e.g. " +
            join_pairs(m.duplicate_vertex_examples) + where);
  if (m.unreferenced_vertices > 0)
    add(r, Severity::warning, ExitCode::ok, p.name,
        std::to_string(m.unreferenced_vertices) + " vertices used by no face, e.g. vertex " +
            join_ids(m.unreferenced_vertex_ids) + where);
  return usable;
}

OrderedJson pairs_json(const std::vector<std::pair<int, int>>& pairs) {
  OrderedJson a = OrderedJson::array();
  for (const auto& [x, y] : pairs) a.push_back({x, y});
  return a;
}

}  // namespace

ExitCode RegisterCheckResult::exit_code() const {
  for (const Finding& f : findings)
    if (f.severity == Severity::error) return f.category;
  for (const Finding& f : findings)
    if (f.severity == Severity::fail) return ExitCode::check_failed;
  return ExitCode::ok;
}

std::string RegisterCheckResult::verdict() const {
  const ExitCode c = exit_code();
  return c == ExitCode::ok ? "pass" : c == ExitCode::check_failed ? "fail" : "error";
}

std::vector<PoseInput> collect_pose_inputs(const std::vector<std::string>& args) {
  std::vector<PoseInput> inputs;
  for (const std::string& arg : args) {
    const fs::path p(arg);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> files;
      for (const auto& entry : fs::directory_iterator(p)) {
        std::string ext = entry.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
        if (entry.is_regular_file() && (ext == ".ply" || ext == ".obj")) files.push_back(entry.path());
      }
      if (files.empty()) throw UsageError("folder holds no .ply or .obj meshes", arg);
      std::sort(files.begin(), files.end());
      for (const auto& f : files) inputs.push_back({f.stem().string(), f});
    } else {
      inputs.push_back({p.stem().string(), p});
    }
  }
  if (inputs.empty()) throw UsageError("no pose meshes given");
  std::set<std::string> names;
  for (const PoseInput& in : inputs) {
    if (!is_valid_pose_name(in.name))
      throw UsageError("pose name '" + in.name +
                           "' (the file's stem) must be 1-64 letters, digits, '-' or '_'; rename the file",
                       in.file.string());
    if (!names.insert(in.name).second)
      throw UsageError("two pose files share the name '" + in.name + "'", in.file.string());
  }
  return inputs;
}

namespace {

// Reads every pose (InputError propagates: nothing to check in an
// unreadable file); the read warnings go into r, order_preserved per pose.
std::vector<Mesh> read_poses(const std::vector<PoseInput>& inputs, const RegisterCheckOptions& o, RegisterCheckResult& r,
                             std::vector<bool>& order_preserved) {
  const int n = static_cast<int>(inputs.size());
  std::vector<Mesh> meshes(static_cast<size_t>(n));
  r.poses.resize(static_cast<size_t>(n));
  std::vector<std::vector<std::string>> read_warnings(static_cast<size_t>(n));
  order_preserved.assign(static_cast<size_t>(n), true);
  parallel_for(n, o.threads, [&](int i) {
    MeshReadOptions ro;
    ro.triangulate = o.triangulate;
    MeshReadResult read = read_mesh(inputs[i].file, ro);
    meshes[i] = std::move(read.mesh);
    r.poses[i].format = read.format;
    read_warnings[i] = std::move(read.warnings);
    order_preserved[i] = read.vertex_order_preserved;
  });
  for (int i = 0; i < n; ++i) {
    r.poses[i].name = inputs[i].name;
    r.poses[i].file = inputs[i].file.string();
    for (const std::string& w : read_warnings[i]) add(r, Severity::warning, ExitCode::ok, inputs[i].name, w);
  }
  return meshes;
}

// Pose i against the reference: its vertices in the reference's order into
// V_ordered (empty where they cannot be), its connectivity and findings in
// r. False when it is not in correspondence.
bool correspond(const std::vector<Mesh>& meshes, const std::vector<PoseInput>& inputs, int i, int ref,
                const std::vector<bool>& usable, const RegisterCheckOptions& o, RegisterCheckResult& r,
                std::vector<Eigen::MatrixXd>& V_ordered) {
  PoseCheck& p = r.poses[i];
  const std::string& refname = inputs[ref].name;
  if (meshes[i].V.rows() != meshes[ref].V.rows() || meshes[i].F.rows() != meshes[ref].F.rows()) {
    p.connectivity = Connectivity::different;
    add(r, Severity::error, ExitCode::geometry, p.name,
        "poses not in correspondence: " + std::to_string(meshes[i].V.rows()) + " vertices and " +
            std::to_string(meshes[i].F.rows()) + " faces, but reference '" + refname + "' has " +
            std::to_string(meshes[ref].V.rows()) + " and " + std::to_string(meshes[ref].F.rows()) +
            " (" + p.file + ")");
    return false;
  }
  p.connectivity = compare_triangle_lists(meshes[ref].F, meshes[i].F);
  if (p.connectivity == Connectivity::identical) {
    V_ordered[i] = meshes[i].V;
    return true;
  }
  if (p.connectivity == Connectivity::same_faces_reordered) {
    // Same vertex order, triangles listed differently: the reference's list serves.
    V_ordered[i] = meshes[i].V;
    if (o.reorder) {
      p.reordered = true;
      p.reorder_note = "triangles listed in another order; rewritten with the reference's triangle list";
      add(r, Severity::warning, ExitCode::ok, p.name, p.reorder_note + " (" + p.file + ")");
      return true;
    }
    add(r, Severity::error, ExitCode::geometry, p.name,
        "same triangles as '" + refname + "' but listed in another order; pass --reorder to "
        "rewrite it with the reference's triangle list (" + p.file + ")");
    return false;
  }
  std::optional<VertexCorrespondence> c;
  if (usable[i] && usable[ref])
    c = find_vertex_correspondence(meshes[ref].V, meshes[ref].F, meshes[i].V, meshes[i].F);
  if (!c) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        "poses not in correspondence: the triangle list differs from reference '" + refname +
            "' and no relabelling of the vertices maps one onto the other (" + p.file + ")");
    return false;
  }
  p.connectivity = Connectivity::permuted;
  if (!o.reorder) {
    add(r, Severity::error, ExitCode::geometry, p.name,
        "same mesh as '" + refname + "' with its vertices in another order; pass --reorder to "
        "re-index it into the reference's order (" + p.file + ")");
    return false;
  }
  p.reordered = true;
  p.reorder_note = "vertices re-indexed into the reference's order (" +
                   std::to_string(c->candidates_tried) + " seed trials; verified: every triangle maps "
                   "to a triangle)";
  if (!c->note.empty()) p.reorder_note += "; " + c->note;
  add(r, Severity::warning, ExitCode::ok, p.name,
      p.reorder_note + " (" + p.file + ")");
  V_ordered[i] = reorder_vertices(meshes[i].V, *c);
  return true;
}

// Units and up axis from the reference pose (findings into r).
UnitsAndUp units_and_up(const Mesh& reference, const std::string& name, const RegisterCheckOptions& o,
                        RegisterCheckResult& r) {
  UnitsAndUp u;
  const std::string where = " (" + r.poses[static_cast<size_t>(r.reference)].file + ")";
  if (o.up == "auto") {
    const UpAxisDetection d = detect_up_axis(reference.V, reference.F);
    u.up = d.up;
    u.up_ambiguous = d.ambiguous;
    u.up_reason = d.reason;
    u.up_cues = d.cues;
    if (d.ambiguous)
      add(r, Severity::error, ExitCode::geometry, name,
          "cannot tell which way is up: " + d.reason + "; pass --up" + where);
  } else {
    u.up = UpAxis::parse(o.up);
    u.up_reason = "given by --up";
  }
  const Eigen::VectorXd along = reference.V.col(u.up.axis);
  u.height = along.maxCoeff() - along.minCoeff();
  if (o.height > 0) {
    if (o.units != "auto") throw UsageError("--height scales the body itself; it excludes --units", "--height");
    if (!(u.height > 0)) {
      add(r, Severity::error, ExitCode::geometry, name,
          "the body has no extent along " + u.up.name() + "; cannot scale it to --height" + where);
    } else {
      u.units = "height";
      u.given_height_m = o.height;
      u.scale_to_metres = o.height / u.height;
    }
  } else {
    if (o.units == "auto") {
      try {
        u.units = detect_units(u.height);
      } catch (const GeometryError& e) {
        add(r, Severity::error, ExitCode::geometry, name,
            std::string(e.what()) + " or --height" + where);
      }
    } else {
      u.units = o.units;
    }
    u.scale_to_metres = metres_per_unit(u.units);
  }
  return u;
}

// Every usable pose in metres, y up, its edge lengths against the
// reference's (a fail beyond max_edge_ratio) and its surface's growth.
void compare_with_reference(const std::vector<PoseInput>& inputs, const std::vector<bool>& usable,
                          const std::vector<Eigen::MatrixXd>& V_ordered, const RegisterCheckOptions& o,
                          RegisterCheckResult& r) {
  const int n = static_cast<int>(inputs.size());
  const int ref = r.reference;
  const Eigen::MatrixXi E = unique_edges(r.F);
  for (int i = 0; i < n; ++i) {
    if (!usable[i] || V_ordered[i].rows() == 0) continue;
    r.poses[i].V = to_metres_y_up(V_ordered[i], *r.units);
  }
  for (int i = 0; i < n; ++i) {
    if (i == ref || r.poses[i].V.rows() == 0 || r.poses[ref].V.rows() == 0) continue;
    r.poses[i].edge_ratios = edge_ratio_stats(r.poses[ref].V, r.poses[i].V, E, o.worst_edges);
    r.poses[i].surface_growth = surface_growth(r.poses[ref].V, r.poses[i].V, r.F, o.surface_radius);
    const EdgeRatioStats& s = *r.poses[i].edge_ratios;
    if (s.worst_factor > o.max_edge_ratio) {
      const EdgeRatioEdge& w = s.worst.front();
      add(r, Severity::fail, ExitCode::check_failed, r.poses[i].name,
          "registration: an edge changes length by a factor of " + format_double(s.worst_factor) +
              " against '" + inputs[ref].name + "' (limit " + format_double(o.max_edge_ratio) +
              "): edge " + std::to_string(w.v0) + "-" + std::to_string(w.v1) + " is " +
              format_double(w.length) + " m, " + format_double(w.reference_length) +
              " m in the reference (" + r.poses[i].file + ")");
    }
  }
}

// Self-intersections (warnings): only on poses CGAL can hold as a surface.
void self_intersection_warnings(const std::vector<Mesh>& meshes, const std::vector<bool>& usable,
                                const RegisterCheckOptions& o, RegisterCheckResult& r) {
  const int n = static_cast<int>(meshes.size());
  parallel_for(n, o.threads, [&](int i) {
    const PoseCheck& p = r.poses[i];
    if (!usable[i] || !p.mesh.manifold() || p.mesh.inconsistent_orientation_edges > 0) return;
    r.poses[i].self_intersections = self_intersections(meshes[i].V, meshes[i].F);
  });
  for (int i = 0; i < n; ++i) {
    const auto& si = r.poses[i].self_intersections;
    if (si && si->pair_count > 0)
      add(r, Severity::warning, ExitCode::ok, r.poses[i].name,
          std::to_string(si->pair_count) + " pairs of triangles intersect, e.g. faces " +
              join_pairs(si->first_pairs) + " (" + r.poses[i].file + ")");
  }
}

}  // namespace

RegisterCheckResult register_check(const std::vector<PoseInput>& inputs,
                                   const RegisterCheckOptions& o) {
  const auto t_start = Clock::now();
  RegisterCheckResult r;
  if (inputs.empty()) throw UsageError("no pose meshes given");
  const int n = static_cast<int>(inputs.size());

  auto t0 = Clock::now();
  std::vector<bool> order_preserved;
  const std::vector<Mesh> meshes = read_poses(inputs, o, r, order_preserved);
  r.seconds_read = seconds_since(t0);

  r.reference = 0;
  if (!o.reference.empty()) {
    r.reference = -1;
    for (int i = 0; i < n; ++i)
      if (inputs[i].name == o.reference) r.reference = i;
    if (r.reference < 0) throw UsageError("no pose named '" + o.reference + "' among the inputs", "--reference");
  }
  const int ref = r.reference;

  // Per-pose checks.
  t0 = Clock::now();
  parallel_for(n, o.threads, [&](int i) { r.poses[i].mesh = check_mesh(meshes[i].V, meshes[i].F, o.mesh); });
  std::vector<bool> usable(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) usable[i] = report_mesh_findings(r, r.poses[i], o);
  r.seconds_checks = seconds_since(t0);

  // Correspondence with the reference.
  t0 = Clock::now();
  r.F = meshes[ref].F;
  std::vector<Eigen::MatrixXd> V_ordered(static_cast<size_t>(n));
  V_ordered[ref] = meshes[ref].V;
  bool all_correspond = true;
  for (int i = 0; i < n; ++i) {
    if (i == ref) continue;
    if (!correspond(meshes, inputs, i, ref, usable, o, r, V_ordered)) all_correspond = false;
  }
  for (int i = 0; i < n; ++i)
    if (!order_preserved[i] && n > 1)
      add(r, Severity::warning, ExitCode::ok, inputs[i].name,
          "read through a format that does not keep vertex order; correspondence rests on --reorder "
          "or luck (" + r.poses[i].file + ")");
  r.seconds_correspondence = seconds_since(t0);

  if (usable[ref]) r.units = units_and_up(meshes[ref], inputs[ref].name, o, r);
  // Normalize and compare edge lengths against the reference.
  if (r.units && all_correspond) compare_with_reference(inputs, usable, V_ordered, o, r);

  t0 = Clock::now();
  if (o.self_intersections) self_intersection_warnings(meshes, usable, o, r);
  r.seconds_self_intersections = seconds_since(t0);
  r.seconds_total = seconds_since(t_start);
  return r;
}

OrderedJson register_check_report(const RegisterCheckResult& r, const RegisterCheckOptions& o) {
  OrderedJson j;
  j["schema"] = schema_tag("register-check-report", 1);
  j["verdict"] = r.verdict();
  j["exit_code"] = static_cast<int>(r.exit_code());
  RegisterCheckOptions used = o;
  if (used.reference.empty()) used.reference = r.poses[r.reference].name;
  j["options"] = write_options(used, RegisterCheckOptionFields{});
  j["reference"] = r.poses[r.reference].name;
  if (r.units) {
    OrderedJson u;
    u["units"] = r.units->units;
    u["scale_to_metres"] = r.units->scale_to_metres;
    u["up"] = r.units->up.name();
    u["up_ambiguous"] = r.units->up_ambiguous;
    u["up_reason"] = r.units->up_reason;
    OrderedJson cues = OrderedJson::array();
    for (const UpCue& c : r.units->up_cues)
      cues.push_back({{"cue", c.name}, {"vote", c.vote == 0 ? "none" : UpAxis{r.units->up.axis, c.vote}.name()},
                      {"detail", c.detail}});
    u["up_cues"] = cues;
    if (r.units->given_height_m > 0) u["scaled_to_height_m"] = r.units->given_height_m;
    u["height_input_units"] = r.units->height;
    u["height_m"] = r.units->height * r.units->scale_to_metres;
    u["output"] = "metres, +y up";
    j["units"] = u;
  } else {
    j["units"] = nullptr;
  }
  j["vertex_count"] = r.F.rows() > 0 ? r.poses[r.reference].mesh.vertex_count : 0;
  j["face_count"] = r.F.rows();
  OrderedJson poses = OrderedJson::array();
  for (const PoseCheck& p : r.poses) {
    OrderedJson pj;
    pj["name"] = p.name;
    pj["file"] = p.file;
    pj["format"] = p.format;
    const MeshCheckResult& m = p.mesh;
    pj["vertex_count"] = m.vertex_count;
    pj["face_count"] = m.face_count;
    OrderedJson c;
    c["nonfinite_vertices"] = m.nonfinite_vertices;
    c["nonfinite_vertex_examples"] = m.nonfinite_vertex_ids;
    c["nonmanifold_edges"] = m.nonmanifold_edges;
    c["nonmanifold_edge_examples"] = pairs_json(m.nonmanifold_edge_examples);
    c["nonmanifold_vertices"] = m.nonmanifold_vertices;
    c["nonmanifold_vertex_examples"] = m.nonmanifold_vertex_ids;
    c["inconsistent_orientation_edges"] = m.inconsistent_orientation_edges;
    c["inconsistent_orientation_examples"] = pairs_json(m.inconsistent_edge_examples);
    c["boundary_loops"] = m.boundary_loop_sizes.size();
    c["boundary_loop_sizes"] = m.boundary_loop_sizes;
    c["components"] = m.components;
    c["degenerate_faces"] = m.degenerate_faces;
    c["degenerate_face_examples"] = m.degenerate_face_ids;
    c["needle_faces"] = m.needle_faces;
    c["needle_face_examples"] = m.needle_face_ids;
    c["duplicate_vertices"] = m.duplicate_vertices;
    c["duplicate_vertex_examples"] = pairs_json(m.duplicate_vertex_examples);
    c["unreferenced_vertices"] = m.unreferenced_vertices;
    c["unreferenced_vertex_examples"] = m.unreferenced_vertex_ids;
    if (p.self_intersections) {
      c["self_intersecting_pairs"] = p.self_intersections->pair_count;
      c["self_intersection_examples"] = pairs_json(p.self_intersections->first_pairs);
    } else {
      c["self_intersecting_pairs"] = nullptr;
    }
    pj["checks"] = c;
    pj["connectivity"] = connectivity_name(p.connectivity);
    pj["reordered"] = p.reordered;
    if (!p.reorder_note.empty()) pj["reorder_note"] = p.reorder_note;
    if (p.edge_ratios) {
      const EdgeRatioStats& s = *p.edge_ratios;
      OrderedJson e;
      e["edges"] = s.edge_count;
      e["min"] = s.min;
      e["p01"] = s.p01;
      e["p05"] = s.p05;
      e["median"] = s.median;
      e["p95"] = s.p95;
      e["p99"] = s.p99;
      e["max"] = s.max;
      e["worst_factor"] = s.worst_factor;
      OrderedJson worst = OrderedJson::array();
      for (const EdgeRatioEdge& w : s.worst)
        worst.push_back({{"v0", w.v0}, {"v1", w.v1}, {"reference_length_m", w.reference_length},
                         {"length_m", w.length}, {"ratio", w.ratio}});
      e["worst_edges"] = worst;
      pj["edge_ratio"] = e;
    } else {
      pj["edge_ratio"] = nullptr;
    }
    if (p.surface_growth) {
      const SurfaceGrowth& g = *p.surface_growth;
      auto patch = [](const SurfacePatch& q) {
        return OrderedJson{{"factor", q.factor}, {"vertex", q.vertex}, {"at_m", {q.at.x(), q.at.y(), q.at.z()}}};
      };
      pj["surface_growth"] = {{"radius_m", g.radius},
                              {"largest", patch(g.largest)},
                              {"smallest", patch(g.smallest)},
                              {"p99", g.p99},
                              {"share_above_1_25", g.share_above_1_25}};
    } else {
      pj["surface_growth"] = nullptr;
    }
    poses.push_back(pj);
  }
  j["poses"] = poses;
  OrderedJson findings = OrderedJson::array();
  for (const Finding& f : r.findings) {
    OrderedJson fj;
    fj["severity"] = f.severity == Severity::error ? "error" : f.severity == Severity::fail ? "fail" : "warning";
    if (f.severity == Severity::error) fj["category"] = category_name(f.category);
    fj["pose"] = f.pose;
    fj["message"] = f.message;
    findings.push_back(fj);
  }
  j["findings"] = findings;
  return j;
}

OrderedJson register_check_timing(const RegisterCheckResult& r) {
  OrderedJson t;
  t["schema"] = schema_tag("timing", 1);
  t["tool"] = "register-check";
  t["read_s"] = r.seconds_read;
  t["checks_s"] = r.seconds_checks;
  t["correspondence_s"] = r.seconds_correspondence;
  t["self_intersections_s"] = r.seconds_self_intersections;
  t["total_s"] = r.seconds_total;
  return t;
}

}  // namespace gp
