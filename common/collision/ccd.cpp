#include "collision/ccd.h"

#include <algorithm>
#include <cmath>
#include <vector>
#include <Eigen/Geometry>

namespace gp::collision {
namespace {

using Eigen::Vector3d;

struct Cubic {
  double c[4] = {0.0, 0.0, 0.0, 0.0};  // f(t) = c0 + c1 t + c2 t^2 + c3 t^3
  double operator()(double t) const { return c[0] + t * (c[1] + t * (c[2] + t * c[3])); }
};

// f(t) = (A(t) x B(t)) . C(t) with A = A0 + t dA, and so on.
Cubic triple_product_cubic(const Vector3d& A0, const Vector3d& dA, const Vector3d& B0, const Vector3d& dB,
                           const Vector3d& C0, const Vector3d& dC) {
  const Vector3d k0 = A0.cross(B0);
  const Vector3d k1 = A0.cross(dB) + dA.cross(B0);
  const Vector3d k2 = dA.cross(dB);
  Cubic f;
  f.c[0] = k0.dot(C0);
  f.c[1] = k0.dot(dC) + k1.dot(C0);
  f.c[2] = k1.dot(dC) + k2.dot(C0);
  f.c[3] = k2.dot(dC);
  return f;
}

// Times in [0, 1], ascending, at which the primitives may meet: the roots of
// f, and the ends and extrema of f (where a grazing contact with f touching
// zero without a sign change would otherwise be lost to rounding).
std::vector<double> candidate_times(const Cubic& f) {
  std::vector<double> breaks{0.0};
  // Extrema: roots of f'(t) = c1 + 2 c2 t + 3 c3 t^2.
  const double qa = 3.0 * f.c[3], qb = 2.0 * f.c[2], qc = f.c[1];
  auto keep = [&breaks](double t) {
    if (t > 0.0 && t < 1.0) breaks.push_back(t);
  };
  if (qa != 0.0) {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      // Stable roots of the quadratic (no cancellation between -qb and the root).
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      if (q != 0.0) {
        keep(q / qa);
        keep(qc / q);
      } else {
        keep(0.0);
      }
    }
  } else if (qb != 0.0) {
    keep(-qc / qb);
  }
  breaks.push_back(1.0);
  std::sort(breaks.begin(), breaks.end());
  std::vector<double> times;
  for (size_t i = 0; i + 1 < breaks.size(); ++i) {
    double lo = breaks[i], hi = breaks[i + 1];
    times.push_back(lo);
    double flo = f(lo);
    const double fhi = f(hi);
    if ((flo < 0.0 && fhi > 0.0) || (flo > 0.0 && fhi < 0.0)) {
      // f is monotone on [lo, hi]: bisection to the last bits.
      for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        const double fm = f(mid);
        if ((fm < 0.0) == (flo < 0.0) && fm != 0.0) {
          lo = mid;
          flo = fm;
        } else {
          hi = mid;
        }
      }
      times.push_back(0.5 * (lo + hi));
    }
  }
  times.push_back(1.0);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

int sign_of(double x) { return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0); }

// The sign of f just before time t (after it for t = 0): f at the middle of
// the stretch to the neighbouring candidate time.
int side_at(const Cubic& f, const std::vector<double>& times, size_t i) {
  const double t = times[i];
  const double other = i > 0 ? times[i - 1] : (times.size() > 1 ? times[1] : 1.0);
  int s = sign_of(f(0.5 * (t + other)));
  if (s == 0) s = sign_of(f(i > 0 ? other : 1.0));
  return s;
}

Vector3d lerp(const Vector3d& x0, const Vector3d& x1, double t) { return x0 + t * (x1 - x0); }

}  // namespace

