#include "core/math.h"

#include <cmath>
#include <limits>

// Classical constructions: Cody & Waite argument reduction with constants
// split so that k * hi is exact, and series kernels on the reduced ranges
// (Muller, "Elementary Functions: Algorithms and Implementation", ch. 6 and
// 11). The series are truncated where the next term is below 2^-60 of the
// result over the reduced range. Constants are written as hexadecimal
// floating-point literals, rounded from 80-digit values.
namespace gp::math {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ln 2 = kLn2Hi + kLn2Lo, kLn2Hi with 32 significant bits (e * kLn2Hi is
// exact for every binary exponent e of a double).
constexpr double kLn2Hi = 0x1.62e42fee00000p-1;
constexpr double kLn2Lo = 0x1.a39ef35793c76p-33;
constexpr double kInvLn2 = 0x1.71547652b82fep+0;
constexpr double kSqrtHalf = 0x1.6a09e667f3bcdp-1;

// pi / 2 in four parts of 27 significant bits and a tail: k * part is exact
// for |k| < 2^26, i.e. |x| below about 1e8.
constexpr double kPio2Part[4] = {0x1.921fb54000000p+0, 0x1.10b4610000000p-30, 0x1.a626330000000p-58,
                                 0x1.45c06e0e68948p-86};
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
constexpr double kPiHi = 0x1.921fb54442d18p+1, kPiLo = 0x1.1a62633145c07p-53;
constexpr double kPio2Hi = 0x1.921fb54442d18p+0, kPio2Lo = 0x1.1a62633145c07p-54;

// atan(k / 16) = hi + lo, k = 0 .. 16.
constexpr double kAtanTable[17][2] = {
    {0x0.0p+0, 0x0.0p+0},
    {0x1.ff55bb72cfdeap-5, -0x1.c934d86d23f1dp-60},
    {0x1.fd5ba9aac2f6ep-4, -0x1.cd37686760c17p-59},
    {0x1.7b97b4bce5b02p-3, 0x1.347b0b4f881cap-58},
    {0x1.f5b75f92c80ddp-3, 0x1.8ab6e3cf7afbdp-57},
    {0x1.362773707ebccp-2, -0x1.963a544b672d8p-57},
    {0x1.6f61941e4def1p-2, -0x1.c63aae6f6e918p-56},
    {0x1.a64eec3cc23fdp-2, -0x1.24dec1b50b7ffp-56},
    {0x1.dac670561bb4fp-2, 0x1.a2b7f222f65e2p-56},
    {0x1.0657e94db30d0p-1, -0x1.d5b495f6349e6p-56},
    {0x1.1e00babdefeb4p-1, -0x1.928df287a668fp-58},
    {0x1.345f01cce37bbp-1, 0x1.1021137c71102p-55},
    {0x1.4978fa3269ee1p-1, 0x1.2419a87f2a458p-56},
    {0x1.5d58987169b18p-1, 0x1.0028e4bc5e7cap-57},
    {0x1.700a7c5784634p-1, -0x1.8c34d25aadef6p-56},
    {0x1.819d0b7158a4dp-1, -0x1.bf76229d3b917p-56},
    {0x1.921fb54442d18p-1, 0x1.1a62633145c07p-55},
};

// sin and cos of r + e for |r| <= pi / 4 (plus a rounding's slack) and a
// tail |e| <= ulp(r) from the argument reduction.
double sin_kernel(double r, double e) {
  const double z = r * r;
  // -1/3! + z (1/5! - z (1/7! - ...)) up to r^17 / 17!.
  double p = 1.0 / 355687428096000.0;
  p = p * z - 1.0 / 1307674368000.0;
  p = p * z + 1.0 / 6227020800.0;
  p = p * z - 1.0 / 39916800.0;
  p = p * z + 1.0 / 362880.0;
  p = p * z - 1.0 / 5040.0;
  p = p * z + 1.0 / 120.0;
  p = p * z - 1.0 / 6.0;
  // sin(r + e) = sin r + e cos r, cos r = 1 - z/2 to the precision e needs.
  return r + (r * z * p + e * (1.0 - 0.5 * z));
}

double cos_kernel(double r, double e) {
  const double z = r * r;
  // 1/4! - z (1/6! - ...) up to r^18 / 18!.
  double q = 1.0 / 6402373705728000.0;
  q = q * z - 1.0 / 20922789888000.0;
  q = q * z + 1.0 / 87178291200.0;
  q = q * z - 1.0 / 479001600.0;
  q = q * z + 1.0 / 3628800.0;
  q = q * z - 1.0 / 40320.0;
  q = q * z + 1.0 / 720.0;
  q = q * z - 1.0 / 24.0;
  // 1 - z/2 + z^2 (1/24 - ...), with the rounding error of 1 - z/2 added
  // back, and cos(r + e) = cos r - e sin r.
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  return w + ((((1.0 - w) - hz) - z * z * q) - e * r);
}

// x = k pi/2 + r + e with |r| <= pi/4 (about) and e the rounding error of r:
// returns r, sets e and k mod 4.
double reduce_quadrant(double x, double& e, int& quadrant) {
  e = 0.0;
  if (std::fabs(x) <= 0x1.921fb54442d18p-1) {
    quadrant = 0;
    return x;
  }
  const double k = std::rint(x * kTwoOverPi);
  // x - k p0 is exact (Sterbenz); the other parts' products are exact and
  // the errors of the differences are carried in e.
  const double t = x - k * kPio2Part[0];
  const double w = k * kPio2Part[1];
  const double r = t - w;
  e = ((t - r) - w) - (k * kPio2Part[2] + k * kPio2Part[3]);
  const double r2 = r + e;
  e = e - (r2 - r);
  const double k4 = k - 4.0 * std::floor(k * 0.25);  // k mod 4, exact
  quadrant = static_cast<int>(k4);
  return r2;
}

// The exact product a b = p + err (Dekker 1971, with Veltkamp's splitting;
// no FMA, so that every CPU computes it alike). Valid while a b neither
// overflows nor underflows.
double two_product(double a, double b, double& err) {
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double p = a * b;
  const double ta = kSplit * a, tb = kSplit * b;
  const double ah = ta - (ta - a), al = a - ah;
  const double bh = tb - (tb - b), bl = b - bh;
  err = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
  return p;
}

// atan(t + t_lo) for 0 <= t <= 1, |t_lo| <= ulp(t): the table's hi,
// returned, plus a tail of the table's lo and a short series.
double atan_unit(double t, double t_lo, double& tail) {
  // Below 1/16 the series alone (|v| <= 1/16): with the table's first entry a
  // result below it would lose the last bit to cancellation.
  const int k = t < 0.0625 ? 0 : static_cast<int>(std::rint(16.0 * t));
  const double c = k / 16.0;
  // v = (t + t_lo - c) / (1 + t c), |v| <= 1/32: t - c is exact, and the
  // denominator is carried in two parts (its rounding would otherwise cost
  // half an ulp of the result).
  double pe = 0.0;
  const double pc = two_product(t, c, pe);
  const double dh = 1.0 + pc, dl = ((1.0 - dh) + pc) + pe;
  const double q = ((t - c) + t_lo) / dh;
  const double v = q - q * (dl / dh);
  const double z = v * v;
  // atan v = v - v^3/3 + ... up to v^13 / 13 (|v| <= 1/16).
  double p = 1.0 / 13.0;
  p = p * z - 1.0 / 11.0;
  p = p * z + 1.0 / 9.0;
  p = p * z - 1.0 / 7.0;
  p = p * z + 1.0 / 5.0;
  p = p * z - 1.0 / 3.0;
  tail = kAtanTable[k][1] + (v + v * z * p);
  return kAtanTable[k][0];
}

// q = a / b for 0 < a <= b, with q_lo the rounding error of the quotient.
double divide(double a, double b, double& q_lo) {
  const double q = a / b;
  double err = 0.0;
  const double p = two_product(q, b, err);
  // Exact products need q b within range: far below it the tail is negligible.
  q_lo = (q > 0x1p-900 && b < 0x1p+900) ? ((a - p) - err) / b : 0.0;
  return q;
}

}  // namespace

double exp(double x) {
  if (std::isnan(x)) return x;
  if (x > 0x1.62e42fefa39efp+9) return kInf;  // above ln(DBL_MAX)
  if (x < -0x1.74910d52d3051p+9) return 0.0;  // below ln of the smallest subnormal / 2
  const double k = std::rint(x * kInvLn2);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  // exp r = 1 + r + r^2 (1/2! + r (1/3! + ...)) up to r^13 / 13!, |r| <= ln2 / 2.
  double p = 1.0 / 6227020800.0;
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  const double e = 1.0 + (r + r * r * p);
  return std::ldexp(e, static_cast<int>(k));
}

double log(double x) {
  if (std::isnan(x)) return x;
  if (x < 0.0) return kNaN;
  if (x == 0.0) return -kInf;
  if (std::isinf(x)) return x;
  int exponent = 0;
  double m = std::frexp(x, &exponent);  // x = m 2^exponent, m in [1/2, 1), exact for subnormals too
  if (m < kSqrtHalf) {
    m *= 2.0;
    --exponent;
  }
  // log m = log(1 + f) = 2 atanh s with s = f / (2 + f), |s| <= 0.1716:
  // 2 atanh s = 2 s + s R, R = 2 s^2/3 + 2 s^4/5 + ..., and 2 s = f - s f.
  const double f = m - 1.0;
  const double s = f / (2.0 + f);
  const double z = s * s;
  double R = 2.0 / 21.0;
  R = R * z + 2.0 / 19.0;
  R = R * z + 2.0 / 17.0;
  R = R * z + 2.0 / 15.0;
  R = R * z + 2.0 / 13.0;
  R = R * z + 2.0 / 11.0;
  R = R * z + 2.0 / 9.0;
  R = R * z + 2.0 / 7.0;
  R = R * z + 2.0 / 5.0;
  R = R * z + 2.0 / 3.0;
  R *= z;
  const double hfsq = 0.5 * f * f;
  const double e = exponent;
  return e * kLn2Hi - ((hfsq - (s * (hfsq + R) + e * kLn2Lo)) - f);
}

double pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  const bool y_integer = std::rint(y) == y;
  const bool y_odd = y_integer && std::fabs(y) < 0x1p53 && std::fmod(y, 2.0) != 0.0;
  if (std::isinf(y)) {
    const double ax = std::fabs(x);
    if (ax == 1.0) return 1.0;
    return (ax < 1.0) == (y < 0.0) ? kInf : 0.0;
  }
  if (x == 0.0) {
    const double magnitude = y < 0.0 ? kInf : 0.0;
    return y_odd ? std::copysign(magnitude, x) : magnitude;
  }
  if (std::isinf(x)) {
    const double magnitude = (y < 0.0) ? 0.0 : kInf;
    return x < 0.0 && y_odd ? -magnitude : magnitude;
  }
  if (x < 0.0) {
    if (!y_integer) return kNaN;
    const double magnitude = exp(y * log(-x));
    return y_odd ? -magnitude : magnitude;
  }
  return exp(y * log(x));
}

