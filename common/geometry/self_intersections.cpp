#include "geometry/self_intersections.h"

#include <algorithm>
#include <iterator>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "core/error.h"

namespace gp {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using FaceIndex = SurfaceMesh::Face_index;

}  // namespace

SelfIntersectionResult self_intersections(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                          int max_pairs) {
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> vid(static_cast<size_t>(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    vid[i] = mesh.add_vertex(Kernel::Point_3(V(i, 0), V(i, 1), V(i, 2)));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const FaceIndex face = mesh.add_face(vid[F(f, 0)], vid[F(f, 1)], vid[F(f, 2)]);
    if (face == SurfaceMesh::null_face())
      throw GeometryError("cannot build a manifold surface for the self-intersection test",
                          "face " + std::to_string(f));
  }
  std::vector<std::pair<FaceIndex, FaceIndex>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
  SelfIntersectionResult result;
  result.pair_count = static_cast<long long>(pairs.size());
  // Faces were added in order, so a face index equals its row in F.
  std::vector<std::pair<int, int>> all;
  all.reserve(pairs.size());
  for (const auto& [a, b] : pairs)
    all.push_back(std::minmax(static_cast<int>(a.idx()), static_cast<int>(b.idx())));
  std::sort(all.begin(), all.end());
  all.resize(std::min(all.size(), static_cast<size_t>(std::max(0, max_pairs))));
  result.first_pairs = std::move(all);
  return result;
}

}  // namespace gp
