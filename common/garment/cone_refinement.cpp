#include "garment/cone_refinement.h"

#include <cmath>
#include <vector>

#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {

std::vector<char> border_vertices(const Eigen::MatrixXi& F, Eigen::Index n) {
  std::vector<char> border(static_cast<size_t>(n), 0);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) border[static_cast<size_t>(v)] = 1;
  return border;
}

std::vector<int> cone_ids(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, double angle_rad) {
  const std::vector<char> border = border_vertices(F, V.rows());
  const Eigen::VectorXd defect = angle_defects(V, F);
  std::vector<int> cones;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (!border[static_cast<size_t>(v)] && std::abs(defect[v]) >= angle_rad) cones.push_back(static_cast<int>(v));
  return cones;
}

}  // namespace

ConeRefinementResult refine_cones(Eigen::MatrixXd& V, Eigen::MatrixXi& F, double target_edge_length,
                                  const PointProjection& project, const ConeRefinementOptions& options) {
  ConeRefinementResult result;
  const double angle = options.cone_angle_deg * M_PI / 180.0;
  const Eigen::Index n_before = V.rows();
  std::vector<int> cones = cone_ids(V, F, angle);
  result.cones_before = static_cast<int>(cones.size());
  double length = target_edge_length;
  for (int round = 0; round < options.max_rounds && !cones.empty(); ++round) {
    // The faces within `rings` rings of a cone.
    const auto ring = vertex_neighbors(F, static_cast<int>(V.rows()));
    std::vector<char> near(static_cast<size_t>(V.rows()), 0);
    std::vector<int> front = cones;
    for (int v : front) near[static_cast<size_t>(v)] = 1;
    for (int r = 1; r < options.rings; ++r) {
      std::vector<int> next;
      for (int v : front)
        for (int w : ring[static_cast<size_t>(v)])
          if (!near[static_cast<size_t>(w)]) {
            near[static_cast<size_t>(w)] = 1;
            next.push_back(w);
          }
      front.swap(next);
    }
    std::vector<char> selected(static_cast<size_t>(F.rows()), 0);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) selected[static_cast<size_t>(f)] |= near[static_cast<size_t>(F(f, k))];

    length *= options.length_factor;
    RemeshOptions remesh;
    remesh.target_edge_length = length;
    remesh.iterations = options.remesh_iterations;
    const Eigen::MatrixXd V_old = V;
    Eigen::VectorXd no_values;
    const std::vector<int> origin = remesh_selected_faces(V, F, selected, remesh, no_values, 1.0);
    // The local remesh works on the flat facets of the old faces: its new
    // and moved vertices go back onto the surface (the patch's border and
    // the selection's border are kept, so border vertices did not move).
    const std::vector<char> border = border_vertices(F, V.rows());
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      if (border[static_cast<size_t>(v)]) continue;
      const int o = origin[static_cast<size_t>(v)];
      if (o >= 0 && V.row(v) == V_old.row(o)) continue;
      V.row(v) = project(V.row(v).transpose()).transpose();
    }
    ++result.rounds;
    result.finest_edge_length = length;
    cones = cone_ids(V, F, angle);
  }
  result.cones_after = static_cast<int>(cones.size());
  result.added_vertices = static_cast<int>(V.rows() - n_before);
  return result;
}

}  // namespace gp
