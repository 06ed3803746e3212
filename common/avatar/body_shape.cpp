#include "avatar/body_shape.h"

#include <algorithm>
#include <cmath>

#include "avatar/girth.h"
#include "core/error.h"
#include "core/math.h"

namespace gp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Polynomial smooth minimum (I. Quilez, "smooth minimum", 2013): equals
// min(a, b) when |a - b| >= k and rounds the crease within k.
double smin(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }

// Signed distance to the round cone spanned by balls (a, ra) and (b, rb): the
// convex hull of two spheres. Exact; derived from the 2-D problem in the plane
// of the axis and the point (tangent line between two circles).
double round_cone(const Eigen::Vector3d& p, const Ball& A, const Ball& B) {
  const Eigen::Vector3d ba = B.c - A.c;
  const double l = ba.norm();
  if (l < 1e-12) return (p - A.c).norm() - std::max(A.r, B.r);
  const Eigen::Vector3d axis = ba / l;
  const Eigen::Vector3d pa = p - A.c;
  const double y = pa.dot(axis);                                        // along the axis
  const double x = std::sqrt(std::max(pa.squaredNorm() - y * y, 0.0));  // off the axis
  // The tangent line touches the circles where the normal makes angle
  // sin(phi) = (ra - rb) / l with the radial direction.
  const double s = (A.r - B.r) / l;
  if (std::abs(s) >= 1.0) return std::min((p - A.c).norm() - A.r, (p - B.c).norm() - B.r);
  const double c = std::sqrt(1.0 - s * s);
  // Project (x, y) onto the tangent direction (-s, c) in (x, y) coordinates.
  const double t = -x * s + y * c;  // position along the tangent line, A's tangent point at 0
  if (t < 0.0) return std::hypot(x, y) - A.r;
  if (t > c * l) return std::hypot(x, y - l) - B.r;
  return x * c + y * s - A.r;
}

// Approximate signed distance to an axis-aligned ellipsoid in local
// coordinates (Quilez's bound k0 (k0 - 1) / k1).
double ellipsoid(const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const double k0 = q.cwiseQuotient(r).norm();
  const double k1 = q.cwiseQuotient(r.cwiseProduct(r)).norm();
  if (k1 < 1e-12) return -r.minCoeff();
  return k0 * (k0 - 1.0) / k1;
}

double chain(const Eigen::Vector3d& p, const Ball* balls, int first, int last) {
  double d = 1e30;
  for (int i = first; i < last; ++i) d = std::min(d, round_cone(p, balls[i], balls[i + 1]));
  return d;
}

// Monotone piecewise-cubic Hermite slopes (Fritsch and Carlson 1980, with the
// weighted harmonic mean of Fritsch and Butland), so the profile never
// overshoots between rows.
std::vector<double> pchip_slopes(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  std::vector<double> m(n, 0.0), h(n - 1), del(n - 1);
  for (size_t i = 0; i + 1 < n; ++i) {
    h[i] = x[i + 1] - x[i];
    del[i] = (y[i + 1] - y[i]) / h[i];
  }
  m[0] = del[0];
  m[n - 1] = del[n - 2];
  for (size_t i = 1; i + 1 < n; ++i) {
    if (del[i - 1] * del[i] <= 0.0) continue;
    const double w1 = 2 * h[i] + h[i - 1], w2 = h[i] + 2 * h[i - 1];
    m[i] = (w1 + w2) / (w1 / del[i - 1] + w2 / del[i]);
  }
  // End slopes must not point away from the neighbouring secant's sign.
  for (size_t e : {size_t(0), n - 1}) {
    const double d = e == 0 ? del[0] : del[n - 2];
    if (m[e] * d < 0) m[e] = 0;
  }
  return m;
}

struct Profile {
  double a, f, b, zc;
};

