#include "cloth/cloth_energy.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "core/error.h"

namespace gp::cloth {
namespace {

using Matrix32d = Eigen::Matrix<double, 3, 2>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// One stretch condition C = |w| - 1 with energy kA/2 C^2 when stretched and
// r kA/2 C^2 when compressed (r = compression_ratio), in w space (3 dofs).
// d2E/dw2 = k'A [n n^T + (1 - 1/|w|)(I - n n^T)] with k' the side's
// stiffness: the transverse eigenvalue is negative under compression, and
// clamping it to zero is the exact PSD projection.
double stretch_term(const Eigen::Vector3d& w, double kA, double compression_ratio, bool project,
                    Eigen::Vector3d& g, Eigen::Matrix3d& H) {
  const double len = w.norm();
  if (len < 1.0) kA *= compression_ratio;
  const double energy = 0.5 * kA * (len - 1.0) * (len - 1.0);
  if (len < 1e-12) {
    // Fully collapsed direction: the energy has a cone point; no direction to push.
    g.setZero();
    H.setZero();
    return energy;
  }
  const Eigen::Vector3d n = w / len;
  g = kA * (len - 1.0) * n;
  double c = 1.0 - 1.0 / len;
  if (project) c = std::max(c, 0.0);
  H = kA * (c * Eigen::Matrix3d::Identity() + (1.0 - c) * n * n.transpose());
  return energy;
}

// Unit vector along v, or any unit vector when v vanishes.
Eigen::Vector3d unit_or_any(const Eigen::Vector3d& v) {
  const double len = v.norm();
  if (len > 1e-300) return v / len;
  return Eigen::Vector3d::UnitX();
}

// Shear condition s = w_u . w_v with energy kA/2 s^2 in (w_u, w_v) space (6 dofs).
// Exact Hessian kA [g g^T + s P] with g = (w_v, w_u), P = [[0 I][I 0]].
// Closed-form eigen-projection: with p = (w_u + w_v)/2, q = (w_v - w_u)/2,
// g = (p, p) + (q, -q) lies in span{u1 = (p^,p^)/sqrt2, u2 = (q^,-q^)/sqrt2}; on the
// complement of that plane P has eigenvalue +1 (in the (e,e) space) and -1 (in the
// (e,-e) space), so the Hessian there is +s resp. -s; on the plane it is the 2x2
// matrix [[2|p|^2 + s, 2|p||q|], [2|p||q|, 2|q|^2 - s]], clamped by its own eigen
// decomposition.
double shear_term(const Eigen::Vector3d& wu, const Eigen::Vector3d& wv, double kA, bool project,
                  Vector6d& g6, Matrix6d& H6) {
  const double s = wu.dot(wv);
  Vector6d gs;
  gs << wv, wu;
  g6 = kA * s * gs;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  if (!project) {
    H6 = gs * gs.transpose();
    H6.block<3, 3>(0, 3) += s * I;
    H6.block<3, 3>(3, 0) += s * I;
    H6 *= kA;
    return 0.5 * kA * s * s;
  }
  const Eigen::Vector3d p = 0.5 * (wu + wv);
  const Eigen::Vector3d q = 0.5 * (wv - wu);
  const double lp = p.norm();
  const double lq = q.norm();
  const Eigen::Vector3d ph = unit_or_any(p);
  const Eigen::Vector3d qh = unit_or_any(q);
  const double r2 = std::sqrt(0.5);
  Vector6d u1, u2;
  u1 << r2 * ph, r2 * ph;
  u2 << r2 * qh, -r2 * qh;
  // 2x2 block and its eigen decomposition.
  const double h11 = 2.0 * lp * lp + s;
  const double h22 = 2.0 * lq * lq - s;
  const double h12 = 2.0 * lp * lq;
  const double mean = 0.5 * (h11 + h22);
  const double rad = std::sqrt(0.25 * (h11 - h22) * (h11 - h22) + h12 * h12);
  const double l1 = mean + rad;
  const double l2 = mean - rad;
  // Eigenvector of l1: (h12, l1 - h11) or (l1 - h22, h12), whichever is better conditioned.
  Eigen::Vector2d e1(h12, l1 - h11);
  const Eigen::Vector2d e1b(l1 - h22, h12);
  if (e1b.squaredNorm() > e1.squaredNorm()) e1 = e1b;
  if (e1.squaredNorm() < 1e-300) e1 = Eigen::Vector2d(1.0, 0.0);
  e1.normalize();
  const Eigen::Vector2d e2(-e1.y(), e1.x());
  const Vector6d v1 = e1.x() * u1 + e1.y() * u2;
  const Vector6d v2 = e2.x() * u1 + e2.y() * u2;

  Matrix6d plus_space, minus_space;
  plus_space << 0.5 * I, 0.5 * I, 0.5 * I, 0.5 * I;
  minus_space << 0.5 * I, -0.5 * I, -0.5 * I, 0.5 * I;
  H6 = std::max(s, 0.0) * (plus_space - u1 * u1.transpose()) +
       std::max(-s, 0.0) * (minus_space - u2 * u2.transpose()) +
       std::max(l1, 0.0) * v1 * v1.transpose() + std::max(l2, 0.0) * v2 * v2.transpose();
  H6 *= kA;
  return 0.5 * kA * s * s;
}

// Maps a 6x6 matrix in (w_u, w_v) space to the 9x9 matrix in vertex space:
// block(i,j) = a_i a_j H_uu + a_i b_j H_uv + b_i a_j H_vu + b_i b_j H_vv.
Matrix9d map_to_vertices(const Matrix6d& H6, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Matrix9d H;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      H.block<3, 3>(3 * i, 3 * j) =
          a(i) * a(j) * H6.block<3, 3>(0, 0) + a(i) * b(j) * H6.block<3, 3>(0, 3) +
          b(i) * a(j) * H6.block<3, 3>(3, 0) + b(i) * b(j) * H6.block<3, 3>(3, 3);
    }
  }
  return H;
}

