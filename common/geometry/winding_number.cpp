#include "geometry/winding_number.h"

#include <cmath>

#include <Eigen/Geometry>

#include "core/math.h"

namespace gp {

double winding_number(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::Vector3d& p) {
  double total = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose() - p, b = V.row(F(f, 1)).transpose() - p,
                          c = V.row(F(f, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    // tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    total += 2.0 * gp::math::atan2(numerator, denominator);
  }
  return total / (4.0 * M_PI);
}

}  // namespace gp