Profile torso_profile(const BodyShape& s, double y) {
  const auto& R = s.torso_rows;
  const auto& M = s.torso_slopes;
  y = std::clamp(y, R.front().y, R.back().y);
  size_t i = 0;
  while (i + 2 < R.size() && y > R[i + 1].y) ++i;
  const double h = R[i + 1].y - R[i].y;
  const double t = (y - R[i].y) / h;
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  auto mix = [&](double v0, double v1, int c) {
    return h00 * v0 + h10 * h * M[i][c] + h01 * v1 + h11 * h * M[i + 1][c];
  };
  Profile p;
  p.a = mix(R[i].half_width, R[i + 1].half_width, 0);
  p.f = mix(R[i].front, R[i + 1].front, 1);
  p.b = mix(R[i].back, R[i + 1].back, 2);
  p.zc = mix(R[i].center_z, R[i + 1].center_z, 3);
  const double u = (y - s.belly_y) / s.belly_sigma;
  p.f += s.m.belly_depth * gp::math::exp(-u * u);
  return p;
}

double torso_distance(const BodyShape& s, const Eigen::Vector3d& p) {
  const Profile pr = torso_profile(s, p.y());
  const double x = p.x(), z = p.z() - pr.zc;
  const double n = s.torso_exponent;
  const double u = std::abs(x) / pr.a, v = std::abs(z) / (z >= 0 ? pr.f : pr.b);
  const double rho = gp::math::pow(gp::math::pow(u, n) + gp::math::pow(v, n), 1.0 / n);
  const double r = std::hypot(x, z);
  // Distance along the horizontal ray from the centre line: exact on the
  // surface, an over-estimate elsewhere (fine for a level set).
  double d = rho > 1e-12 ? r * (1.0 - 1.0 / rho) : -std::min(pr.a, std::min(pr.f, pr.b));
  const double kcap = 0.03 * s.scale;
  d = smax(d, s.torso_bottom - p.y(), kcap);
  d = smax(d, p.y() - s.torso_top, kcap);
  return d;
}

double head_distance(const BodyShape& s, const Eigen::Vector3d& p) {
  return ellipsoid(p - s.head_center, s.head_radii);
}

// A round cone squeezed by `widening` along `lateral` (evaluated in the
// stretched space, so distances shrink by at most that factor).
double flat_round_cone(const Eigen::Vector3d& p, const Ball& A, const Ball& B, const Eigen::Vector3d& lateral,
                       double widening) {
  Eigen::Vector3d q = p - A.c;
  const double l = q.dot(lateral);
  q += lateral * (l / widening - l);
  return round_cone(A.c + q, A, B);
}

double hand_distance(const BodyShape& s, int side, const Eigen::Vector3d& p) {
  return flat_round_cone(p, s.hand[side][0], s.hand[side][1], s.hand_breadth[side], s.hand_widening);
}

double foot_distance(const BodyShape& s, int side, const Eigen::Vector3d& p) {
  const Ball& heel = s.foot[side][0];
  const Ball& toe = s.foot[side][1];
  Eigen::Vector3d axis = toe.c - heel.c;
  axis.y() = 0;
  const Eigen::Vector3d lateral = Eigen::Vector3d::UnitY().cross(axis).normalized();
  return flat_round_cone(p, heel, toe, lateral, s.foot_widening);
}

double part_distance(const BodyShape& s, int part, const Eigen::Vector3d& p) {
  switch (part) {
    case kTorso:
      return torso_distance(s, p);
    case kNeckPart:
      return round_cone(p, s.neck[0], s.neck[1]);
    case kHeadPart:
      return head_distance(s, p);
    case kLTrapezius:
      return round_cone(p, s.trapezius[0][0], s.trapezius[0][1]);
    case kRTrapezius:
      return round_cone(p, s.trapezius[1][0], s.trapezius[1][1]);
    case kLUpperArm:
      return chain(p, s.arm[0].data(), 0, 2);
    case kLForearm:
      return chain(p, s.arm[0].data(), 2, 4);
    case kLHand:
      return hand_distance(s, 0, p);
    case kRUpperArm:
      return chain(p, s.arm[1].data(), 0, 2);
    case kRForearm:
      return chain(p, s.arm[1].data(), 2, 4);
    case kRHand:
      return hand_distance(s, 1, p);
    case kLThigh:
      return chain(p, s.leg[0].data(), 0, 1);
    case kLShin:
      return chain(p, s.leg[0].data(), 1, 3);
    case kLFoot:
      return foot_distance(s, 0, p);
    case kRThigh:
      return chain(p, s.leg[1].data(), 0, 1);
    case kRShin:
      return chain(p, s.leg[1].data(), 1, 3);
    case kRFoot:
      return foot_distance(s, 1, p);
    default:
      return 1e30;
  }
}

