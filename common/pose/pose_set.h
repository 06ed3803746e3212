#pragma once
// A pose set: several meshes of one body with identical connectivity, and the
// manifest (poses.json, schema "pose-set/1") that register-check and
// make-avatar write and every later stage reads.
//
// poses.json:
//   {
//     "schema": "pose-set/1",
//     "units": "m", "up": "+y",
//     "vertex_count": 27578, "face_count": 55152,
//     "topology_sha256": "<sha256 of the triangle list, see topology_checksum>",
//     "reference": "apose",
//     "poses": [ { "name": "apose", "file": "apose.ply", "sha256": "<file digest>",
//                  "source": "<where it came from>" }, ... ]
//   }
// Files are relative to the manifest's folder. Pose names are unique and made
// of letters, digits, '-' and '_' (they name files and make targets).
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "spec/json_file.h"

namespace gp {

struct PoseEntry {
  std::string name;
  std::string file;    // relative to the manifest's folder
  std::string sha256;  // of the file's bytes
  std::string source;  // original input this pose was normalized from (free text)
};

struct PoseSetManifest {
  std::string units = "m";
  std::string up = "+y";
  long long vertex_count = 0;
  long long face_count = 0;
  std::string topology_sha256;
  std::string reference;
  std::vector<PoseEntry> poses;
};

// A loaded pose set: one vertex matrix per pose over one shared triangle list.
struct PoseSet {
  std::vector<std::string> names;
  std::vector<Eigen::MatrixXd> V;  // per pose, #V by 3, metres, +y up
  Eigen::MatrixXi F;               // #F by 3, shared by all poses
  std::string reference;           // name of the reference pose

  // Index of the pose called `name`; SpecError naming `where` if there is none.
  int index_of(const std::string& name, const std::string& where) const;
};

// Digest of a triangle list (its int32 little-endian bytes, row by row), so that
// stages can tell that two files share connectivity without comparing them.
std::string topology_checksum(const Eigen::MatrixXi& F);

// Digest of a pose's vertex positions (#V by 3, metres), each rounded to a whole micrometre (int64,
// little-endian, row by row): the same body in the same pose gives the same digest whatever file and
// units it came from (a centimetre scan converted to metres differs by about 1e-16 m, which crosses
// a rounding boundary for about one coordinate in 10^9), while any other body differs.
std::string vertex_checksum(const Eigen::MatrixXd& V);

// True for names made of [A-Za-z0-9_-], 1 to 64 characters.
bool is_valid_pose_name(const std::string& name);

OrderedJson to_json(const PoseSetManifest& manifest);
// Strict reading: SpecError naming the field for a wrong schema, unknown or
// mistyped field, duplicate or invalid pose name.
PoseSetManifest read_pose_set_manifest(const std::filesystem::path& path);
void write_pose_set_manifest(const std::filesystem::path& path, const PoseSetManifest& manifest);

// Reads the manifest and every pose it lists. Checks each file's checksum
// (InputError if it changed), that all poses share the manifest's
// connectivity and that no pose spans more than 5 m (a body in other units
// than metres; GeometryError otherwise).
PoseSet load_pose_set(const std::filesystem::path& manifest_path);

// Builds a pose set straight from mesh files (name = file stem); the first is
// the reference. GeometryError names the file whose connectivity differs.
PoseSet load_pose_files(const std::vector<std::filesystem::path>& files);

}  // namespace gp
