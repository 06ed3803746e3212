#include "registration/units.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/math.h"
#include "mesh/slice_mesh.h"

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

namespace {

// Cross-sections of the mesh in the plane `axis` = level that are at least
// `min_length` long (shorter ones are noise: an eye shell, a stray fragment).
int count_sections(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int axis, double level,
                   double min_length) {
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero();
  point(axis) = level;
  normal(axis) = 1;
  std::vector<bool> closed;
  const auto cut = slice_mesh(V, F, point, normal, &closed);
  int count = 0;
  for (size_t i = 0; i < cut.size(); ++i)
    if (polyline_length(cut[i], closed[i]) >= min_length) ++count;
  return count;
}

// The middle value of a few counts.
int median_count(std::vector<int> counts) {
  std::sort(counts.begin(), counts.end());
  return counts[counts.size() / 2];
}

std::string format(double x, int precision = 3) {
  std::ostringstream s;
  s.precision(precision);
  s << x;
  return s.str();
}

std::string join_counts(const std::vector<int>& counts) {
  std::string s;
  for (int c : counts) s += (s.empty() ? "" : " ") + std::to_string(c);
  return s;
}

}  // namespace

UpAxisDetection detect_up_axis(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
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
  UpAxisDetection d;
  int axis = 0;
  variance.maxCoeff(&axis);
  d.up = UpAxis{axis, +1};
  double runner_up = 0;
  for (int k = 0; k < 3; ++k)
    if (k != axis) runner_up = std::max(runner_up, variance(k));
  d.spread_ratio = variance(axis) > 0 ? runner_up / variance(axis) : 1.0;
  const bool axis_ambiguous = !(d.spread_ratio <= kUpAxisSpreadMargin);

  double lo = INFINITY, hi = -INFINITY;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (std::isfinite(V(i, axis))) {
      lo = std::min(lo, V(i, axis));
      hi = std::max(hi, V(i, axis));
    }
  const double height = hi - lo;
  if (!(height > 0)) throw GeometryError("mesh is flat along its longest axis; cannot find its up axis");

  // Soles: surface facing along the axis (within 20 degrees) in the lowest
  // and highest 5 %. The generated bodies' feet show 0.006 h^2 standing with
  // the arms down and 0.004 h^2 with the arms up (a taller extent); capped
  // wrists or ankles about 0.001-0.002 h^2. The vote needs 0.0025 h^2 and
  // five times the other end.
  const double cos20 = gp::math::cos(20.0 * M_PI / 180.0);
  double flat_low = 0, flat_high = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d n2 = (b - a).cross(c - a);  // length = 2 * area
    const double len = n2.norm();
    if (!(len > 0) || !std::isfinite(len)) continue;
    const double h = ((a + b + c)(axis) / 3.0 - lo) / height;
    // Either way along the axis: a mirrored or inside-out scan has its normals reversed.
    const double facing = std::abs(n2(axis)) / len;
    if (h < 0.05 && facing > cos20) flat_low += 0.5 * len;
    if (h > 0.95 && facing > cos20) flat_high += 0.5 * len;
  }
  UpCue soles{"soles", 0, ""};
  {
    const double enough = 0.0025 * height * height;
    if (flat_low >= enough && flat_low > 5 * flat_high) soles.vote = +1;
    else if (flat_high >= enough && flat_high > 5 * flat_low) soles.vote = -1;
    soles.detail = "flat surface across the axis at the low end " + format(flat_low / (height * height)) +
                   " h^2, at the high end " + format(flat_high / (height * height)) +
                   " h^2 (soles: at least 0.0025 h^2 and five times the other end)";
  }

  // Legs: cross-sections in slices 4-22 % of the height from each end.
  UpCue legs{"legs", 0, ""};
  {
    std::vector<int> low, high;
    for (int k = 0; k < 7; ++k) {
      const double t = 0.04 + 0.03 * k;
      low.push_back(count_sections(V, F, axis, lo + t * height, 0.05 * height));
      high.push_back(count_sections(V, F, axis, hi - t * height, 0.05 * height));
    }
    // The legs' end holds two sections: against one (head and neck) at the
    // other end; or, with the arms raised, two throughout against two arms
    // with the head appearing between them (three) at the other end.
    const auto median_is = [](const std::vector<int>& c, int n) { return median_count(c) == n; };
    const auto most = [](const std::vector<int>& c) { return *std::max_element(c.begin(), c.end()); };
    const auto legs_at = [&](const std::vector<int>& legs_end, const std::vector<int>& head_end) {
      return (median_is(legs_end, 2) && median_is(head_end, 1)) ||
             (median_is(legs_end, 2) && most(legs_end) == 2 && most(head_end) >= 3 && !median_is(head_end, 1));
    };
    if (legs_at(low, high)) legs.vote = +1;
    else if (legs_at(high, low)) legs.vote = -1;
    legs.detail = "cross-sections 4-22 % of the height from the low end " + join_counts(low) +
                  ", from the high end " + join_counts(high) +
                  " (legs: two at the feet against one at the head, or two throughout against two arms and then the head)";
  }
  d.cues = {soles, legs};

  int votes_up = 0, votes_down = 0;
  for (const UpCue& c : d.cues) {
    if (c.vote > 0) ++votes_up;
    if (c.vote < 0) ++votes_down;
  }
  d.up.sign = votes_down > votes_up ? -1 : +1;
  const bool sign_ambiguous = (votes_up > 0) == (votes_down > 0);  // none, or disagreeing cues
  d.ambiguous = axis_ambiguous || sign_ambiguous;

  std::ostringstream s;
  s << "longest along " << "xyz"[axis] << " (area-weighted variances x " << format(variance(0)) << ", y "
    << format(variance(1)) << ", z " << format(variance(2)) << "; the next axis at "
    << format(100 * d.spread_ratio, 2) << " % of it" << (axis_ambiguous ? ", too close to tell" : "") << ")";
  for (const UpCue& c : d.cues)
    s << "; " << c.name << " say "
      << (c.vote == 0 ? std::string("nothing") : UpAxis{axis, c.vote}.name() + " up") << " (" << c.detail << ")";
  if (sign_ambiguous)
    s << (votes_up > 0 ? "; the cues disagree" : "; no cue tells which end is up");
  d.reason = s.str();
  return d;
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