double box_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.norm();
}

// Perimeter of the torso cross-section with unit half-width and the given
// depth ratios (numerically, 720 samples of the super-ellipse).
double unit_section_perimeter(double front, double back, double n) {
  const int N = 720;
  double per = 0;
  Eigen::Vector2d prev;
  for (int i = 0; i <= N; ++i) {
    const double t = 2 * kPi * i / N;
    const double c = gp::math::cos(t), s = gp::math::sin(t);
    const double x = (c < 0 ? -1 : 1) * gp::math::pow(std::abs(c), 2.0 / n);
    const double z = (s < 0 ? -back : front) * gp::math::pow(std::abs(s), 2.0 / n);
    const Eigen::Vector2d q(x, z);
    if (i > 0) per += (q - prev).norm();
    prev = q;
  }
  return per;
}

}  // namespace

int body_part_chain(int part) {
  switch (part) {
    case kLUpperArm:
    case kLForearm:
    case kLHand:
      return 1;
    case kRUpperArm:
    case kRForearm:
    case kRHand:
      return 2;
    case kLThigh:
    case kLShin:
    case kLFoot:
      return 3;
    case kRThigh:
    case kRShin:
    case kRFoot:
      return 4;
    default:
      return 0;
  }
}

int body_part_bone(int part) {
  switch (part) {
    case kTorso:
      return kPelvis;
    case kNeckPart:
      return kNeck;
    case kHeadPart:
      return kHead;
    case kLTrapezius:
      return kLClavicle;
    case kRTrapezius:
      return kRClavicle;
    case kLUpperArm:
      return kLShoulder;
    case kLForearm:
      return kLElbow;
    case kLHand:
      return kLWrist;
    case kRUpperArm:
      return kRShoulder;
    case kRForearm:
      return kRElbow;
    case kRHand:
      return kRWrist;
    case kLThigh:
      return kLHip;
    case kLShin:
      return kLKnee;
    case kLFoot:
      return kLAnkle;
    case kRThigh:
      return kRHip;
    case kRShin:
      return kRKnee;
    case kRFoot:
      return kRAnkle;
    default:
      return kPelvis;
  }
}

Eigen::Vector3d torso_bone_weights(const BodyShape& s, double y) {
  auto step = [](double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
  };
  const Eigen::MatrixXd& J = s.skeleton.rest;
  const double w = 0.06 * s.scale;
  const double y1 = 0.5 * (J(kPelvis, 1) + J(kSpine, 1));
  const double y2 = 0.5 * (J(kSpine, 1) + J(kChest, 1));
  const double t1 = step((y - y1 + w) / (2 * w));
  const double t2 = step((y - y2 + w) / (2 * w));
  return Eigen::Vector3d(1 - t1, t1 - t2, t2);
}

void body_part_distances(const BodyShape& s, const Eigen::Vector3d& p, std::array<double, kPartCount>& d) {
  for (int i = 0; i < kPartCount; ++i) d[i] = part_distance(s, i, p);
}

double body_field(const BodyShape& s, const Eigen::Vector3d& p) {
  // Parts farther than `far` can only raise the smooth minimum where the
  // field is far from zero, so their box distance (a lower bound) stands in.
  const double far = 0.12 * s.scale;
  std::array<double, kPartCount> d;
  for (int i = 0; i < kPartCount; ++i) {
    const double lb = box_distance(p, s.part_min[i], s.part_max[i]);
    d[i] = lb > far ? lb : part_distance(s, i, p);
  }
  const double ks = s.blend_small;
  double torso = smin(d[kTorso], d[kNeckPart], s.blend_torso);
  torso = smin(torso, d[kLTrapezius], s.blend_torso);
  torso = smin(torso, d[kRTrapezius], s.blend_torso);
  torso = smin(torso, d[kHeadPart], 0.8 * s.blend_torso);
  double arms = 1e30, legs = 1e30;
  for (int side = 0; side < 2; ++side) {
    const int o = side * 3;
    double arm = smin(d[kLUpperArm + o], d[kLForearm + o], ks);
    arm = smin(arm, d[kLHand + o], 1.5 * ks);
    arms = std::min(arms, arm);
    double leg = smin(d[kLThigh + o], d[kLShin + o], ks);
    leg = smin(leg, d[kLFoot + o], 2 * ks);
    legs = std::min(legs, leg);
  }
  // Left and right limbs are joined by a plain minimum and then blended with
  // the torso as a whole, so the blend never bridges the gap between the thighs.
  double body = smin(torso, arms, s.blend_limb);
  body = smin(body, legs, s.blend_leg);
  return body;
}

