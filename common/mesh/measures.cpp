#include "mesh/measures.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <Eigen/Geometry>

#include "core/math.h"

namespace gp {

Eigen::VectorXd face_areas(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd A(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    A(f) = 0.5 * (b - a).cross(c - a).norm();
  }
  return A;
}

double mesh_area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double area = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

double area_weighted_percentile(const Eigen::VectorXd& values, const Eigen::VectorXd& weights, double fraction) {
  if (values.size() == 0) return 0.0;
  double total = 0.0;
  for (Eigen::Index i = 0; i < weights.size(); ++i) total += weights(i);
  std::vector<Eigen::Index> order(static_cast<size_t>(values.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return values(a) < values(b); });
  double accumulated = 0.0;
  for (Eigen::Index i : order) {
    accumulated += weights(i);
    if (accumulated >= fraction * total) return values(i);
  }
  return values(order.back());
}

Eigen::MatrixXd face_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    N.row(f) = len > 0 ? Eigen::RowVector3d(n.transpose() / len) : Eigen::RowVector3d::Zero();
  }
  return N;
}

Eigen::MatrixXd vertex_normals(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();  // length = 2 * area
    for (int k = 0; k < 3; ++k) N.row(F(f, k)) += n;
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

double signed_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  double vol = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    vol += a.dot(b.cross(c));
  }
  return vol / 6.0;
}

double bounding_box_diagonal(const Eigen::MatrixXd& V) {
  if (V.rows() == 0) return 0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

Eigen::VectorXd edge_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E) {
  Eigen::VectorXd L(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) L(e) = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return L;
}

Eigen::VectorXd angle_defects(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::VectorXd defect = Eigen::VectorXd::Constant(V.rows(), 2.0 * M_PI);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = (V.row(F(f, (k + 1) % 3)) - V.row(F(f, k))).transpose();
      const Eigen::Vector3d b = (V.row(F(f, (k + 2) % 3)) - V.row(F(f, k))).transpose();
      // atan2 of |a x b| and a . b: accurate for slivers, where acos is not.
      defect[F(f, k)] -= math::atan2(a.cross(b).norm(), a.dot(b));
    }
  return defect;
}

Eigen::Vector3d area_centroid(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    centroid += area * (a + b + c) / 3.0;
    total += area;
  }
  if (total > 0.0) centroid /= total;
  return centroid;
}

}  // namespace gp