Vector3d closest_triangle_weights(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return Vector3d(1, 0, 0);
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return Vector3d(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return Vector3d(1.0 - v, v, 0.0);
  }
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return Vector3d(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return Vector3d(1.0 - w, 0.0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return Vector3d(0.0, 1.0 - w, w);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return Vector3d(1, 0, 0);  // degenerate: the corner tests above decide
  return Vector3d(va / sum, vb / sum, vc / sum);
}

void closest_segment_parameters(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d, double& s,
                                double& u) {
  const Vector3d d1 = b - a, d2 = d - c, r = a - c;
  const double aa = d1.squaredNorm(), ee = d2.squaredNorm(), f = d2.dot(r);
  if (!(aa > 0.0) && !(ee > 0.0)) {
    s = u = 0.0;
    return;
  }
  if (!(aa > 0.0)) {
    s = 0.0;
    u = std::clamp(f / ee, 0.0, 1.0);
    return;
  }
  const double cc = d1.dot(r);
  if (!(ee > 0.0)) {
    u = 0.0;
    s = std::clamp(-cc / aa, 0.0, 1.0);
    return;
  }
  const double bb = d1.dot(d2);
  const double denom = aa * ee - bb * bb;
  s = denom > 0.0 ? std::clamp((bb * f - cc * ee) / denom, 0.0, 1.0) : 0.0;
  u = (bb * s + f) / ee;
  if (u < 0.0) {
    u = 0.0;
    s = std::clamp(-cc / aa, 0.0, 1.0);
  } else if (u > 1.0) {
    u = 1.0;
    s = std::clamp((bb - cc) / aa, 0.0, 1.0);
  }
}

std::optional<PointTriangleHit> point_triangle_ccd(const Vector3d& p0, const Vector3d& p1, const Vector3d& a0,
                                                   const Vector3d& a1, const Vector3d& b0, const Vector3d& b1,
                                                   const Vector3d& c0, const Vector3d& c1, double tolerance) {
  const Vector3d da = a1 - a0;
  const Cubic f = triple_product_cubic(b0 - a0, (b1 - b0) - da, c0 - a0, (c1 - c0) - da, p0 - a0, (p1 - p0) - da);
  const std::vector<double> times = candidate_times(f);
  for (size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    const Vector3d p = lerp(p0, p1, t), a = lerp(a0, a1, t), b = lerp(b0, b1, t), c = lerp(c0, c1, t);
    // Farther than the tolerance from the triangle's plane: no contact now.
    if (std::abs(f(t)) > tolerance * (b - a).cross(c - a).norm()) continue;
    const Vector3d w = closest_triangle_weights(p, a, b, c);
    if ((w(0) * a + w(1) * b + w(2) * c - p).norm() > tolerance) continue;
    PointTriangleHit hit;
    hit.t = t;
    hit.weights = w;
    hit.side = side_at(f, times, i);
    return hit;
  }
  return std::nullopt;
}

std::optional<EdgeEdgeHit> edge_edge_ccd(const Vector3d& a0, const Vector3d& a1, const Vector3d& b0,
                                         const Vector3d& b1, const Vector3d& c0, const Vector3d& c1,
                                         const Vector3d& d0, const Vector3d& d1, double tolerance) {
  const Vector3d da = a1 - a0;
  const Cubic f =
      triple_product_cubic(b0 - a0, (b1 - b0) - da, d0 - c0, (d1 - d0) - (c1 - c0), c0 - a0, (c1 - c0) - da);
  const std::vector<double> times = candidate_times(f);
  for (size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    const Vector3d a = lerp(a0, a1, t), b = lerp(b0, b1, t), c = lerp(c0, c1, t), d = lerp(d0, d1, t);
    // The lines' distance bounds the segments' from below.
    if (std::abs(f(t)) > tolerance * (b - a).cross(d - c).norm()) continue;
    double s = 0.0, u = 0.0;
    closest_segment_parameters(a, b, c, d, s, u);
    if ((a + s * (b - a) - c - u * (d - c)).norm() > tolerance) continue;
    EdgeEdgeHit hit;
    hit.t = t;
    hit.s = s;
    hit.u = u;
    hit.side = side_at(f, times, i);
    return hit;
  }
  return std::nullopt;
}

}  // namespace gp::collision