void update_bounds(BodyShape& s) {
  std::vector<double> ys, a, f, b, zc;
  for (const TorsoRow& r : s.torso_rows) {
    ys.push_back(r.y);
    a.push_back(r.half_width);
    f.push_back(r.front);
    b.push_back(r.back);
    zc.push_back(r.center_z);
  }
  const auto ma = pchip_slopes(ys, a), mf = pchip_slopes(ys, f), mb = pchip_slopes(ys, b),
             mz = pchip_slopes(ys, zc);
  s.torso_slopes.resize(ys.size());
  for (size_t i = 0; i < ys.size(); ++i) s.torso_slopes[i] = Eigen::Vector4d(ma[i], mf[i], mb[i], mz[i]);

  auto ball_box = [](const Ball* balls, int first, int last, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    lo.setConstant(1e30);
    hi.setConstant(-1e30);
    for (int i = first; i <= last; ++i) {
      lo = lo.cwiseMin(balls[i].c - Eigen::Vector3d::Constant(balls[i].r));
      hi = hi.cwiseMax(balls[i].c + Eigen::Vector3d::Constant(balls[i].r));
    }
  };
  // Torso: sample the profile (its extremes lie between rows).
  Eigen::Vector3d lo(1e30, s.torso_bottom, 1e30), hi(-1e30, s.torso_top, -1e30);
  for (int i = 0; i <= 200; ++i) {
    const double y = s.torso_bottom + (s.torso_top - s.torso_bottom) * i / 200.0;
    const Profile pr = torso_profile(s, y);
    lo.x() = std::min(lo.x(), -pr.a);
    hi.x() = std::max(hi.x(), pr.a);
    lo.z() = std::min(lo.z(), pr.zc - pr.b);
    hi.z() = std::max(hi.z(), pr.zc + pr.f);
  }
  s.part_min[kTorso] = lo;
  s.part_max[kTorso] = hi;
  ball_box(s.neck.data(), 0, 1, s.part_min[kNeckPart], s.part_max[kNeckPart]);
  s.part_min[kHeadPart] = s.head_center - s.head_radii;
  s.part_max[kHeadPart] = s.head_center + s.head_radii;
  for (int side = 0; side < 2; ++side) {
    const int o = side * 3;
    ball_box(s.trapezius[side].data(), 0, 1, s.part_min[kLTrapezius + side], s.part_max[kLTrapezius + side]);
    ball_box(s.arm[side].data(), 0, 2, s.part_min[kLUpperArm + o], s.part_max[kLUpperArm + o]);
    ball_box(s.arm[side].data(), 2, 4, s.part_min[kLForearm + o], s.part_max[kLForearm + o]);
    Eigen::Vector3d hlo, hhi;
    ball_box(s.hand[side].data(), 0, 1, hlo, hhi);
    const Eigen::Vector3d hw = Eigen::Vector3d::Constant((s.hand_widening - 1.0) * s.hand[side][0].r);
    s.part_min[kLHand + o] = hlo - hw;
    s.part_max[kLHand + o] = hhi + hw;
    ball_box(s.leg[side].data(), 0, 1, s.part_min[kLThigh + o], s.part_max[kLThigh + o]);
    ball_box(s.leg[side].data(), 1, 3, s.part_min[kLShin + o], s.part_max[kLShin + o]);
    Eigen::Vector3d flo, fhi;
    ball_box(s.foot[side].data(), 0, 1, flo, fhi);
    const Eigen::Vector3d widen =
        Eigen::Vector3d::Constant((s.foot_widening - 1.0) * std::max(s.foot[side][0].r, s.foot[side][1].r));
    s.part_min[kLFoot + o] = flo - widen;
    s.part_max[kLFoot + o] = fhi + widen;
  }
  s.box_min.setConstant(1e30);
  s.box_max.setConstant(-1e30);
  for (int i = 0; i < kPartCount; ++i) {
    s.box_min = s.box_min.cwiseMin(s.part_min[i]);
    s.box_max = s.box_max.cwiseMax(s.part_max[i]);
  }
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.03 * s.scale);
  s.box_min -= margin;
  s.box_max += margin;
}

