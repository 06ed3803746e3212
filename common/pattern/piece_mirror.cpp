#include "pattern/piece_mirror.h"

#include <map>

#include <Eigen/Geometry>

#include "garment/surface_point.h"
#include "mesh/measures.h"

namespace gp {

PieceMirror mirror_pieces(const Pattern& pattern, double min_overlap) {
  const PatternMesh& mesh = pattern.mesh;
  PieceMirror mirror;
  mirror.plane_x = area_centroid(mesh.rest_V, mesh.rest_F).x();
  const size_t n = pattern.pieces.size();
  mirror.partner.assign(n, -1);
  if (n == 0 || mesh.F.rows() == 0) return mirror;
  const SurfaceLocator locator(mesh.V, mesh.F);
  // shared[c][d]: area of piece c whose mirror image lies on piece d.
  std::vector<std::map<int, double>> shared(n);
  std::vector<double> area(n, 0.0);
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
    const double w = 0.5 * (b - a).cross(c - a).norm();
    const int piece = pattern.piece_of_face[static_cast<size_t>(f)];
    const int image = pattern.piece_of_face[static_cast<size_t>(locator.closest(mirror.reflect((a + b + c) / 3.0)).at.face)];
    shared[static_cast<size_t>(piece)][image] += w;
    area[static_cast<size_t>(piece)] += w;
  }
  std::vector<int> best(n, -1);
  for (size_t c = 0; c < n; ++c) {
    double most = 0.0;
    for (const auto& [d, w] : shared[c])
      if (w > most) most = w, best[c] = d;  // ties: the lower index (map order)
    if (!(most >= min_overlap * area[c])) best[c] = -1;
  }
  for (size_t c = 0; c < n; ++c)
    if (best[c] >= 0 && best[static_cast<size_t>(best[c])] == static_cast<int>(c)) mirror.partner[c] = best[c];
  return mirror;
}

}  // namespace gp
