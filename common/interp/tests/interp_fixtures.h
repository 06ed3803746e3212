#pragma once
// Procedural meshes and poses for the interpolation tests.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "io/mesh.h"
#include "mesh/measures.h"
#include "mesh/topology.h"
#include "pose/pose_set.h"
#include "testing/test_meshes.h"

namespace interp_test {

constexpr double kPi = 3.14159265358979323846;

inline double deg(double d) { return d * kPi / 180.0; }

inline Eigen::Matrix3d rot(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

inline gp::PoseSet make_pose_set(const Eigen::MatrixXi& F, const std::vector<Eigen::MatrixXd>& V,
                                 const std::vector<std::string>& names) {
  gp::PoseSet set;
  set.F = F;
  set.V = V;
  set.names = names;
  set.reference = names.front();
  return set;
}

// A body-like closed surface ("scarecrow"): a horizontal bar along x from
// -0.9 to 0.9 m whose middle (|x| < 0.15) is a thick torso (radius 0.15) and
// whose ends are thin arms (radius 0.05), with rounded ends, from a UV sphere
// (poles on the bar's axis). `rings` rows along the bar, `segments` around.
inline gp::Mesh make_scarecrow(int rings = 120, int segments = 24) {
  gp::Mesh m = gp::testing::make_uv_sphere(rings, segments, 1.0);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    const double s = m.V(v, 1);  // -1..1 along the bar
    const double x = 0.9 * s;
    const double u = std::clamp((std::abs(x) - 0.12) / 0.16, 0.0, 1.0);
    const double blend = u * u * (3 - 2 * u);
    const double r = 0.15 + (0.05 - 0.15) * blend;
    const double around = std::sqrt(std::max(0.0, 1.0 - s * s));
    const double scale = around > 0 ? r * std::pow(around, 0.35) / around : 0.0;
    m.V.row(v) = Eigen::RowVector3d(x, 1.2 + scale * m.V(v, 0), scale * m.V(v, 2));
  }
  m.F.col(1).swap(m.F.col(2));  // the axis swap above mirrors the surface: keep normals outward
  return m;
}

// Poses the scarecrow: each arm rotates about the z axis through its shoulder
// joint (x = +-0.32, y = 1.2, inside the thin arm) by `angle_deg` (positive =
// raised). Over the joint (|x| from 0.26 to 0.38) the angle, not the position, is blended, so that the
// joint bends without the volume loss of linear blend skinning. Mirror-symmetric.
inline Eigen::MatrixXd pose_scarecrow(const Eigen::MatrixXd& V_rest, double angle_deg) {
  Eigen::MatrixXd V = V_rest;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V_rest.row(v).transpose();
    const double side = p.x() >= 0 ? 1.0 : -1.0;
    const double u = std::clamp((std::abs(p.x()) - 0.26) / 0.12, 0.0, 1.0);
    const double w = u * u * (3 - 2 * u);
    const Eigen::Vector3d c(side * 0.32, 1.2, 0.0);
    V.row(v) = (c + rot(Eigen::Vector3d::UnitZ(), w * side * deg(angle_deg)) * (p - c)).transpose();
  }
  return V;
}

// A long thin open tube along +y (radius 0.05 m, length 2 m), `rows` rows of
// `around` vertices, twisted about its axis by total_deg * y / length.
inline Eigen::MatrixXd twist_tube(const Eigen::MatrixXd& V_rest, double total_deg, double length) {
  Eigen::MatrixXd V = V_rest;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const double a = deg(total_deg) * V_rest(v, 1) / length;
    V.row(v) = (rot(Eigen::Vector3d::UnitY(), a) * V_rest.row(v).transpose()).transpose();
  }
  return V;
}

// A chain of `links` rigid beads along +y: each bead an elliptic spheroid
// (semi-axes 0.05, 0.1, 0.03 m) from a UV sphere, touching the next bead at a
// single shared vertex on the y axis (its pole). One mesh, one vertex-connected
// component, `links` edge-connected parts.
inline gp::Mesh make_bead_chain(int links, int rings = 10, int segments = 12) {
  const gp::Mesh bead = gp::testing::make_uv_sphere(rings, segments, 1.0);
  const int nb = static_cast<int>(bead.V.rows());
  const int north = 0, south = nb - 1;  // poles of make_uv_sphere (+y, -y)
  std::vector<Eigen::RowVector3d> V;
  std::vector<Eigen::RowVector3i> F;
  int previous_north = -1;
  for (int k = 0; k < links; ++k) {
    std::vector<int> id(static_cast<size_t>(nb));
    for (int v = 0; v < nb; ++v) {
      if (v == south && previous_north >= 0) {
        id[static_cast<size_t>(v)] = previous_north;  // shared with the bead below
        continue;
      }
      id[static_cast<size_t>(v)] = static_cast<int>(V.size());
      V.emplace_back(0.05 * bead.V(v, 0), 0.1 + 0.2 * k + 0.1 * bead.V(v, 1), 0.03 * bead.V(v, 2));
    }
    for (int f = 0; f < bead.F.rows(); ++f)
      F.emplace_back(id[static_cast<size_t>(bead.F(f, 0))], id[static_cast<size_t>(bead.F(f, 1))],
                     id[static_cast<size_t>(bead.F(f, 2))]);
    previous_north = id[static_cast<size_t>(north)];
  }
  gp::Mesh m;
  m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (size_t i = 0; i < V.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = V[i];
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t i = 0; i < F.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = F[i];
  return m;
}

// Turns bead k of a chain made by make_bead_chain rigidly about the y axis by
// total_deg * k / (links - 1); shared poles lie on the axis and stay put.
inline Eigen::MatrixXd twist_chain(const Eigen::MatrixXd& V_rest, int links, double total_deg) {
  Eigen::MatrixXd V = V_rest;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const int k = std::min(links - 1, static_cast<int>(std::floor(V_rest(v, 1) / 0.2)));
    const double a = deg(total_deg) * k / (links - 1);
    V.row(v) = (rot(Eigen::Vector3d::UnitY(), a) * V_rest.row(v).transpose()).transpose();
  }
  return V;
}

inline Eigen::VectorXd lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  return gp::edge_lengths(V, gp::unique_edges(F));
}

inline double height(const Eigen::MatrixXd& V) {
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
}

}  // namespace interp_test