namespace {

// Landmark heights from anthropometric proportions of stature (e.g. the
// ratios tabulated in Drillis and Contini 1966) and the given inseam, metres.
struct BodyHeights {
  double crotch, shoulder, torso;  // torso: shoulder - crotch
  double hip, waist, under, chest, armpit;
};

BodyHeights body_heights(const Measurements& m) {
  BodyHeights h;
  h.crotch = m.inseam + 0.5 * std::abs(m.leg_length_difference);
  h.shoulder = 0.818 * m.height;
  h.torso = h.shoulder - h.crotch;
  h.hip = h.crotch + 0.14 * h.torso;
  h.waist = h.crotch + 0.45 * h.torso;
  h.under = h.crotch + 0.635 * h.torso;
  h.chest = h.crotch + 0.73 * h.torso;
  h.armpit = h.crotch + 0.85 * h.torso;
  return h;
}

// Rows with depth ratios of typical adult cross-sections; half-widths are
// solved from the girths (fit_girths refines them on the final shape).
void build_torso(BodyShape& s, const Measurements& m, const BodyHeights& y) {
  const double k = s.scale;
  const double n = s.torso_exponent;
  auto row_for = [&](double at, double girth, double front, double back, double zc) {
    const double a = girth / unit_section_perimeter(front, back, n);
    return TorsoRow{at, a, front * a, back * a, zc};
  };
  const TorsoRow hip = row_for(y.hip, m.hip, 0.60, 0.80, -0.01 * k);
  const TorsoRow waist = row_for(y.waist, m.waist, 0.72, 0.70, 0.0);
  const TorsoRow under = row_for(y.under, m.under_bust, 0.72, 0.72, 0.0);
  const TorsoRow chest = row_for(y.chest, m.chest, 0.80, 0.72, 0.0);
  TorsoRow bottom{y.crotch - 0.005 * k, 0.86 * hip.half_width, 0.85 * hip.front, 0.8 * hip.back, hip.center_z};
  TorsoRow armpit{y.armpit, 0.96 * chest.half_width, 0.66 * chest.half_width, 0.70 * chest.half_width,
                  -0.005 * k};
  TorsoRow shoulder{y.shoulder - 0.025 * k, std::max(0.5 * m.shoulder_width - 0.055 * k, 0.07 * k), 0.075 * k,
                    0.08 * k, -0.015 * k};
  TorsoRow top{y.shoulder + 0.045 * k, 0.06 * k, 0.05 * k, 0.06 * k, -0.02 * k};
  s.torso_rows = {bottom, hip, waist, under, chest, armpit, shoulder, top};
  s.torso_bottom = bottom.y;
  s.torso_top = top.y;
  s.belly_y = y.waist - 0.03 * k;
  s.belly_sigma = 0.16 * y.torso;
}

// Neck and head.
void build_neck_and_head(BodyShape& s, const Measurements& m, const BodyHeights& y) {
  const double k = s.scale, H = m.height;
  const double r_neck = m.neck / (2 * kPi);
  s.neck[0] = Ball{Eigen::Vector3d(0, y.shoulder + 0.005 * k, -0.02 * k), 1.12 * r_neck};
  s.neck[1] = Ball{Eigen::Vector3d(0, H - 0.17 * k, -0.01 * k), r_neck};
  s.head_radii = Eigen::Vector3d(0.075, 0.11, 0.095) * k;
  s.head_center = Eigen::Vector3d(0, H - s.head_radii.y(), 0.012 * k);
}

// Arms in the A-pose, with mitten hands.
void build_arms(BodyShape& s, const Measurements& m, const BodyHeights& y) {
  const double k = s.scale;
  const double shoulder_y = y.shoulder;
  const double r_upper = m.upper_arm / (2 * kPi), r_wrist = m.wrist / (2 * kPi);
  const double arm_angle = 42.0 * kPi / 180.0;
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1.0 : -1.0;
    s.trapezius[side][0] =
        Ball{Eigen::Vector3d(sx * 0.035 * k, shoulder_y + 0.02 * k, -0.025 * k), 0.035 * k};
    s.trapezius[side][1] =
        Ball{Eigen::Vector3d(sx * (0.5 * m.shoulder_width - 0.035 * k), shoulder_y - 0.02 * k, -0.01 * k),
             0.03 * k};
    const Eigen::Vector3d d(sx * gp::math::sin(arm_angle), -gp::math::cos(arm_angle), 0.0);
    const double L = m.arm_length + sx * 0.5 * m.arm_length_difference;
    const double Lj = L - 0.03 * k;  // the shoulder point sits above the joint centre
    const double u = 0.54 * Lj, f = 0.46 * Lj;
    const Eigen::Vector3d S0(sx * (0.5 * m.shoulder_width - 0.03 * k), shoulder_y - 0.045 * k, -0.005 * k);
    auto& A = s.arm[side];
    A[0] = Ball{S0, 1.1 * r_upper};
    A[1] = Ball{S0 + 0.5 * u * d, r_upper};
    A[2] = Ball{S0 + u * d, std::max(0.78 * r_upper, 1.1 * r_wrist)};
    A[3] = Ball{S0 + (u + 0.25 * f) * d, std::max(0.88 * r_upper, 1.15 * r_wrist)};
    A[4] = Ball{S0 + Lj * d, r_wrist};
    // Mitten: palm thickness ~1.1 wrist radius, breadth ~2.9 times that
    // (hand breadth about half the wrist girth), palms facing the thighs.
    const double hand_length = 0.33 * L;
    const double r_palm = 0.55 * r_wrist, r_tip = 0.4 * r_wrist;
    s.hand[side][0] = Ball{A[4].c + 0.15 * hand_length * d, r_palm};
    s.hand[side][1] = Ball{A[4].c + (hand_length - r_tip) * d, r_tip};
    s.hand_breadth[side] = Eigen::Vector3d::UnitZ();
  }
}

