#include "avatar/body_checks.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "mesh/topology.h"

namespace gp {

void check_closed_genus0(const Eigen::MatrixXi& F, const std::string& what) {
  if (F.rows() == 0) throw GeometryError(what + " has no triangles");
  // Every directed edge must appear once and its reverse once: closed,
  // manifold and consistently oriented in one test.
  std::vector<std::pair<int, int>> directed;
  directed.reserve(static_cast<size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) directed.emplace_back(F(f, k), F(f, (k + 1) % 3));
  std::sort(directed.begin(), directed.end());
  for (size_t i = 0; i < directed.size(); ++i) {
    const auto& e = directed[i];
    auto name = [&] { return "(" + std::to_string(e.first) + ", " + std::to_string(e.second) + ")"; };
    if (i + 1 < directed.size() && directed[i + 1] == e)
      throw GeometryError(what + ": edge " + name() + " is used twice in the same direction");
    if (!std::binary_search(directed.begin(), directed.end(), std::make_pair(e.second, e.first)))
      throw GeometryError(what + ": edge " + name() + " is a boundary edge");
  }
  Eigen::VectorXi comp;
  const int n = face_components(F, comp);
  if (n != 1) throw GeometryError(what + " has " + std::to_string(n) + " components, expected 1");
  const int chi = euler_characteristic(F);
  if (chi != 2)
    throw GeometryError(what + " has Euler characteristic " + std::to_string(chi) +
                        ", expected 2 (a sphere)");
}

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

SurfaceMesh to_surface_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> vid(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    vid[i] = sm.add_vertex(Kernel::Point_3(V(i, 0), V(i, 1), V(i, 2)));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (sm.add_face(vid[F(f, 0)], vid[F(f, 1)], vid[F(f, 2)]) == SurfaceMesh::null_face())
      throw GeometryError("mesh is not an oriented 2-manifold (face " + std::to_string(f) + ")");
  return sm;
}
}  // namespace

bool has_self_intersection(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return CGAL::Polygon_mesh_processing::does_self_intersect(to_surface_mesh(V, F));
}

std::vector<int> self_intersecting_faces(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  const SurfaceMesh sm = to_surface_mesh(V, F);
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
  std::vector<int> ids;
  for (const auto& p : pairs) {
    ids.push_back(static_cast<int>(p.first.idx()));
    ids.push_back(static_cast<int>(p.second.idx()));
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace gp
