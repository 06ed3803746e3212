#pragma once
// Scenes for the hard-case tests of simulate-adapt, built
// the way a user builds them: a generated body (make-avatar, ~2,000 vertices)
// and a small short-sleeved top on it (make-garment: neck loop pinned, waist
// hem and upper-arm sleeve ends free, about 350 vertices, 1 cm comfort offset).
// The stages run as commands into a temporary folder; library tests then read
// the files back.
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/sha256.h"
#include "garment/garment_file.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"
#include "testing/command.h"
#include "testing/files.h"
#include "testing/test_meshes.h"

namespace gp::hard_cases {

namespace fs = std::filesystem;

struct Scene {
  fs::path dir;          // the scene's folder
  fs::path poses;        // body/poses.json (make-avatar)
  fs::path garment;      // top/garment.json (make-garment)
  double height = 0.0;   // body height [m]
  double chest_y = 0.0;  // height of the chest girth's plane [m]
};

// Eight body vertex ids around the girth landmark `name` of make-avatar's
// report (plane through its point with its normal), by angle around it.
inline Json ring_vertex_ids(const Eigen::MatrixXd& V, const Json& report, const std::string& name) {
  for (const auto& g : report["girths"]) {
    if (g["name"] != name) continue;
    const Eigen::Vector3d c(g["plane_point_m"][0].get<double>(), g["plane_point_m"][1].get<double>(),
                            g["plane_point_m"][2].get<double>());
    const Eigen::Vector3d n = Eigen::Vector3d(g["plane_normal"][0].get<double>(), g["plane_normal"][1].get<double>(),
                                              g["plane_normal"][2].get<double>())
                                  .normalized();
    const double reach = 1.5 * g["target_m"].get<double>() / (2.0 * M_PI);
    return Json(gp::testing::ring_vertex_ids(V, c, n, reach));
  }
  return Json::array();
}

// Runs make-avatar (spec file or the default body when empty, the given
// comma-separated poses, small resolution) and make-garment into dir.
// Returns an empty scene dir when a stage failed; `log` gets its stderr.
inline Scene build_scene(const fs::path& dir, const std::string& avatar_spec, const std::string& poses,
                         int garment_vertices, std::string& log) {
  Scene s;
  fs::create_directories(dir);
  const auto avatar = testing::run_command(testing::tool_path("make-avatar") + " " + avatar_spec +
                                           " --resolution small --poses " + poses + " --quiet --out " +
                                           (dir / "body").string());
  log += avatar.err;
  if (avatar.exit_code != 0) return s;
  const Json report = read_json_file(dir / "body" / "report.json");
  const PoseSet body = load_pose_set(dir / "body" / "poses.json");
  const Eigen::MatrixXd& V = body.V[static_cast<size_t>(body.index_of("apose", "test"))];
  Json spec;
  spec["schema"] = "garment-spec/1";
  spec["name"] = "hard-case-top";
  spec["design_pose"] = "apose";
  spec["loops"] = Json::array({
      {{"name", "neck"}, {"pinned", true}, {"points", ring_vertex_ids(V, report, "neck")}},
      {{"name", "hem"}, {"points", ring_vertex_ids(V, report, "waist")}},
      {{"name", "sleeve_left"}, {"points", ring_vertex_ids(V, report, "upper_arm_left")}},
      {{"name", "sleeve_right"}, {"points", ring_vertex_ids(V, report, "upper_arm_right")}},
  });
  // Region: the front-most torso vertex at chest height.
  double chest_y = 0.0;
  for (const auto& g : report["girths"]) {
    if (g["name"] == "chest") chest_y = g["plane_point_m"][1].get<double>();
  }
  int front = -1;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (std::abs(V(v, 1) - chest_y) < 0.03 && std::abs(V(v, 0)) < 0.05 && (front < 0 || V(v, 2) > V(front, 2))) {
      front = static_cast<int>(v);
    }
  }
  spec["region"] = front;
  spec["resolution"] = {{"vertex_count", garment_vertices}};
  spec["offset"] = 0.01;
  write_json_file(dir / "top-spec.json", spec);
  const auto garment = testing::run_command(testing::tool_path("make-garment") + " " +
                                            (dir / "top-spec.json").string() + " --poses " +
                                            (dir / "body" / "poses.json").string() + " --quiet --out " +
                                            (dir / "top").string());
  log += garment.err;
  if (garment.exit_code != 0) return s;
  s.dir = dir;
  s.poses = dir / "body" / "poses.json";
  s.garment = dir / "top" / "garment.json";
  s.height = V.col(1).maxCoeff() - V.col(1).minCoeff();
  s.chest_y = chest_y;
  return s;
}

// The default 1.70 m body in the A-pose, T-pose and arms-up pose with its
// top, built once per test process.
inline const Scene& default_scene() {
  static std::string log;
  static const Scene scene =
      build_scene(testing::fresh_temp_dir("hard_cases_default"), "", "apose,tpose,armsup", 350, log);
  if (scene.dir.empty()) throw std::runtime_error("could not build the default hard-case scene: " + log);
  return scene;
}

// A motion file (motion/1) through `sequence` with `steps` frames per transition.
inline fs::path write_motion(const fs::path& path, const std::vector<std::string>& sequence, int steps) {
  OrderedJson motion;
  motion["schema"] = schema_tag("motion", 1);
  motion["steps"] = steps;
  motion["sequence"] = sequence;
  write_json_file(path, motion);
  return path;
}

// A pose-set manifest written by hand beside the given pose files (names =
// file stems, the first the reference), as a user bypassing register-check
// would write it. `units` empty: the field is left out.
inline fs::path write_manual_manifest(const fs::path& path, const std::vector<fs::path>& files,
                                      const std::string& units) {
  const MeshReadResult first = read_mesh(files[0]);
  OrderedJson j;
  j["schema"] = schema_tag("pose-set", 1);
  if (!units.empty()) j["units"] = units;
  j["vertex_count"] = first.mesh.V.rows();
  j["face_count"] = first.mesh.F.rows();
  j["topology_sha256"] = topology_checksum(first.mesh.F);
  j["reference"] = files[0].stem().string();
  j["poses"] = OrderedJson::array();
  for (const fs::path& f : files) {
    j["poses"].push_back({{"name", f.stem().string()},
                          {"file", fs::relative(f, path.parent_path()).string()},
                          {"sha256", sha256_file_hex(f)},
                          {"source", "written by hand"}});
  }
  write_json_file(path, j);
  return path;
}

}  // namespace gp::hard_cases