// Legs and feet: the inner thigh surfaces are `gap` apart at the crotch.
void build_legs(BodyShape& s, const Measurements& m, const BodyHeights& y) {
  const double k = s.scale;
  const double crotch = y.crotch, ld = m.leg_length_difference;
  const double r_thigh = m.thigh / (2 * kPi);
  const double gap = 0.022 * k;
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1.0 : -1.0;
    const double leg_len = m.inseam + sx * 0.5 * ld;
    const double floor_y = crotch - leg_len;
    const double ankle_y = floor_y + 0.075 * k;
    const double knee_y = floor_y + 0.61 * leg_len;
    const double xc = r_thigh + 0.5 * gap;
    const double spread = 0.035 * k;
    auto axis_x = [&](double at) { return sx * (xc + (crotch - at) / (crotch - ankle_y) * spread); };
    const double hip_y = crotch + 0.07 * k;
    const double calf_y = knee_y - 0.28 * (knee_y - ankle_y);
    auto& Lg = s.leg[side];
    // The thigh cone starts at crotch level (its top stays inside the seat,
    // so the hip girth is the torso's); the hip joint sits higher.
    s.hip_joint[side] = Eigen::Vector3d(axis_x(hip_y), hip_y, -0.01 * k);
    const double top_y = crotch + 0.01 * k;
    Lg[0] = Ball{Eigen::Vector3d(axis_x(top_y), top_y, -0.005 * k), r_thigh};
    Lg[1] = Ball{Eigen::Vector3d(axis_x(knee_y), knee_y, 0.0), 0.64 * r_thigh};
    Lg[2] = Ball{Eigen::Vector3d(axis_x(calf_y), calf_y, -0.012 * k), 0.62 * r_thigh};
    Lg[3] = Ball{Eigen::Vector3d(axis_x(ankle_y), ankle_y, -0.01 * k), std::max(0.39 * r_thigh, 0.03 * k)};
    const Eigen::Vector3d ankle = Lg[3].c;
    s.foot[side][0] = Ball{Eigen::Vector3d(ankle.x(), floor_y + 0.032 * k, ankle.z() - 0.03 * k), 0.032 * k};
    s.foot[side][1] =
        Ball{Eigen::Vector3d(ankle.x() + sx * 0.02 * k, floor_y + 0.02 * k, ankle.z() + 0.165 * k), 0.02 * k};
  }
}