std::pair<double, double> sincos(double x) {
  if (!std::isfinite(x)) return {kNaN, kNaN};
  if (std::fabs(x) < 0x1p-27) return {x, 1.0};  // x - x^3/6 rounds to x, keeping its sign
  int quadrant = 0;
  double e = 0.0;
  const double r = reduce_quadrant(x, e, quadrant);
  const double s = sin_kernel(r, e), c = cos_kernel(r, e);
  switch (quadrant) {
    case 0: return {s, c};
    case 1: return {c, -s};
    case 2: return {-s, -c};
    default: return {-c, s};
  }
}

double sin(double x) { return sincos(x).first; }

double cos(double x) { return sincos(x).second; }

double atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  const double ax = std::fabs(x), ay = std::fabs(y);
  double angle;  // in [0, pi], for |y| and the sign of x
  if (ay == 0.0) {
    angle = std::signbit(x) ? kPiHi : 0.0;
  } else if (std::isinf(ax) || std::isinf(ay)) {
    if (std::isinf(ax) && std::isinf(ay))
      angle = std::signbit(x) ? 3.0 * 0x1.921fb54442d18p-1 : 0x1.921fb54442d18p-1;
    else if (std::isinf(ay))
      angle = kPio2Hi;
    else
      angle = std::signbit(x) ? kPiHi : 0.0;
  } else {
    // atan of the ratio <= 1, in two parts; pi/2 minus it where |y| > |x|.
    double tail = 0.0, hi = 0.0;
    double t_lo = 0.0;
    if (ay <= ax) {
      const double t = divide(ay, ax, t_lo);
      hi = atan_unit(t, t_lo, tail);
    } else {
      const double t = divide(ax, ay, t_lo);
      const double head = atan_unit(t, t_lo, tail);
      const double h = kPio2Hi - head;
      tail = (kPio2Hi - h - head) + (kPio2Lo - tail);
      hi = h;
    }
    if (std::signbit(x)) {
      const double h = kPiHi - hi;
      tail = (kPiHi - h - hi) + (kPiLo - tail);
      hi = h;
    }
    angle = hi + tail;
  }
  return std::copysign(angle, y);
}

}  // namespace gp::math
