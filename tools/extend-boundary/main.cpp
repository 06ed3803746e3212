// extend-boundary: tool T2. Extends one boundary loop of a garment along its
// axis (skirts, wide sleeves), pushes the extension clear of the body, and
// writes the updated garment.ply, garment.json and report.json into --out.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cli/tool.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/sha256.h"
#include "garment/design_body.h"
#include "garment/extend_boundary.h"
#include "io/mesh_io.h"
#include "spec/json_file.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  gp::Tool tool("extend-boundary", "Extend a garment boundary loop along its axis (extend-spec/1)");
  std::string garment_path, spec_path;
  auto& app = tool.app();
  app.add_option("garment", garment_path, "Garment file (garment.json, garment/1); its mesh is read from beside it")
      ->required();
  app.add_option("spec", spec_path, "Extension spec (JSON, schema extend-spec/1)")->required();
  std::string body_path;
  app.add_option("--body", body_path,
                 "Body in the design pose (poses.json or mesh), which the extension is pushed clear of "
                 "[default: the garment file's body source]");
  tool.add_common_options();

  return tool.run(argc, argv, [&] {
    const auto start = std::chrono::steady_clock::now();
    const gp::ExtendSpec spec = gp::read_extend_spec(spec_path);
    const gp::GarmentFile file = gp::read_garment_file(garment_path);
    const fs::path mesh_path = fs::path(garment_path).parent_path() / file.mesh_file;
    if (gp::sha256_file_hex(mesh_path) != file.mesh_sha256)
      throw gp::InputError("the garment mesh changed since its garment file was written (sha256 differs)",
                           mesh_path.string());
    const gp::MeshReadResult read = gp::read_mesh(mesh_path);

    const gp::DesignBody body = gp::load_design_body(file, garment_path, body_path);

    const gp::ExtendResult result = gp::extend_boundary(read.mesh, file, spec, &body);
    if (result.unpinned)
      tool.log().warning("loop '" + spec.loop + "' was pinned; the extended loop is no longer on the body and is unpinned");
    const gp::BodyClearanceResult& clearance = result.clearance;
    for (const gp::ClearancePlace& place : clearance.places) {
      char line[300];
      std::snprintf(line, sizeof(line),
                    "the extension met the body near body vertex %d (%.3f, %.3f, %.3f): pushed %s by up to %.1f mm%s",
                    place.body_vertex, place.center.x(), place.center.y(), place.center.z(),
                    place.side > 0 ? "along the garment normals" : "against the garment normals",
                    1e3 * place.largest_push, place.room ? "" : " (no room for the comfort offset there)");
      tool.log().info(line);
    }
    if (!clearance.clear()) {
      const auto& a = clearance.after;
      tool.log().warning("the garment still passes through the body: " + std::to_string(a.crossings()) +
                         " edge/triangle crossings, " + std::to_string(a.cloth_vertices_inside) +
                         " vertices inside (deepest " + std::to_string(1e3 * a.deepest_cloth_vertex) + " mm at vertex " +
                         std::to_string(a.deepest_cloth_vertex_id) + ")");
    }

    gp::StagedOutputDir out(tool.common().out_dir, tool.common().force);
    gp::write_mesh(out.file("garment.ply"), result.mesh);
    gp::GarmentFile updated = result.file;
    updated.mesh_file = "garment.ply";
    updated.mesh_sha256 = gp::sha256_file_hex(out.file("garment.ply"));
    gp::write_garment_file(out.file("garment.json"), updated);

    gp::OrderedJson report;
    report["schema"] = gp::schema_tag("extend-boundary-report", 1);
    report["options"] = {{"garment", garment_path},
                         {"spec", spec_path},
                         {"body", body_path},
                         {"threads", tool.common().threads},
                         {"effective_spec", gp::to_json(spec)}};
    report["inputs"] = {{"garment_sha256", gp::sha256_file_hex(garment_path)},
                        {"mesh_sha256", file.mesh_sha256},
                        {"spec_sha256", gp::sha256_file_hex(spec_path)}};
    report["extension"] = {{"loop", spec.loop},
                           {"centroid", {result.centroid[0], result.centroid[1], result.centroid[2]}},
                           {"axis", {result.axis[0], result.axis[1], result.axis[2]}},
                           {"distance", result.distance},
                           {"scale", result.scale},
                           {"old_girth", result.old_girth},
                           {"new_girth", result.new_girth},
                           {"unpinned", result.unpinned}};
    report["body_clearance"] = gp::to_json(clearance);
    report["counts"] = {{"garment_vertices", result.mesh.V.rows()},
                        {"garment_faces", result.mesh.F.rows()},
                        {"band_faces", result.band_faces},
                        {"band_flipped_faces", result.band_flipped_faces}};
    gp::OrderedJson timing;
    timing["schema"] = gp::schema_tag("timing", 1);
    timing["tool"] = "extend-boundary";
    timing["total_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    gp::write_json_file(out.file("timing.json"), timing);
    gp::write_json_file(out.file("report.json"), report);
    out.commit();
    tool.log().info("wrote " + tool.common().out_dir + " (loop '" + spec.loop + "' girth " +
                    std::to_string(result.new_girth) + " m, " + std::to_string(result.band_faces) +
                    " band triangles)");
    return 0;
  });
}