// Skeleton (joint centres), from the limbs' balls.
void build_skeleton(BodyShape& s, const Measurements& m, const BodyHeights& y) {
  const double k = s.scale, H = m.height;
  Skeleton& sk = s.skeleton;
  sk.names = avatar_joint_names();
  sk.parents = avatar_joint_parents();
  sk.rest.resize(kJointCount, 3);
  auto set = [&](int j, const Eigen::Vector3d& p) { sk.rest.row(j) = p.transpose(); };
  set(kPelvis, Eigen::Vector3d(0, y.crotch + 0.07 * k, -0.01 * k));
  set(kSpine, Eigen::Vector3d(0, y.waist, -0.03 * k));
  set(kChest, Eigen::Vector3d(0, y.under, -0.03 * k));
  set(kNeck, Eigen::Vector3d(0, y.shoulder + 0.03 * k, -0.025 * k));
  set(kHead, Eigen::Vector3d(0, H - 0.2 * k, -0.01 * k));
  for (int side = 0; side < 2; ++side) {
    const double sx = side == 0 ? 1.0 : -1.0;
    const int o = side * 4;
    set(kLClavicle + o, Eigen::Vector3d(sx * 0.02 * k, y.shoulder - 0.01 * k, 0.0));
    set(kLShoulder + o, s.arm[side][0].c);
    set(kLElbow + o, s.arm[side][2].c);
    set(kLWrist + o, s.arm[side][4].c);
    const int g = side * 3;
    set(kLHip + g, s.hip_joint[side]);
    set(kLKnee + g, s.leg[side][1].c);
    set(kLAnkle + g, s.leg[side][3].c);
  }
}

// Girth landmarks: where each measured girth is taken, and the bone it follows.
void build_girth_landmarks(BodyShape& s, const Measurements& m, const BodyHeights& y) {
  const double k = s.scale, H = m.height;
  const double y_neck = 0.5 * (y.shoulder + 0.045 * k + H - 2 * s.head_radii.y()) + 0.005 * k;
  auto torso_mark = [&](const char* name, double target, double at, int bone) {
    GirthLandmark g;
    g.name = g.field = name;
    g.target = target;
    g.center = Eigen::Vector3d(0, at, 0);
    g.normal = Eigen::Vector3d::UnitY();
    g.bone = bone;
    return g;
  };
  s.landmarks.push_back(torso_mark("neck", m.neck, y_neck, kNeck));
  s.landmarks.back().center.z() = -0.015 * k;
  s.landmarks.push_back(torso_mark("chest", m.chest, y.chest, kChest));
  s.landmarks.push_back(torso_mark("under_bust", m.under_bust, y.under, kChest));
  s.landmarks.push_back(torso_mark("waist", m.waist, y.waist, kSpine));
  s.landmarks.push_back(torso_mark("hip", m.hip, y.hip, kPelvis));
  for (int side = 0; side < 2; ++side) {
    const std::string sfx = side == 0 ? "_left" : "_right";
    const auto& A = s.arm[side];
    const Eigen::Vector3d d = (A[4].c - A[0].c).normalized();
    GirthLandmark ua;
    ua.name = "upper_arm" + sfx;
    ua.field = "upper_arm";
    ua.target = m.upper_arm;
    ua.center = A[1].c;
    ua.normal = d;
    ua.bone = side == 0 ? kLShoulder : kRShoulder;
    s.landmarks.push_back(ua);
    GirthLandmark wr = ua;
    wr.name = "wrist" + sfx;
    wr.field = "wrist";
    wr.target = m.wrist;
    wr.center = A[4].c - 0.012 * k * d;
    wr.bone = side == 0 ? kLElbow : kRElbow;
    s.landmarks.push_back(wr);
    const auto& Lg = s.leg[side];
    const double at = y.crotch - 0.03 * k;
    const double t = (Lg[0].c.y() - at) / (Lg[0].c.y() - Lg[1].c.y());
    GirthLandmark th;
    th.name = "thigh" + sfx;
    th.field = "thigh";
    th.target = m.thigh;
    th.center = Lg[0].c + t * (Lg[1].c - Lg[0].c);
    th.normal = Eigen::Vector3d::UnitY();
    th.bone = side == 0 ? kLHip : kRHip;
    s.landmarks.push_back(th);
  }
}

}  // namespace

