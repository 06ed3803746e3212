#include "cloth/cloth_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include <Eigen/Dense>

#include "core/error.h"

namespace gp::cloth {
namespace {

Eigen::Matrix3d triangle_positions(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int f) {
  Eigen::Matrix3d X;
  for (int k = 0; k < 3; ++k) X.col(k) = V.row(F(f, k)).transpose();
  return X;
}

Eigen::Matrix<double, 3, 4> stencil_positions(const Eigen::MatrixXd& V, const Eigen::Vector4i& ids) {
  Eigen::Matrix<double, 3, 4> X;
  for (int k = 0; k < 4; ++k) X.col(k) = V.row(ids(k)).transpose();
  return X;
}

// Per-triangle rest frames, total area and lumped masses (a third of each
// triangle's mass to each corner) into `rest`, whose triangles are sized and
// masses zeroed by the caller.
void set_triangles_and_masses(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                              const ClothParameters& params, ClothRestState& rest) {
  const double ratio = weft_ratio(params);
  for (int f = 0; f < F.rows(); ++f) {
    try {
      rest.triangles[f] = triangle_rest(triangle_positions(V_rest, F, f), params.material_direction,
                                        grain_angle(params, f, F.rows()));
    } catch (const GeometryError& e) {
      throw GeometryError(e.what(), "face " + std::to_string(f));
    }
    rest.triangles[f].weft_ratio = ratio;
    const double A = rest.triangles[f].area;
    rest.total_area += A;
    for (int k = 0; k < 3; ++k) rest.masses(F(f, k)) += params.density * A / 3.0;
  }
}

}  // namespace

double weft_ratio(const ClothParameters& params) {
  if (!(params.k_stretch_weft >= 0.0) || !(params.k_stretch >= 0.0)) {
    throw UsageError("stretch stiffnesses must be non-negative");
  }
  if (params.k_stretch_weft == params.k_stretch) return 1.0;
  if (!(params.k_stretch > 0.0)) throw UsageError("a weft stiffness needs a positive warp stiffness");
  return params.k_stretch_weft / params.k_stretch;
}

double grain_angle(const ClothParameters& params, int f, long face_count) {
  if (params.grain_angles.empty()) return 0.0;
  if (static_cast<long>(params.grain_angles.size()) != face_count) {
    throw UsageError("grain angles must be one per face (" + std::to_string(params.grain_angles.size()) + " for " +
                     std::to_string(face_count) + " faces)");
  }
  return params.grain_angles[f];
}

ClothRestState build_rest_state(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                                const ClothParameters& params) {
  const int n = static_cast<int>(V_rest.rows());
  if (V_rest.cols() != 3 || F.cols() != 3) throw InputError("cloth mesh must be #V by 3 and #F by 3");
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (F(f, k) < 0 || F(f, k) >= n) {
        throw InputError("vertex id out of range", "face " + std::to_string(f));
      }
    }
  }
  ClothRestState rest;
  rest.triangles.resize(F.rows());
  rest.masses = Eigen::VectorXd::Zero(n);
  set_triangles_and_masses(V_rest, F, params, rest);

  // Interior edges: exactly two faces; (a, b) in the first face's order.
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edge_faces;  // -> (face, corner opposite)
  for (int f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back({f, k});
    }
  }
  std::vector<Eigen::Triplet<double>> triplets;
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 2) continue;
    const int f0 = faces[0].first, k0 = faces[0].second;
    const int f1 = faces[1].first, k1 = faces[1].second;
    BendingStencil s;
    s.vertex_ids = Eigen::Vector4i(F(f0, (k0 + 1) % 3), F(f0, (k0 + 2) % 3), F(f0, k0), F(f1, k1));
    try {
      const BendingStencil w = bending_stencil(stencil_positions(V_rest, s.vertex_ids));
      s.K = w.K;
      s.coefficient = w.coefficient;
    } catch (const GeometryError& e) {
      throw GeometryError(e.what(), "faces " + std::to_string(f0) + " and " + std::to_string(f1));
    }
    rest.stencils.push_back(s);
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        triplets.emplace_back(s.vertex_ids(i), s.vertex_ids(j), s.coefficient * s.K(i) * s.K(j));
      }
    }
  }
  rest.Q.resize(n, n);
  rest.Q.setFromTriplets(triplets.begin(), triplets.end());
  return rest;
}

