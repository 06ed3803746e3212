// register-check: validates a customer's registered poses and writes the
// normalized pose set (poses.json + one binary PLY per pose) for later stages.

#include <cstdio>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/sha256.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "registration/register_check.h"

int main(int argc, char** argv) {
  gp::Tool tool("register-check",
                "Checks that pose meshes are one body in correspondence (same vertices, same "
                "triangles), valid and in known units, and writes them normalized to metres, +y up, "
                "with a poses.json manifest. Exit 0 pass, 8 a check failed (report written), 5 invalid "
                "geometry (report written), 3 unreadable input.");
  std::vector<std::string> inputs;
  gp::RegisterCheckOptions o;
  bool no_self = false;
  auto& app = tool.app();
  app.add_option("poses", inputs, "Pose meshes (.ply/.obj; other formats via assimp) or folders of them")
      ->required();
  app.add_option("--reference", o.reference, "Reference pose name (file stem) [default: first pose]");
  app.add_option("--units", o.units, "Input units: auto, m, cm, mm or in")
      ->check(CLI::IsMember({"auto", "m", "cm", "mm", "in"}));
  auto* units = app.get_option("--units");
  app.add_option("--up", o.up,
                 "Input up axis: auto, +y, -y, +z, -z, +x or -x (auto refuses a body whose up direction its cues "
                 "cannot tell, exit 5)")
      ->check(CLI::IsMember({"auto", "+x", "-x", "+y", "-y", "+z", "-z"}));
  auto* height = app.add_option("--height", o.height,
                                "Scale the body so that the reference pose is this tall along the up axis, for a "
                                "body in unknown units; the report records the factor. Excludes --units [m]")
                     ->check(CLI::Range(0.3, 3.0));
  app.add_flag("--reorder", o.reorder,
               "Re-index poses whose vertices are in another order into the reference's order");
  app.add_flag("--triangulate", o.triangulate, "Split polygons into triangles instead of rejecting them");
  app.add_flag("--allow-open", o.allow_open, "Accept meshes with holes (warning instead of error)");
  app.add_option("--max-edge-ratio", o.max_edge_ratio,
                 "Fail when an edge's length changes by more than this factor against the reference [ratio]")
      ->check(CLI::Range(1.0, 1e6));
  app.add_flag("--no-self-intersections", no_self, "Skip the self-intersection test");
  app.add_option("--needle-angle", o.mesh.needle_angle_degrees,
                 "Warn about triangles with a smaller angle than this [degrees]")
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--worst-edges", o.worst_edges, "Worst edges listed per pose in the report [count]")
      ->check(CLI::Range(0, 1000));
  app.add_option("--surface-radius", o.surface_radius,
                 "Radius of the neighbourhoods whose area growth against the reference each pose reports: where "
                 "the registration stretches the skin, a garment fitted there grows [m]")
      ->check(CLI::Range(0.001, 10.0));
  height->excludes(units);
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    o.self_intersections = !no_self;
    o.threads = tool.common().threads;
    const auto poses = gp::collect_pose_inputs(inputs);
    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    const gp::RegisterCheckResult result = gp::register_check(poses, o);
    auto& log = tool.log();

    const gp::ExitCode code = result.exit_code();
    if (code == gp::ExitCode::ok) {
      gp::PoseSetManifest m;
      m.vertex_count = result.F.rows() > 0 ? result.poses[result.reference].V.rows() : 0;
      m.face_count = result.F.rows();
      m.topology_sha256 = gp::topology_checksum(result.F);
      m.reference = result.poses[result.reference].name;
      for (const gp::PoseCheck& p : result.poses) {
        gp::Mesh mesh;
        mesh.V = p.V;
        mesh.F = result.F;
        const std::string file = p.name + ".ply";
        gp::write_mesh(out.file(file), mesh);
        m.poses.push_back({p.name, file, gp::sha256_file_hex(out.file(file)), p.file});
      }
      gp::write_pose_set_manifest(out.file("poses.json"), m);
    }
    gp::write_json_file(out.file("timing.json"), gp::register_check_timing(result));
    gp::write_json_file(out.file("report.json"), gp::register_check_report(result, o));
    out.commit();

    const std::string report_path = tool.common().out_dir + "/report.json";
    if (code != gp::ExitCode::ok) {
      // One line: the first error (or failed check); the others are in the report.
      const gp::Severity first = code == gp::ExitCode::check_failed ? gp::Severity::fail : gp::Severity::error;
      int others = -1;
      std::string message;
      for (const gp::Finding& f : result.findings)
        if (f.severity != gp::Severity::warning) {
          if (message.empty() && f.severity == first) message = (f.pose.empty() ? "" : f.pose + ": ") + f.message;
          ++others;
        }
      log.error(code, message + (others > 0 ? "; " + std::to_string(others) + " more in " : "; see ") + report_path);
      return static_cast<int>(code);
    }
    for (const gp::Finding& f : result.findings)
      log.warning((f.pose.empty() ? "" : f.pose + ": ") + f.message);
    std::string summary = std::to_string(result.poses.size()) + " poses, " +
                          std::to_string(result.F.rows()) + " triangles";
    if (result.units)
      summary += ", units " + result.units->units + ", up " + result.units->up.name();
    double worst = 1;
    for (const gp::PoseCheck& p : result.poses)
      if (p.edge_ratios) worst = std::max(worst, p.edge_ratios->worst_factor);
    if (result.poses.size() > 1) summary += ", worst edge-length factor " + std::to_string(worst);
    // Where the skin stretches most: a garment resting there grows with it.
    const gp::PoseCheck* most = nullptr;
    for (const gp::PoseCheck& p : result.poses)
      if (p.surface_growth && (!most || p.surface_growth->largest.factor > most->surface_growth->largest.factor))
        most = &p;
    if (most) {
      const gp::SurfacePatch& q = most->surface_growth->largest;
      char where[160];
      std::snprintf(where, sizeof(where), ", surface grown most x%.2f within %.0f mm of (%.3f, %.3f, %.3f) m in '%s'",
                    q.factor, 1000.0 * most->surface_growth->radius, q.at.x(), q.at.y(), q.at.z(), most->name.c_str());
      summary += where;
    }
    log.info(result.verdict() + ": " + summary + "; report in " + report_path);
    return static_cast<int>(code);
  });
}