BodyShape build_body_shape(const Measurements& m) {
  BodyShape s;
  s.m = m;
  const double k = m.height / 1.70;
  s.scale = k;
  s.blend_torso = 0.03 * k;
  s.blend_limb = 0.035 * k;
  s.blend_leg = 0.03 * k;
  s.blend_small = 0.012 * k;
  const BodyHeights heights = body_heights(m);
  build_torso(s, m, heights);
  build_neck_and_head(s, m, heights);
  build_arms(s, m, heights);
  build_legs(s, m, heights);
  build_skeleton(s, m, heights);
  build_girth_landmarks(s, m, heights);
  update_bounds(s);
  return s;
}

void scale_landmark_parameter(BodyShape& s, size_t i, double factor) {
  const GirthLandmark& g = s.landmarks.at(i);
  auto scale_row = [&](size_t r) {
    s.torso_rows[r].half_width *= factor;
    s.torso_rows[r].front *= factor;
    s.torso_rows[r].back *= factor;
  };
  const int side = g.name.size() > 5 && g.name.substr(g.name.size() - 5) == "right" ? 1 : 0;
  if (g.field == "neck") {
    s.neck[0].r *= factor;
    s.neck[1].r *= factor;
  } else if (g.field == "hip") {
    scale_row(1);
    // The crotch row follows the seat so the buttocks keep their shape.
    scale_row(0);
  } else if (g.field == "waist") {
    scale_row(2);
  } else if (g.field == "under_bust") {
    scale_row(3);
  } else if (g.field == "chest") {
    scale_row(4);
  } else if (g.field == "upper_arm") {
    s.arm[side][1].r *= factor;
  } else if (g.field == "wrist") {
    s.arm[side][4].r *= factor;
  } else if (g.field == "thigh") {
    s.leg[side][0].r *= factor;
  } else {
    throw Error(ExitCode::internal, "no shape parameter for landmark '" + g.name + "'");
  }
}

double field_girth(const BodyShape& s, const GirthLandmark& g, int rays) {
  const Eigen::Vector3d n = g.normal.normalized();
  const Eigen::Vector3d e1 =
      (std::abs(n.y()) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(rays);
  const double max_len = 0.6 * s.scale;
  const double min_step = 0.001 * s.scale;
  if (body_field(s, g.center) >= 0)
    throw GeometryError("girth landmark '" + g.name + "' lies outside the body");
  for (int i = 0; i < rays; ++i) {
    const double t = 2 * kPi * i / rays;
    const Eigen::Vector3d dir = gp::math::cos(t) * e1 + gp::math::sin(t) * e2;
    double lo = 0.0, hi = -1.0;
    double r = 0.0;
    while (r < max_len) {
      const double f = body_field(s, g.center + r * dir);
      if (f >= 0) {
        hi = r;
        break;
      }
      lo = r;
      r += std::max(0.5 * -f, min_step);
    }
    if (hi < 0) throw GeometryError("girth ray does not leave the body at landmark '" + g.name + "'");
    for (int it = 0; it < 30 && hi - lo > 1e-6; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (body_field(s, g.center + mid * dir) < 0)
        lo = mid;
      else
        hi = mid;
    }
    const double rr = 0.5 * (lo + hi);
    pts.emplace_back(rr * gp::math::cos(t), rr * gp::math::sin(t));
  }
  return convex_hull_perimeter(pts);
}

double fit_girths(BodyShape& s, double tolerance, int max_iterations,
                  const std::vector<double>& target_scale) {
  double worst = 0.0;
  for (int it = 0; it < max_iterations; ++it) {
    worst = 0.0;
    std::vector<double> factors(s.landmarks.size());
    for (size_t i = 0; i < s.landmarks.size(); ++i) {
      const double target = s.landmarks[i].target * (i < target_scale.size() ? target_scale[i] : 1.0);
      const double g = field_girth(s, s.landmarks[i]);
      worst = std::max(worst, std::abs(g - target));
      factors[i] = std::clamp(target / g, 0.75, 1.33);
    }
    if (worst <= tolerance) break;
    for (size_t i = 0; i < s.landmarks.size(); ++i) scale_landmark_parameter(s, i, factors[i]);
    update_bounds(s);
  }
  return worst;
}

}  // namespace gp