Vector9d map_gradient(const Eigen::Vector3d& gu, const Eigen::Vector3d& gv,
                      const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Vector9d g;
  for (int i = 0; i < 3; ++i) g.segment<3>(3 * i) = a(i) * gu + b(i) * gv;
  return g;
}

double cotangent(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return u.dot(v) / u.cross(v).norm();
}

// Smallest accepted shape quality 2A / (longest edge)^2 of a rest triangle.
// A face of quality q is about 1/q^2 times stiffer than a regular one of the
// same size, and the implicit system's conditioning follows: below 1e-6 the
// motion drifts by millimetres and more (cloth/README.md, "Smallest
// rest-triangle quality").
constexpr double kMinRestQuality = 1e-6;

}  // namespace

Eigen::Vector3d warp_direction(const Eigen::Matrix3d& X_rest, const Eigen::Vector3d& material_direction,
                               double grain_angle) {
  const Eigen::Vector3d e1 = X_rest.col(1) - X_rest.col(0);
  const Eigen::Vector3d e2 = X_rest.col(2) - X_rest.col(0);
  Eigen::Vector3d n = e1.cross(e2);
  const double area2 = n.norm();
  const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), (e2 - e1).squaredNorm()});
  if (!X_rest.allFinite() || !(area2 >= kMinRestQuality * longest2) || longest2 <= 0.0) {
    throw GeometryError("degenerate (zero-area or sliver) rest triangle");
  }
  n /= area2;
  Eigen::Vector3d d = material_direction - material_direction.dot(n) * n;
  // A material direction nearly normal to the triangle gives no stable in-plane
  // axis; the first edge is used then (the anisotropy is lost there, not the model).
  if (!(d.norm() >= 0.1 * material_direction.norm())) d = e1;
  d.normalize();
  // A turned grain (a bias cut): the warp rotated about the normal. Skipped at
  // 0 so that the default frame is bit for bit the unturned one.
  if (grain_angle != 0.0) d = std::cos(grain_angle) * d + std::sin(grain_angle) * n.cross(d);
  return d;
}

TriangleRest triangle_rest(const Eigen::Matrix3d& X_rest, const Eigen::Vector3d& material_direction,
                           double grain_angle) {
  const Eigen::Vector3d d = warp_direction(X_rest, material_direction, grain_angle);
  const Eigen::Vector3d e1 = X_rest.col(1) - X_rest.col(0);
  const Eigen::Vector3d e2 = X_rest.col(2) - X_rest.col(0);
  Eigen::Vector3d n = e1.cross(e2);
  n /= n.norm();
  const Eigen::Vector3d v = n.cross(d);
  // The triangle in its own (u, v) frame: a flat triangle with the warp along x.
  Eigen::Matrix<double, 2, 3> P;
  P << 0.0, e1.dot(d), e2.dot(d), 0.0, e1.dot(v), e2.dot(v);
  return triangle_rest_flat(P);
}

TriangleRest triangle_rest_flat(const Eigen::Matrix<double, 2, 3>& P) {
  Eigen::Matrix2d Dm;
  Dm.col(0) = P.col(1) - P.col(0);
  Dm.col(1) = P.col(2) - P.col(0);
  const double longest2 = std::max({Dm.col(0).squaredNorm(), Dm.col(1).squaredNorm(),
                                    (Dm.col(1) - Dm.col(0)).squaredNorm()});
  const double area2 = std::abs(Dm.determinant());
  if (!P.allFinite() || !(area2 >= kMinRestQuality * longest2) || longest2 <= 0.0) {
    throw GeometryError("degenerate (zero-area or sliver) rest triangle");
  }
  const Eigen::Matrix2d B = Dm.inverse();
  TriangleRest rest;
  rest.area = 0.5 * area2;
  rest.a = Eigen::Vector3d(-B(0, 0) - B(1, 0), B(0, 0), B(1, 0));
  rest.b = Eigen::Vector3d(-B(0, 1) - B(1, 1), B(0, 1), B(1, 1));
  return rest;
}

