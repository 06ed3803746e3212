#include "pose/pose_set.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>

#include "core/error.h"
#include "core/sha256.h"
#include "io/mesh_io.h"
#include "spec/spec_object.h"

namespace gp {

int PoseSet::index_of(const std::string& name, const std::string& where) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  std::string known;
  for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
  throw SpecError("unknown pose '" + name + "' (the pose set has: " + known + ")", where);
}

std::string topology_checksum(const Eigen::MatrixXi& F) {
  std::string bytes;
  bytes.reserve(static_cast<size_t>(F.rows()) * 12);
  for (Eigen::Index t = 0; t < F.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = static_cast<uint32_t>(F(t, k));
      for (int b = 0; b < 4; ++b) bytes.push_back(static_cast<char>((v >> (8 * b)) & 0xff));
    }
  return sha256_hex(bytes);
}

std::string vertex_checksum(const Eigen::MatrixXd& V) {
  std::string bytes;
  bytes.reserve(static_cast<size_t>(V.rows()) * 24);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      // Non-finite or absurd coordinates (no body) all hash as the largest value.
      const double um = V(i, k) * 1e6;
      const int64_t q = std::abs(um) < 9e18 ? static_cast<int64_t>(std::llround(um)) : INT64_MAX;
      const uint64_t bits = static_cast<uint64_t>(q);
      for (int b = 0; b < 8; ++b) bytes.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
    }
  return sha256_hex(bytes);
}

bool is_valid_pose_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

OrderedJson to_json(const PoseSetManifest& m) {
  OrderedJson j;
  j["schema"] = schema_tag("pose-set", 1);
  j["units"] = m.units;
  j["up"] = m.up;
  j["vertex_count"] = m.vertex_count;
  j["face_count"] = m.face_count;
  j["topology_sha256"] = m.topology_sha256;
  j["reference"] = m.reference;
  j["poses"] = OrderedJson::array();
  for (const PoseEntry& p : m.poses) {
    OrderedJson e;
    e["name"] = p.name;
    e["file"] = p.file;
    e["sha256"] = p.sha256;
    e["source"] = p.source;
    j["poses"].push_back(e);
  }
  return j;
}

PoseSetManifest read_pose_set_manifest(const std::filesystem::path& path) {
  const std::string file = path.string();
  const Json j = read_json_file(path);
  check_schema(j, "pose-set", {1}, file);
  SpecObject root(j, file);
  root.allow("schema");
  PoseSetManifest m;
  m.units = root.choice("units", "m", {"m"});
  m.up = root.choice("up", "+y", {"+y"});
  m.vertex_count = root.required_integer("vertex_count", Range::positive());
  m.face_count = root.required_integer("face_count", Range::positive());
  m.topology_sha256 = root.required_string("topology_sha256");
  m.reference = root.required_string("reference");
  SpecArray poses = root.array("poses");
  if (poses.empty()) throw SpecError("a pose set needs at least one pose", root.where("poses"));
  std::set<std::string> seen;
  for (size_t i = 0; i < poses.size(); ++i) {
    SpecObject p = poses.object(i);
    PoseEntry e;
    e.name = p.required_string("name");
    if (!is_valid_pose_name(e.name))
      throw SpecError("pose name '" + e.name + "' must be 1-64 letters, digits, '-' or '_'",
                      p.where("name"));
    if (!seen.insert(e.name).second)
      throw SpecError("duplicate pose name '" + e.name + "'", p.where("name"));
    e.file = p.required_string("file");
    e.sha256 = p.string("sha256", "");
    e.source = p.string("source", "");
    p.finish();
    m.poses.push_back(e);
  }
  if (!seen.count(m.reference))
    throw SpecError("reference pose '" + m.reference + "' is not among the poses", root.where("reference"));
  root.finish();
  return m;
}

void write_pose_set_manifest(const std::filesystem::path& path, const PoseSetManifest& manifest) {
  write_json_file(path, to_json(manifest));
}

PoseSet load_pose_set(const std::filesystem::path& manifest_path) {
  const PoseSetManifest m = read_pose_set_manifest(manifest_path);
  const std::filesystem::path dir = manifest_path.parent_path();
  PoseSet set;
  set.reference = m.reference;
  for (const PoseEntry& e : m.poses) {
    const std::filesystem::path file = dir / e.file;
    if (!e.sha256.empty() && sha256_file_hex(file) != e.sha256)
      throw InputError("file changed since the manifest was written (checksum differs); rerun register-check",
                       file.string());
    Mesh mesh = read_mesh(file).mesh;
    if (mesh.V.rows() != m.vertex_count || mesh.F.rows() != m.face_count ||
        topology_checksum(mesh.F) != m.topology_sha256)
      throw GeometryError("pose does not have the manifest's connectivity (" +
                              std::to_string(mesh.V.rows()) + " vertices, " +
                              std::to_string(mesh.F.rows()) + " faces)",
                          file.string());
    // The manifest holds metres only ("units": "m"); a hand-written one over
    // a scan in centimetres or millimetres would otherwise load as a body
    // 100 or 1000 times too large, which later stages report only as a
    // numerical failure (simulate-adapt: pins jumping at 20 m/s and more).
    // No body or test scene spans more than kMaxExtent metres.
    constexpr double kMaxExtent = 5.0;
    const double extent = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).maxCoeff();
    if (!(extent <= kMaxExtent))
      throw GeometryError("pose '" + e.name + "' spans " + std::to_string(extent) +
                              " units, but pose sets are in metres (a body in centimetres or "
                              "millimetres? register-check converts units)",
                          file.string());
    if (set.names.empty()) set.F = mesh.F;
    set.names.push_back(e.name);
    set.V.push_back(std::move(mesh.V));
  }
  return set;
}

PoseSet load_pose_files(const std::vector<std::filesystem::path>& files) {
  if (files.empty()) throw UsageError("no pose files given");
  PoseSet set;
  std::set<std::string> seen;
  for (const auto& file : files) {
    Mesh mesh = read_mesh(file).mesh;
    const std::string name = file.stem().string();
    if (!seen.insert(name).second)
      throw UsageError("two pose files share the name '" + name + "'", file.string());
    if (set.names.empty()) {
      set.F = mesh.F;
      set.reference = name;
    } else if (mesh.V.rows() != set.V[0].rows() || mesh.F.rows() != set.F.rows() || mesh.F != set.F) {
      throw GeometryError("poses not in correspondence: connectivity differs from '" + set.names[0] +
                              "' (run register-check)",
                          file.string());
    }
    set.names.push_back(name);
    set.V.push_back(std::move(mesh.V));
  }
  return set;
}

}  // namespace gp
