#include "registration/units.h"

#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/math.h"

namespace gp {

std::string UpAxis::name() const {
  return std::string(sign > 0 ? "+" : "-") + "xyz"[axis];
}

UpAxis UpAxis::parse(const std::string& s) {
  if (s.size() == 2 && (s[0] == '+' || s[0] == '-') && s[1] >= 'x' && s[1] <= 'z')
    return UpAxis{s[1] - 'x', s[0] == '+' ? +1 : -1};
  throw UsageError("up axis must be one of +x, -x, +y, -y, +z, -z; got '" + s + "'", "--up");
}

double metres_per_unit(const std::string& units) {
  if (units == "m") return 1.0;
  if (units == "cm") return 0.01;
  if (units == "mm") return 0.001;
  if (units == "in") return 0.0254;
  throw UsageError("units must be one of m, cm, mm, in; got '" + units + "'", "--units");
}

UpAxis detect_up_axis(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, bool* ambiguous,
                      std::string* reason) {
  // Area-weighted first and second moments of the surface.
  double total = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), second = Eigen::Vector3d::Zero();
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (!std::isfinite(area)) continue;
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    total += area;
    mean += area * centroid;
    second += area * centroid.cwiseProduct(centroid);
  }
  if (total <= 0) throw GeometryError("mesh has no area; cannot find its up axis");
  mean /= total;
  const Eigen::Vector3d variance = second / total - mean.cwiseProduct(mean);
  int axis = 0;
  variance.maxCoeff(&axis);

  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (std::isfinite(V(i, axis))) {
      lo = std::min(lo, V(i, axis));
      hi = std::max(hi, V(i, axis));
    }
  const double height = hi - lo;

  // Sign, first cue: the soles. A standing body's lowest 5 % holds flat
  // surface facing the floor (about 0.04 m^2 for two feet), while its highest
  // 5 % is a rounded head or hands with little surface facing straight up.
  const double cos20 = gp::math::cos(20.0 * M_PI / 180.0);
  double flat_low = 0, flat_high = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n2 = (b - a).cross(c - a);  // length = 2 * area
    const double len = n2.norm();
    if (!(len > 0) || !std::isfinite(len)) continue;
    const double h = ((a + b + c)(axis) / 3.0 - lo) / height;
    const double facing = n2(axis) / len;
    if (h < 0.05 && facing < -cos20) flat_low += 0.5 * len;
    if (h > 0.95 && facing > cos20) flat_high += 0.5 * len;
  }
  // Second cue: the upper body carries more surface than the legs, so the
  // surface centroid lies above the middle of the extent.
  const double offset = height > 0 ? (mean(axis) - 0.5 * (lo + hi)) / height : 0.0;

  UpAxis up{axis, +1};
  bool guess = false;
  const double floor_ratio = (flat_low + 1e-12 * height * height) / (flat_high + 1e-12 * height * height);
  if (floor_ratio > 2.0 || floor_ratio < 0.5) {
    up.sign = floor_ratio > 1.0 ? +1 : -1;
  } else {
    up.sign = offset >= 0 ? +1 : -1;
    guess = std::abs(offset) < 0.02;
  }
  if (ambiguous) *ambiguous = guess;
  if (reason) {
    std::ostringstream s;
    s.precision(3);
    s << "largest area-weighted spread along " << "xyz"[axis] << " (variances x " << variance(0)
      << ", y " << variance(1) << ", z " << variance(2) << "); surface facing away from the body "
      << "at its low end " << flat_low << ", at its high end " << flat_high
      << " (soles are low); surface centroid " << (offset * 100) << " % of the height from the middle"
      << (guess ? " (neither cue is clear: assumed " + up.name() + ")" : "");
    *reason = s.str();
  }
  return up;
}

std::string detect_units(double height) {
  if (height >= 0.5 && height <= 2.5) return "m";
  if (height >= 50 && height <= 250) return "cm";
  if (height >= 500 && height <= 2500) return "mm";
  std::ostringstream s;
  s << "cannot infer units from a body height of " << height
    << " (expected 0.5-2.5 m, 50-250 cm or 500-2500 mm); pass --units";
  throw GeometryError(s.str());
}

Eigen::Matrix3d rotation_to_y_up(const UpAxis& up) {
  // Rows are the new x, y, z axes expressed in input coordinates: new y is the
  // up direction; new x and z complete a right-handed frame.
  Eigen::Vector3d y = Eigen::Vector3d::Zero();
  y(up.axis) = up.sign;
  Eigen::Vector3d x;
  if (up.axis == 1) x = Eigen::Vector3d(up.sign, 0, 0);  // +y: identity; -y: turn about z
  else if (up.axis == 2) x = Eigen::Vector3d(1, 0, 0);   // z-up scans keep x
  else x = Eigen::Vector3d(0, -up.sign, 0);              // x-up scans
  const Eigen::Vector3d z = x.cross(y);
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

Eigen::MatrixXd to_metres_y_up(const Eigen::MatrixXd& V, const UnitsAndUp& u) {
  const Eigen::Matrix3d R = rotation_to_y_up(u.up);
  return (V * R.transpose()) * u.scale_to_metres;
}

}  // namespace gp
