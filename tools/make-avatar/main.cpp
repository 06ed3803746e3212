// make-avatar: a posable body from tailoring measurements. Writes one binary
// PLY per pose (metres, +y up, facing +z, feet at y = 0, identical
// connectivity), poses.json, skeleton.json, report.json (deterministic) and
// timing.json (wall-clock seconds per phase).
#include <sstream>

#include "avatar/make_avatar.h"
#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/sha256.h"
#include "io/mesh_io.h"
#include "pose/pose_set.h"

namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  gp::Tool tool("make-avatar",
                "Generates a watertight, posable body from tailoring measurements (JSON spec, schema "
                "avatar-spec/1; without a spec, the built-in 1.70 m default body). Writes <pose>.ply per "
                "pose, poses.json, skeleton.json, report.json and timing.json into --out.");
  std::string spec_path;
  std::string poses = "all";
  std::string resolution = "default";
  int vertices = 0;
  auto& app = tool.app();
  app.add_option("spec", spec_path,
                 "Measurement spec (JSON, schema avatar-spec/1); omit for the default body");
  app.add_option("--poses", poses,
                 "Comma-separated poses: apose,tpose,armsup,armsforward,elbowsbent,stepforward,seated,handsonthighs and "
                 "the spec's poses, or 'all' [names]")
      ->capture_default_str();
  app.add_option("--resolution", resolution,
                 "Mesh size: small (~2,000 vertices), default (~12,000) or large (~40,000) [preset]")
      ->check(CLI::IsMember({"small", "default", "large"}))
      ->capture_default_str();
  app.add_option("--vertices", vertices, "Vertex budget, overrides --resolution [vertices]")
      ->check(CLI::Range(500, 2000000));
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    gp::set_thread_count(tool.common().threads);
    const gp::AvatarSpec spec =
        spec_path.empty() ? gp::default_avatar_spec() : gp::read_avatar_spec(spec_path);
    gp::AvatarOptions o;
    o.target_vertices = resolution == "small"   ? gp::kAvatarSmallVertices
                        : resolution == "large" ? gp::kAvatarLargeVertices
                                                : gp::kAvatarDefaultVertices;
    if (vertices > 0) o.target_vertices = vertices;
    if (poses != "all") o.poses = split_list(poses);
    if (poses != "all" && o.poses.empty()) throw gp::UsageError("--poses lists no pose", "--poses");

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    const gp::AvatarResult r = gp::make_avatar(spec, o);
    const auto t_write = std::chrono::steady_clock::now();

    gp::PoseSetManifest m;
    m.vertex_count = r.poses.V[0].rows();
    m.face_count = r.poses.F.rows();
    m.topology_sha256 = gp::topology_checksum(r.poses.F);
    m.reference = r.poses.reference;
    for (size_t i = 0; i < r.poses.names.size(); ++i) {
      gp::Mesh mesh;
      mesh.V = r.poses.V[i];
      mesh.F = r.poses.F;
      const std::string file = r.poses.names[i] + ".ply";
      gp::write_mesh(out.file(file), mesh);
      m.poses.push_back({r.poses.names[i], file, gp::sha256_file_hex(out.file(file)),
                         "make-avatar " + (spec_path.empty() ? std::string("default body") : spec_path)});
    }
    gp::write_pose_set_manifest(out.file("poses.json"), m);
    gp::write_json_file(out.file("skeleton.json"), gp::skeleton_json(r));
    const double write_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
    gp::OrderedJson timing;
    timing["schema"] = gp::schema_tag("timing", 1);
    timing["tool"] = "make-avatar";
    timing["units"] = "s";
    timing["fit"] = r.timing.fit;
    timing["polygonize"] = r.timing.polygonize;
    timing["simplify"] = r.timing.simplify;
    timing["project"] = r.timing.project;
    timing["measure"] = r.timing.measure;
    timing["check"] = r.timing.check;
    timing["skin"] = r.timing.skin;
    timing["pose"] = r.timing.pose;
    timing["build_total"] = r.timing.total;
    timing["write"] = write_seconds;
    gp::write_json_file(out.file("timing.json"), timing);
    gp::write_json_file(out.file("report.json"), gp::avatar_report(spec, o, r));
    out.commit();

    double worst = 0;
    for (const auto& g : r.girths) {
      worst = std::max(worst, std::abs(g.measured - g.target));
      std::ostringstream line;
      line.precision(4);
      line << "girth " << g.name << ": target " << g.target << " m, measured " << g.measured << " m";
      tool.log().detail(line.str());
    }
    for (size_t i = 0; i < r.poses.names.size(); ++i) {
      std::ostringstream line;
      line.precision(5);
      line << "pose " << r.poses.names[i] << ": volume " << r.volumes[i] << " m^3";
      tool.log().detail(line.str());
    }
    std::ostringstream msg;
    msg.precision(3);
    msg << r.poses.names.size() << " poses, " << m.vertex_count << " vertices, " << m.face_count
        << " triangles, largest girth error " << worst * 1000 << " mm, " << r.timing.total << " s";
    tool.log().info(msg.str());
    return 0;
  });
}
