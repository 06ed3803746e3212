#include "garment/remesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/math.h"
#include "garment/surface_point.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using CgalMesh = CGAL::Surface_mesh<Point>;
using VertexIndex = CgalMesh::Vertex_index;
using FaceIndex = CgalMesh::Face_index;
namespace PMP = CGAL::Polygon_mesh_processing;

CgalMesh to_cgal(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  CgalMesh mesh;
  for (Eigen::Index v = 0; v < V.rows(); ++v) mesh.add_vertex(Point(V(v, 0), V(v, 1), V(v, 2)));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const FaceIndex face = mesh.add_face(VertexIndex(F(f, 0)), VertexIndex(F(f, 1)), VertexIndex(F(f, 2)));
    if (face == CgalMesh::null_face())
      throw GeometryError("cannot remesh: triangle " + std::to_string(f) +
                          " makes the patch non-manifold");
  }
  return mesh;
}

void from_cgal(CgalMesh& mesh, Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  mesh.collect_garbage();
  V.resize(static_cast<Eigen::Index>(mesh.number_of_vertices()), 3);
  for (VertexIndex v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    V.row(static_cast<Eigen::Index>(v.idx())) << p.x(), p.y(), p.z();
  }
  F.resize(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  for (FaceIndex f : mesh.faces()) {
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      F(static_cast<Eigen::Index>(f.idx()), k++) = static_cast<int>(v.idx());
  }
}

Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& x, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// Keeps border vertices on the garment's boundary curves and every other vertex
// on the cut body surface; CGAL calls it after each relaxation.
struct CurveAndSurfaceProjection {
  const CgalMesh* mesh;
  const SurfaceLocator* surface;
  const std::vector<Eigen::MatrixXd>* curves;
  const PointProjection* interior;
  Point operator()(VertexIndex v) const {
    const Point& p = mesh->point(v);
    const Eigen::Vector3d x(p.x(), p.y(), p.z());
    Eigen::Vector3d best = x;
    if (mesh->is_border(v)) {
      double best_d2 = std::numeric_limits<double>::infinity();
      for (const auto& P : *curves)
        for (Eigen::Index i = 0; i < P.rows(); ++i) {
          const Eigen::Vector3d c = closest_on_segment(x, P.row(i), P.row((i + 1) % P.rows()));
          const double d2 = (c - x).squaredNorm();
          if (d2 < best_d2) {
            best_d2 = d2;
            best = c;
          }
        }
    } else {
      best = *interior ? (*interior)(x) : surface->closest(x).point;
    }
    return Point(best[0], best[1], best[2]);
  }
};

}  // namespace

void remesh_patch(Eigen::MatrixXd& V, Eigen::MatrixXi& F,
                  const std::vector<Eigen::MatrixXd>& boundary_curves, const RemeshOptions& options,
                  const PointProjection& project_interior) {
  if (!(options.target_edge_length > 0)) throw GeometryError("remeshing needs a positive edge length");
  CgalMesh mesh = to_cgal(V, F);
  const SurfaceLocator surface(V, F);
  const CurveAndSurfaceProjection project{&mesh, &surface, &boundary_curves, &project_interior};
  PMP::isotropic_remeshing(
      faces(mesh), options.target_edge_length, mesh,
      CGAL::parameters::number_of_iterations(static_cast<unsigned>(options.iterations))
          .number_of_relaxation_steps(static_cast<unsigned>(options.relaxation_steps))
          .protect_constraints(false)
          .relax_constraints(false)
          .projection_functor(project));
  // The last relaxation leaves border vertices where the 1D smoothing put
  // them; one more projection puts them exactly on the curves.
  for (VertexIndex v : mesh.vertices())
    if (mesh.is_border(v)) mesh.point(v) = project(v);
  from_cgal(mesh, V, F);

  // CGAL leaves a few slivers where an interior vertex sits next to a border
  // vertex and collapsing their edge would make a too long one. Some rounds of
  // Laplacian smoothing of the interior vertices, each projected back onto the
  // surface, open them up without touching the boundary.
  const auto ring = vertex_neighbors(F, static_cast<int>(V.rows()));
  std::vector<char> border(static_cast<size_t>(V.rows()), 0);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) border[static_cast<size_t>(v)] = 1;
  for (int round = 0; round < options.final_smoothing_rounds; ++round) {
    Eigen::MatrixXd next = V;
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      if (border[static_cast<size_t>(v)] || ring[static_cast<size_t>(v)].empty()) continue;
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int w : ring[static_cast<size_t>(v)]) c += V.row(w).transpose();
      c /= static_cast<double>(ring[static_cast<size_t>(v)].size());
      next.row(v) = (project_interior ? project_interior(c) : surface.closest(c).point).transpose();
    }
    V = next;
  }
}

