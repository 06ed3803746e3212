#include "geometry/self_intersections.h"

#include <algorithm>
#include <iterator>
#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "core/error.h"

namespace gp {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using FaceIndex = SurfaceMesh::Face_index;

// Faces are added in order, so a CGAL face index equals its row in F.
SurfaceMesh to_surface_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
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
  return mesh;
}

std::vector<std::pair<int, int>> intersecting_pairs(const Eigen::MatrixXd& V,
                                                    const Eigen::MatrixXi& F) {
  const SurfaceMesh mesh = to_surface_mesh(V, F);
  std::vector<std::pair<FaceIndex, FaceIndex>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
  std::vector<std::pair<int, int>> ids;
  ids.reserve(pairs.size());
  for (const auto& [a, b] : pairs)
    ids.push_back(std::minmax(static_cast<int>(a.idx()), static_cast<int>(b.idx())));
  std::sort(ids.begin(), ids.end());
  return ids;
}

}  // namespace

SelfIntersectionResult self_intersections(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                          int max_pairs) {
  std::vector<std::pair<int, int>> all = intersecting_pairs(V, F);
  SelfIntersectionResult result;
  result.pair_count = static_cast<long long>(all.size());
  all.resize(std::min(all.size(), static_cast<size_t>(std::max(0, max_pairs))));
  result.first_pairs = std::move(all);
  return result;
}

std::vector<int> self_intersecting_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  std::vector<int> ids;
  for (const auto& [a, b] : intersecting_pairs(V, F)) {
    ids.push_back(a);
    ids.push_back(b);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

bool has_self_intersection(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return CGAL::Polygon_mesh_processing::does_self_intersect(to_surface_mesh(V, F));
}

}  // namespace gp
