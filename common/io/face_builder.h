#pragma once
// Collects polygon faces from a reader, checks their indices and splits
// polygons into triangles when asked. Shared by the OBJ, PLY and assimp readers
// so that they treat bad faces identically.
#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace gp {

class FaceBuilder {
 public:
  FaceBuilder(std::string file, bool triangulate) : file_(std::move(file)), triangulate_(triangulate) {}

  // Adds one face with its corners (0-based). `face_index` is the face's
  // number in the file and `where` how to name it in messages. Throws
  // GeometryError for fewer than three corners or an untriangulated polygon.
  // Returns how many triangles were added.
  int add(const std::vector<long long>& corners, long long face_index);

  // Checks every index against the vertex count (InputError naming the face
  // otherwise) and returns #F by 3; records a warning if polygons were split.
  Eigen::MatrixXi finish(long long vertex_count, std::vector<std::string>& warnings) const;

  // For per-face scalar fields: the file face that triangle t came from.
  const std::vector<long long>& source_face() const { return source_face_; }

 private:
  std::string file_;
  bool triangulate_;
  std::vector<long long> corners_;  // three per triangle
  std::vector<long long> source_face_;
  long long polygons_split_ = 0;
};

}  // namespace gp
