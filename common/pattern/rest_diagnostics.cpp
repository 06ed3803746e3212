#include "pattern/rest_diagnostics.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <Eigen/Dense>

#include "core/error.h"
#include "core/math.h"
#include "mesh/measures.h"
#include "mesh/principal_stretches.h"
#include "mesh/topology.h"

namespace gp {
namespace {

// Angle defects of the inner vertices (mesh/measures.h), 0 on the boundary.
std::vector<double> inner_angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                        const std::vector<char>& inner) {
  const Eigen::VectorXd all = angle_defects(V, F);
  std::vector<double> defect(static_cast<size_t>(V.rows()), 0.0);
  for (size_t v = 0; v < defect.size(); ++v)
    if (inner[v]) defect[v] = all(static_cast<Eigen::Index>(v));
  return defect;
}

// Corner matrix of face f in its own orthonormal frame (columns: corners 1, 2)
// and its unit normal; false for a degenerate face.
bool corners(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f, Eigen::Matrix2d& P, Eigen::Vector3d& n) {
  const Eigen::Vector3d e1 = (V.row(F(f, 1)) - V.row(F(f, 0))).transpose();
  const Eigen::Vector3d e2 = (V.row(F(f, 2)) - V.row(F(f, 0))).transpose();
  const Eigen::Vector3d c = e1.cross(e2);
  const double l1 = e1.norm(), a = c.norm();
  if (!(l1 > 0.0) || !(a > 1e-14 * std::max(e1.squaredNorm(), e2.squaredNorm())) || !std::isfinite(a)) return false;
  P << l1, e2.dot(e1) / l1, 0.0, a / l1;
  n = c / a;
  return true;
}

}  // namespace

RestShapeDiagnostics diagnose_rest_shape(const Eigen::MatrixXd& V_design, const Eigen::MatrixXd& V_rest,
                                         const Eigen::MatrixXi& F, double cone_angle) {
  if (V_design.rows() != V_rest.rows() || V_design.cols() != 3 || V_rest.cols() != 3)
    throw GeometryError("the rest shape and the designed garment differ in size");
  RestShapeDiagnostics d;
  d.cone_angle = cone_angle;
  const int m = static_cast<int>(F.rows());
  std::vector<double> growth(static_cast<size_t>(m), 1.0), design_area(static_cast<size_t>(m), 0.0);
  double area_design = 0.0, area_rest = 0.0, area_turned = 0.0;
  for (int f = 0; f < m; ++f) {
    Eigen::Matrix2d Pd, Pr;
    Eigen::Vector3d nd, nr;
    const bool ok_d = corners(V_design, F, f, Pd, nd), ok_r = corners(V_rest, F, f, Pr, nr);
    const double ad = ok_d ? 0.5 * Pd.determinant() : 0.0, ar = ok_r ? 0.5 * Pr.determinant() : 0.0;
    area_design += ad;
    area_rest += ar;
    design_area[static_cast<size_t>(f)] = ad;
    if (!ok_d || !ok_r) continue;
    growth[static_cast<size_t>(f)] = singular_values_2x2(Pr * Pd.inverse())(0);
    if (nd.dot(nr) < 0.0) {
      ++d.turned_faces;
      area_turned += ar;
    }
  }
  d.area_growth = area_design > 0.0 ? area_rest / area_design : 1.0;
  d.turned_area_fraction = area_rest > 0.0 ? area_turned / area_rest : 0.0;
  const Eigen::Map<const Eigen::VectorXd> growth_of(growth.data(), m), area_of(design_area.data(), m);
  if (m > 0) d.growth_p95 = area_weighted_percentile(growth_of, area_of, 0.95);
  d.growth_max = m > 0 ? growth_of.maxCoeff() : 1.0;

  std::vector<char> inner(static_cast<size_t>(V_rest.rows()), 1);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) inner[static_cast<size_t>(v)] = 0;
  const std::vector<double> K_rest = inner_angle_defects(V_rest, F, inner),
                            K_design = inner_angle_defects(V_design, F, inner);
  for (size_t v = 0; v < K_rest.size(); ++v) {
    d.abs_defect_sum += std::abs(K_rest[v]);
    d.abs_defect_sum_design += std::abs(K_design[v]);
    d.max_abs_defect = std::max(d.max_abs_defect, std::abs(K_rest[v]));
    if (std::abs(K_rest[v]) >= cone_angle) ++d.cone_points;
    if (std::abs(K_design[v]) >= cone_angle) ++d.cone_points_design;
  }
  return d;
}

InnerCones cone_points_inside_pieces(const Eigen::MatrixXd& V_design, const Eigen::MatrixXd& V_rest,
                                     const Eigen::MatrixXi& F, double cone_angle, const Eigen::MatrixXd& V_cut,
                                     const Eigen::MatrixXi& F_cut, double margin) {
  if (V_design.rows() != V_rest.rows() || V_design.cols() != 3 || V_rest.cols() != 3)
    throw GeometryError("the rest shape and the designed garment differ in size");
  // Boundary edges of the cut mesh: used by one face.
  std::vector<std::pair<int, int>> edges;
  for (int f = 0; f < F_cut.rows(); ++f)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::min(F_cut(f, k), F_cut(f, (k + 1) % 3)),
                                                   std::max(F_cut(f, k), F_cut(f, (k + 1) % 3)));
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<int, int>> boundary;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) boundary.push_back(edges[i]);
    i = j;
  }
  const auto inside = [&](const Eigen::Vector3d& p) {
    for (const auto& [a, b] : boundary) {
      const Eigen::Vector3d x = V_cut.row(a).transpose(), y = V_cut.row(b).transpose();
      const double len2 = (y - x).squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - x).dot(y - x) / len2, 0.0, 1.0) : 0.0;
      if ((x + t * (y - x) - p).norm() < margin) return false;
    }
    return true;
  };
  std::vector<char> inner(static_cast<size_t>(V_rest.rows()), 1);
  for (const auto& loop : boundary_loops(F))
    for (int v : loop) inner[static_cast<size_t>(v)] = 0;
  const std::vector<double> K_rest = inner_angle_defects(V_rest, F, inner),
                            K_design = inner_angle_defects(V_design, F, inner);
  InnerCones c;
  for (size_t v = 0; v < K_rest.size(); ++v) {
    const Eigen::Vector3d p = V_rest.row(static_cast<Eigen::Index>(v)).transpose();
    if (std::abs(K_rest[v]) >= cone_angle && inside(p)) ++c.rest;
    // The design's cones measured against the same cuts, at the same vertex.
    if (std::abs(K_design[v]) >= cone_angle && inside(p)) ++c.design;
  }
  return c;
}

}  // namespace gp
