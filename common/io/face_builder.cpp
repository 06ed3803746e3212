#include "io/face_builder.h"

#include "core/error.h"

namespace gp {

int FaceBuilder::add(const std::vector<long long>& corners, long long face_index) {
  const std::string where = file_ + ": face " + std::to_string(face_index);
  if (corners.size() < 3)
    throw GeometryError("face has " + std::to_string(corners.size()) + " corners; at least 3 needed",
                        where);
  if (corners.size() > 3 && !triangulate_)
    throw GeometryError("face has " + std::to_string(corners.size()) +
                            " corners; the pipeline needs triangles (pass --triangulate to split polygons)",
                        where);
  if (corners.size() > 3) ++polygons_split_;
  // Fan triangulation keeps the polygon's orientation.
  for (size_t k = 1; k + 1 < corners.size(); ++k) {
    corners_.push_back(corners[0]);
    corners_.push_back(corners[k]);
    corners_.push_back(corners[k + 1]);
    source_face_.push_back(face_index);
  }
  return static_cast<int>(corners.size()) - 2;
}

Eigen::MatrixXi FaceBuilder::finish(long long vertex_count, std::vector<std::string>& warnings) const {
  const long long nf = static_cast<long long>(source_face_.size());
  Eigen::MatrixXi F(nf, 3);
  for (long long t = 0; t < nf; ++t) {
    for (int c = 0; c < 3; ++c) {
      const long long v = corners_[3 * t + c];
      if (v < 0 || v >= vertex_count)
        throw InputError("vertex index " + std::to_string(v) + " out of range [0, " +
                             std::to_string(vertex_count) + ")",
                         file_ + ": face " + std::to_string(source_face_[t]));
      F(t, c) = static_cast<int>(v);
    }
  }
  if (polygons_split_ > 0)
    warnings.push_back(file_ + ": split " + std::to_string(polygons_split_) +
                       " polygons into triangles (fan triangulation)");
  return F;
}

}  // namespace gp