void update_rest_state(const Eigen::MatrixXd& V_rest, const Eigen::MatrixXi& F,
                       const ClothParameters& params, ClothRestState& rest) {
  if (V_rest.rows() != rest.masses.size() || static_cast<size_t>(F.rows()) != rest.triangles.size()) {
    throw UsageError("update_rest_state needs the same mesh the rest state was built for");
  }
  rest.masses.setZero();
  rest.total_area = 0.0;
  set_triangles_and_masses(V_rest, F, params, rest);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(rest.stencils.size() * 16);
  for (BendingStencil& s : rest.stencils) {
    try {
      const BendingStencil w = bending_stencil(stencil_positions(V_rest, s.vertex_ids));
      s.K = w.K;
      s.coefficient = w.coefficient;
    } catch (const GeometryError& e) {
      throw GeometryError(e.what(), "bending stencil at edge " + std::to_string(s.vertex_ids(0)) + "-" +
                                        std::to_string(s.vertex_ids(1)));
    }
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        triplets.emplace_back(s.vertex_ids(i), s.vertex_ids(j), s.coefficient * s.K(i) * s.K(j));
      }
    }
  }
  rest.Q.setFromTriplets(triplets.begin(), triplets.end());
}

void set_rest_triangles(const std::vector<TriangleRest>& triangles, const Eigen::MatrixXi& F,
                        const ClothParameters& params, ClothRestState& rest) {
  if (triangles.size() != rest.triangles.size() || static_cast<size_t>(F.rows()) != triangles.size()) {
    throw UsageError("set_rest_triangles needs one rest triangle per face of the rest state's mesh");
  }
  rest.masses.setZero();
  rest.total_area = 0.0;
  const double ratio = weft_ratio(params);
  for (int f = 0; f < F.rows(); ++f) {
    const double A = triangles[f].area;
    if (!(A > 0.0) || !std::isfinite(A)) {
      throw GeometryError("rest triangle has zero or non-finite area", "face " + std::to_string(f));
    }
    rest.triangles[f] = triangles[f];
    rest.triangles[f].weft_ratio = ratio;
    rest.total_area += A;
    for (int k = 0; k < 3; ++k) rest.masses(F(f, k)) += params.density * A / 3.0;
  }
}

ClothEnergies cloth_energies(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                             const ClothRestState& rest, const ClothParameters& params) {
  ClothEnergies e;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix3d X = triangle_positions(V, F, f);
    e.stretch += stretch_energy(X, rest.triangles[f], params.k_stretch, params.compression_ratio);
    e.shear += shear_energy(X, rest.triangles[f], params.k_shear);
  }
  for (const BendingStencil& s : rest.stencils) {
    e.bend += bending_energy(stencil_positions(V, s.vertex_ids), s, params.k_bend);
  }
  e.gravity = gravity_energy(V, rest.masses, params.gravity);
  return e;
}

Eigen::MatrixXd face_principal_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                         const ClothRestState& rest) {
  if (rest.triangles.size() != static_cast<size_t>(F.rows())) {
    throw UsageError("one rest triangle per face is needed for the stretches");
  }
  Eigen::MatrixXd S(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix<double, 3, 2> W = triangle_w(triangle_positions(V, F, f), rest.triangles[f]);
    S.row(f) = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(W).singularValues().transpose();
  }
  return S;
}

Eigen::MatrixXd face_grain_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const ClothRestState& rest) {
  if (rest.triangles.size() != static_cast<size_t>(F.rows())) {
    throw UsageError("one rest triangle per face is needed for the stretches");
  }
  Eigen::MatrixXd S(F.rows(), 2);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix<double, 3, 2> W = triangle_w(triangle_positions(V, F, f), rest.triangles[f]);
    S(f, 0) = W.col(0).norm();
    S(f, 1) = W.col(1).norm();
  }
  return S;
}

Eigen::VectorXd face_limit_stretches(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                     const ClothRestState& rest, double limit_warp, double limit_weft) {
  if (rest.triangles.size() != static_cast<size_t>(F.rows())) {
    throw UsageError("one rest triangle per face is needed for the stretches");
  }
  if (!(limit_warp > 0.0) || !(limit_weft > 0.0)) throw UsageError("stretch limits must be positive");
  Eigen::VectorXd s(F.rows());
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix<double, 3, 2> W = triangle_w(triangle_positions(V, F, f), rest.triangles[f]);
    s(f) = std::max(W.col(0).norm() / limit_warp, W.col(1).norm() / limit_weft);
  }
  return s;
}

Eigen::MatrixXd cloth_gradient(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const ClothRestState& rest, const ClothParameters& params) {
  Eigen::MatrixXd G = gravity_gradient(V, rest.masses, params.gravity);
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Matrix3d X = triangle_positions(V, F, f);
    const Vector9d g = stretch_gradient(X, rest.triangles[f], params.k_stretch, params.compression_ratio) +
                       shear_gradient(X, rest.triangles[f], params.k_shear);
    for (int k = 0; k < 3; ++k) G.row(F(f, k)) += g.segment<3>(3 * k).transpose();
  }
  G += params.k_bend * (rest.Q * V);
  return G;
}

}  // namespace gp::cloth