Eigen::Matrix<double, 3, 2> triangle_w(const Eigen::Matrix3d& X, const TriangleRest& rest) {
  Matrix32d W;
  W.col(0) = X * rest.a;
  W.col(1) = X * rest.b;
  return W;
}

double stretch_energy(const Eigen::Matrix3d& X, const TriangleRest& rest, double k, double compression_ratio) {
  const Matrix32d W = triangle_w(X, rest);
  Eigen::Vector3d g;
  Eigen::Matrix3d H;
  return stretch_term(W.col(0), k * rest.area, compression_ratio, false, g, H) +
         stretch_term(W.col(1), k * rest.area * rest.weft_ratio, compression_ratio, false, g, H);
}

Vector9d stretch_gradient(const Eigen::Matrix3d& X, const TriangleRest& rest, double k, double compression_ratio) {
  const Matrix32d W = triangle_w(X, rest);
  Eigen::Vector3d gu, gv;
  Eigen::Matrix3d H;
  stretch_term(W.col(0), k * rest.area, compression_ratio, false, gu, H);
  stretch_term(W.col(1), k * rest.area * rest.weft_ratio, compression_ratio, false, gv, H);
  return map_gradient(gu, gv, rest.a, rest.b);
}

Matrix9d stretch_hessian(const Eigen::Matrix3d& X, const TriangleRest& rest, double k, bool project_psd,
                         double compression_ratio) {
  const Matrix32d W = triangle_w(X, rest);
  Eigen::Vector3d g;
  Eigen::Matrix3d Hu, Hv;
  stretch_term(W.col(0), k * rest.area, compression_ratio, project_psd, g, Hu);
  stretch_term(W.col(1), k * rest.area * rest.weft_ratio, compression_ratio, project_psd, g, Hv);
  Matrix6d H6 = Matrix6d::Zero();
  H6.block<3, 3>(0, 0) = Hu;
  H6.block<3, 3>(3, 3) = Hv;
  return map_to_vertices(H6, rest.a, rest.b);
}

double shear_energy(const Eigen::Matrix3d& X, const TriangleRest& rest, double k) {
  const Matrix32d W = triangle_w(X, rest);
  const double s = W.col(0).dot(W.col(1));
  return 0.5 * k * rest.area * s * s;
}

Vector9d shear_gradient(const Eigen::Matrix3d& X, const TriangleRest& rest, double k) {
  const Matrix32d W = triangle_w(X, rest);
  const double s = W.col(0).dot(W.col(1));
  const double kA = k * rest.area;
  return map_gradient(kA * s * W.col(1), kA * s * W.col(0), rest.a, rest.b);
}

Matrix9d shear_hessian(const Eigen::Matrix3d& X, const TriangleRest& rest, double k,
                       bool project_psd) {
  const Matrix32d W = triangle_w(X, rest);
  Vector6d g6;
  Matrix6d H6;
  shear_term(W.col(0), W.col(1), k * rest.area, project_psd, g6, H6);
  return map_to_vertices(H6, rest.a, rest.b);
}

Matrix9d stretch_damping(const Eigen::Matrix3d& X, const TriangleRest& rest, double k_d) {
  const Matrix32d W = triangle_w(X, rest);
  Matrix6d D = Matrix6d::Zero();
  const double kA = k_d * rest.area;
  for (int c = 0; c < 2; ++c) {
    const double len = W.col(c).norm();
    if (len < 1e-12) continue;
    const Eigen::Vector3d n = W.col(c) / len;
    D.block<3, 3>(3 * c, 3 * c) = kA * n * n.transpose();
  }
  return map_to_vertices(D, rest.a, rest.b);
}

Matrix9d shear_damping(const Eigen::Matrix3d& X, const TriangleRest& rest, double k_d) {
  const Matrix32d W = triangle_w(X, rest);
  Vector6d gs;
  gs << W.col(1), W.col(0);
  const Matrix6d D = k_d * rest.area * gs * gs.transpose();
  return map_to_vertices(D, rest.a, rest.b);
}