std::vector<int> remesh_selected_faces(Eigen::MatrixXd& V, Eigen::MatrixXi& F,
                                       const std::vector<char>& face_selected,
                                       const RemeshOptions& options, Eigen::VectorXd& face_values,
                                       double new_face_value) {
  if (!(options.target_edge_length > 0)) throw GeometryError("remeshing needs a positive edge length");
  const Eigen::Index n_old = V.rows();
  CgalMesh mesh = to_cgal(V, F);
  auto old_id = mesh.add_property_map<VertexIndex, int>("v:old_id", -1).first;
  for (VertexIndex v : mesh.vertices()) old_id[v] = static_cast<int>(v.idx());
  auto value = mesh.add_property_map<FaceIndex, double>("f:value", new_face_value).first;
  auto old_face = mesh.add_property_map<FaceIndex, int>("f:old_id", -1).first;
  for (FaceIndex f : mesh.faces()) {
    if (face_values.size() == F.rows()) value[f] = face_values[static_cast<Eigen::Index>(f.idx())];
    old_face[f] = static_cast<int>(f.idx());
  }
  std::vector<FaceIndex> selected;
  for (FaceIndex f : mesh.faces())
    if (face_selected[f.idx()]) selected.push_back(f);
  auto constrained = mesh.add_property_map<CgalMesh::Edge_index, bool>("e:constrained", false).first;
  for (auto e : mesh.edges()) {
    const auto h = mesh.halfedge(e);
    const FaceIndex f0 = mesh.face(h), f1 = mesh.face(mesh.opposite(h));
    const bool s0 = f0 != CgalMesh::null_face() && face_selected[f0.idx()];
    const bool s1 = f1 != CgalMesh::null_face() && face_selected[f1.idx()];
    if (s0 != s1 || (mesh.is_border(e) && (s0 || s1))) constrained[e] = true;
  }
  PMP::isotropic_remeshing(
      selected, options.target_edge_length, mesh,
      CGAL::parameters::number_of_iterations(static_cast<unsigned>(options.iterations))
          .number_of_relaxation_steps(static_cast<unsigned>(options.relaxation_steps))
          .edge_is_constrained_map(constrained)
          .protect_constraints(true));
  mesh.collect_garbage();
  // Vertices in the order: untouched old ones (by old id), then the others by
  // their CGAL index; faces: old unselected faces in old order, then the rest.
  std::vector<std::pair<long long, int>> vorder;
  for (VertexIndex v : mesh.vertices())
    vorder.push_back({old_id[v] >= 0 ? old_id[v] : n_old + static_cast<long long>(v.idx()),
                      static_cast<int>(v.idx())});
  std::sort(vorder.begin(), vorder.end());
  std::vector<int> new_id(mesh.number_of_vertices());
  std::vector<int> origin;
  Eigen::MatrixXd V_new(static_cast<Eigen::Index>(vorder.size()), 3);
  for (size_t i = 0; i < vorder.size(); ++i) {
    const VertexIndex v(static_cast<CgalMesh::size_type>(vorder[i].second));
    new_id[vorder[i].second] = static_cast<int>(i);
    const Point& p = mesh.point(v);
    V_new.row(static_cast<Eigen::Index>(i)) << p.x(), p.y(), p.z();
    origin.push_back(old_id[v]);
  }
  std::vector<std::pair<long long, int>> forder;
  const long long n_faces_old = F.rows();
  for (FaceIndex f : mesh.faces()) {
    const int of = old_face[f];
    const bool kept = of >= 0 && !face_selected[static_cast<size_t>(of)];
    forder.push_back({kept ? of : n_faces_old + static_cast<long long>(f.idx()), static_cast<int>(f.idx())});
  }
  std::sort(forder.begin(), forder.end());
  Eigen::MatrixXi F_new(static_cast<Eigen::Index>(forder.size()), 3);
  Eigen::VectorXd values(static_cast<Eigen::Index>(forder.size()));
  for (size_t i = 0; i < forder.size(); ++i) {
    const FaceIndex f(static_cast<CgalMesh::size_type>(forder[i].second));
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      F_new(static_cast<Eigen::Index>(i), k++) = new_id[v.idx()];
    values[static_cast<Eigen::Index>(i)] = value[f];
  }
  V = V_new;
  F = F_new;
  face_values = values;
  return origin;
}

MeshQuality measure_quality(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                            double target_edge_length) {
  MeshQuality q;
  q.vertex_count = static_cast<int>(V.rows());
  q.face_count = static_cast<int>(F.rows());
  if (F.rows() == 0) return q;
  q.min_angle_deg = 180.0;
  int good = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    double smallest = 180.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = V.row(F(f, k)), b = V.row(F(f, (k + 1) % 3)), c = V.row(F(f, (k + 2) % 3));
      const Eigen::Vector3d u = b - a, w = c - a;
      const double angle = gp::math::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / M_PI;
      smallest = std::min(smallest, angle);
    }
    q.min_angle_deg = std::min(q.min_angle_deg, smallest);
    if (smallest > 20.0) ++good;
    if (smallest < 5.0) ++q.faces_min_angle_under_5;
  }
  std::vector<char> inner(static_cast<size_t>(V.rows()), 1);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) inner[static_cast<size_t>(v)] = 0;
  const Eigen::VectorXd defect = angle_defects(V, F);
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!inner[static_cast<size_t>(v)]) continue;
    const double k = std::abs(defect[v]) * 180.0 / M_PI;
    q.abs_angle_defect_sum += std::abs(defect[v]);
    q.max_abs_angle_defect_deg = std::max(q.max_abs_angle_defect_deg, k);
    if (k >= kConeDefectDeg) ++q.cone_vertices;
  }
  q.fraction_min_angle_over_20 = static_cast<double>(good) / static_cast<double>(F.rows());
  const Eigen::MatrixXi E = unique_edges(F);
  double sum = 0.0;
  int within = 0;
  q.min_edge_ratio = std::numeric_limits<double>::infinity();
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const double len = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
    sum += len;
    const double ratio = len / target_edge_length;
    q.min_edge_ratio = std::min(q.min_edge_ratio, ratio);
    q.max_edge_ratio = std::max(q.max_edge_ratio, ratio);
    if (std::abs(ratio - 1.0) <= 0.3) ++within;
  }
  q.mean_edge_length = sum / static_cast<double>(E.rows());
  q.fraction_edges_within_30 = static_cast<double>(within) / static_cast<double>(E.rows());
  return q;
}

}  // namespace gp
