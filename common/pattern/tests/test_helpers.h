#pragma once
// Meshes built by the pattern tests.
#include <vector>
#include <Eigen/Core>

#include "io/mesh.h"
#include "testing/test_meshes.h"

namespace gp::testing {

// Removes vertices no face uses (keeps the order of the others).
inline Mesh compact(const Eigen::MatrixXd& V, const std::vector<Eigen::Vector3i>& faces) {
  std::vector<int> map(static_cast<size_t>(V.rows()), -1);
  Mesh m;
  int n = 0;
  for (const auto& f : faces)
    for (int k = 0; k < 3; ++k)
      if (map[static_cast<size_t>(f[k])] < 0) map[static_cast<size_t>(f[k])] = 0;
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] == 0) map[i] = n++;
  m.V.resize(n, 3);
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) m.V.row(map[i]) = V.row(static_cast<int>(i));
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) m.F(static_cast<int>(i), k) = map[static_cast<size_t>(faces[i][k])];
  return m;
}

// Upper half (y > 0) of an icosphere: an open cap with a slightly jagged rim.
inline Mesh make_hemisphere(int levels, double radius) {
  const Mesh s = make_icosphere(levels, radius);
  std::vector<Eigen::Vector3i> faces;
  for (int f = 0; f < s.F.rows(); ++f) {
    const double y = (s.V(s.F(f, 0), 1) + s.V(s.F(f, 1), 1) + s.V(s.F(f, 2), 1)) / 3.0;
    if (y > 0.0) faces.emplace_back(s.F(f, 0), s.F(f, 1), s.F(f, 2));
  }
  return compact(s.V, faces);
}

}  // namespace gp::testing