BendingStencil bending_stencil(const Eigen::Matrix<double, 3, 4>& X_rest) {
  const Eigen::Vector3d x0 = X_rest.col(0), x1 = X_rest.col(1), x2 = X_rest.col(2),
                        x3 = X_rest.col(3);
  const double a0 = 0.5 * (x1 - x0).cross(x2 - x0).norm();
  const double a1 = 0.5 * (x1 - x0).cross(x3 - x0).norm();
  const double e2 = (x1 - x0).squaredNorm();
  // Each face against its own longest edge, as triangle_rest measures it, so
  // that a rest shape whose faces are accepted has valid stencils too.
  const double scale0 = std::max({e2, (x2 - x0).squaredNorm(), (x2 - x1).squaredNorm()});
  const double scale1 = std::max({e2, (x3 - x0).squaredNorm(), (x3 - x1).squaredNorm()});
  if (!X_rest.allFinite() || !(2.0 * a0 >= kMinRestQuality * scale0) ||
      !(2.0 * a1 >= kMinRestQuality * scale1)) {
    throw GeometryError("degenerate (zero-area or sliver) rest triangle at a bending stencil");
  }
  const double c0 = cotangent(x1 - x0, x2 - x0);
  const double c1 = cotangent(x0 - x1, x2 - x1);
  const double d0 = cotangent(x1 - x0, x3 - x0);
  const double d1 = cotangent(x0 - x1, x3 - x1);
  BendingStencil s;
  s.K = Eigen::Vector4d(c1 + d1, c0 + d0, -c0 - c1, -d0 - d1);
  s.coefficient = 3.0 / (a0 + a1);
  return s;
}

double bending_energy(const Eigen::Matrix<double, 3, 4>& X, const BendingStencil& s, double k) {
  const Eigen::Vector3d m = X * s.K;
  return 0.5 * k * s.coefficient * m.squaredNorm();
}

Vector12d bending_gradient(const Eigen::Matrix<double, 3, 4>& X, const BendingStencil& s, double k) {
  const Eigen::Vector3d m = k * s.coefficient * (X * s.K);
  Vector12d g;
  for (int i = 0; i < 4; ++i) g.segment<3>(3 * i) = s.K(i) * m;
  return g;
}

Matrix12d bending_hessian(const BendingStencil& s, double k) {
  Matrix12d H;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      H.block<3, 3>(3 * i, 3 * j) =
          k * s.coefficient * s.K(i) * s.K(j) * Eigen::Matrix3d::Identity();
    }
  }
  return H;
}

double gravity_energy(const Eigen::MatrixXd& V, const Eigen::VectorXd& m, const Eigen::Vector3d& g) {
  return -(m.transpose() * (V * g))(0);
}

Eigen::MatrixXd gravity_gradient(const Eigen::MatrixXd& V, const Eigen::VectorXd& m,
                                 const Eigen::Vector3d& g) {
  Eigen::MatrixXd G(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) G.row(i) = -m(i) * g.transpose();
  return G;
}

double membrane_system_block(const Eigen::Matrix3d& X, const TriangleRest& rest,
                             const MembraneCoefficients& c, double h, Vector9d& gradient,
                             Matrix9d& K) {
  const Matrix32d W = triangle_w(X, rest);
  const Eigen::Vector3d wu = W.col(0), wv = W.col(1);
  const double A = rest.area;
  Eigen::Vector3d gu, gv;
  Eigen::Matrix3d Hu, Hv;
  double energy = stretch_term(wu, c.k_stretch * A, c.compression_ratio, true, gu, Hu);
  energy += stretch_term(wv, c.k_stretch * A * rest.weft_ratio, c.compression_ratio, true, gv, Hv);
  Vector6d g6;
  Matrix6d H6;
  energy += shear_term(wu, wv, c.k_shear * A, true, g6, H6);
  g6.head<3>() += gu;
  g6.tail<3>() += gv;

  const double h2 = h * h;
  Matrix6d K6 = h2 * H6;
  K6.block<3, 3>(0, 0) += h2 * Hu;
  K6.block<3, 3>(3, 3) += h2 * Hv;
  // Damping: BW sec. 4.5, k_d A J^T J per condition.
  const double dA = h * c.damping_stretch * A;
  const double lu = wu.norm(), lv = wv.norm();
  if (lu > 1e-12) K6.block<3, 3>(0, 0) += (dA / (lu * lu)) * wu * wu.transpose();
  if (lv > 1e-12) K6.block<3, 3>(3, 3) += (dA / (lv * lv)) * wv * wv.transpose();
  Vector6d gs;
  gs << wv, wu;
  K6 += (h * c.damping_shear * A) * gs * gs.transpose();

  gradient = map_gradient(g6.head<3>(), g6.tail<3>(), rest.a, rest.b);
  K = map_to_vertices(K6, rest.a, rest.b);
  return energy;
}

}  // namespace gp::cloth
