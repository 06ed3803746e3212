// make-garment: designs the initial garment on the body in the design pose from
// a garment spec (tools T1 boundary, T3 paint, T4 comfort offset, T5 pins).
// Writes garment.ply, garment.json ("garment/1") and report.json into --out.
#include <chrono>
#include <filesystem>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"
#include "garment/make_garment.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  gp::Tool tool("make-garment", "Design a garment on the body from a garment spec (garment-spec/1)");
  std::string spec_path, poses_path, avatar_path, pose_name;
  auto& app = tool.app();
  app.add_option("spec", spec_path, "Garment spec (JSON, schema garment-spec/1)")->required();
  auto* poses = app.add_option("--poses", poses_path, "Pose set manifest (poses.json, pose-set/1)");
  auto* avatar = app.add_option("--avatar", avatar_path, "A single avatar mesh (PLY/OBJ, metres, +y up) instead of a pose set");
  poses->excludes(avatar);
  app.add_option("--pose", pose_name,
                 "Design pose name (default: the spec's design_pose, else the pose set's reference)");
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    if (poses_path.empty() && avatar_path.empty())
      throw gp::UsageError("give the body as --poses <poses.json> or --avatar <mesh>", "see --help");
    const gp::GarmentSpec spec = gp::read_garment_spec(spec_path);

    Eigen::MatrixXd V_body;
    Eigen::MatrixXi F_body;
    gp::GarmentBodyInfo body_info;
    if (!poses_path.empty()) {
      const gp::PoseSet set = gp::load_pose_set(poses_path);
      std::string name = !pose_name.empty() ? pose_name : !spec.design_pose.empty() ? spec.design_pose : set.reference;
      const int index = set.index_of(name, pose_name.empty() && !spec.design_pose.empty()
                                               ? spec_path + ": /design_pose"
                                               : "--pose");
      V_body = set.V[static_cast<size_t>(index)];
      F_body = set.F;
      body_info.source = poses_path;
      body_info.design_pose = name;
    } else {
      gp::MeshReadResult read = gp::read_mesh(avatar_path);
      for (const auto& w : read.warnings) tool.log().warning(w);
      V_body = read.mesh.V;
      F_body = read.mesh.F;
      body_info.source = avatar_path;
      body_info.design_pose = !pose_name.empty() ? pose_name
                              : !spec.design_pose.empty() ? spec.design_pose
                                                          : fs::path(avatar_path).stem().string();
    }
    body_info.source_sha256 = gp::sha256_file_hex(body_info.source);
    body_info.vertex_count = V_body.rows();
    body_info.face_count = F_body.rows();
    body_info.topology_sha256 = gp::topology_checksum(F_body);
    body_info.design_pose_sha256 = gp::vertex_checksum(V_body);

    gp::MakeGarmentResult result = gp::make_garment(V_body, F_body, spec);
    tool.log().detail("garment: " + std::to_string(result.mesh.V.rows()) + " vertices, " +
                      std::to_string(result.mesh.F.rows()) + " triangles");

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    gp::write_mesh(out.file("garment.ply"), result.mesh);
    gp::GarmentFile& file = result.file;
    file.mesh_file = "garment.ply";
    file.mesh_sha256 = gp::sha256_file_hex(out.file("garment.ply"));
    file.body = body_info;
    file.spec_file = spec_path;
    file.spec_sha256 = gp::sha256_file_hex(spec_path);
    gp::write_garment_file(out.file("garment.json"), file);

    gp::OrderedJson report;
    report["schema"] = gp::schema_tag("make-garment-report", 1);
    report["options"] = {{"spec", spec_path},
                         {"poses", poses_path},
                         {"avatar", avatar_path},
                         {"design_pose", body_info.design_pose},
                         {"threads", tool.common().threads},
                         {"effective_spec", gp::to_json(spec)}};
    report["counts"] = {{"body_vertices", V_body.rows()},
                        {"body_faces", F_body.rows()},
                        {"cut_vertices", result.cut.V.rows()},
                        {"cut_faces", result.cut.F.rows()},
                        {"garment_vertices", result.mesh.V.rows()},
                        {"garment_faces", result.mesh.F.rows()},
                        {"boundary_loops", result.boundary_loop_count},
                        {"components", result.component_count},
                        {"euler_characteristic", result.euler_characteristic}};
    gp::OrderedJson curves = gp::OrderedJson::array();
    for (const auto& c : result.cut.curves)
      curves.push_back({{"name", c.name},
                        {"points", c.segments.size()},
                        {"length", gp::curve_length(V_body, F_body, c)}});
    const auto& q = result.quality;
    report["quality"] = {{"region_area", result.cut.area},
                         {"target_edge_length", result.target_edge_length},
                         {"mean_edge_length", q.mean_edge_length},
                         {"min_edge_ratio", q.min_edge_ratio},
                         {"max_edge_ratio", q.max_edge_ratio},
                         {"fraction_edges_within_30_percent", q.fraction_edges_within_30},
                         {"min_angle_deg", q.min_angle_deg},
                         {"fraction_min_angle_over_20_deg", q.fraction_min_angle_over_20},
                         {"faces_min_angle_under_5_deg", q.faces_min_angle_under_5},
                         {"cone_vertices", q.cone_vertices},
                         {"max_abs_angle_defect_deg", q.max_abs_angle_defect_deg},
                         {"abs_angle_defect_sum_rad", q.abs_angle_defect_sum},
                         {"boundary_curve_error", result.boundary_curve_error},
                         {"offset_max_error", result.offset_error.max_error},
                         {"offset_mean_error", result.offset_error.mean_error},
                         {"offset_max_below", result.offset_error.max_below},
                         {"offset_max_above", result.offset_error.max_above},
                         {"binding_max_deviation", result.binding_max_deviation},
                         {"curves", curves}};
    report["body_clearance"] = gp::to_json(result.clearance);
    if (!result.clearance.clear()) {
      const auto& a = result.clearance.after;
      tool.log().warning("the garment passes through the body: " + std::to_string(a.crossings()) +
                         " edge/triangle crossings, " + std::to_string(a.cloth_vertices_inside) + " vertices inside");
    }
    // Timings differ between runs, so they live apart from the report.
    gp::OrderedJson timing;
    timing["schema"] = gp::schema_tag("timing", 1);
    timing["tool"] = "make-garment";
    for (auto it = result.timing.begin(); it != result.timing.end(); ++it) timing[it.key() + "_s"] = it.value();
    timing["total_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::write_json_file(out.file("timing.json"), timing);
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    tool.log().info("wrote " + tool.common().out_dir + " (" + std::to_string(result.mesh.V.rows()) +
                    " vertices, " + std::to_string(result.boundary_loop_count) + " boundary loops)");
    return 0;
  });
}
