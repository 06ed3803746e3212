#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "core/math.h"

// The portable elementary functions against glibc's long double versions
// (64-bit significand: 11 bits more than a double, so their rounding to double
// is the correctly rounded result but for ties within 2^-11 ulp).

namespace {

// Distance of `got` from the exact value `ref` in ulps of the double nearest ref.
double ulps(double got, long double ref) {
  const double r = static_cast<double>(ref);
  const double ulp = std::nextafter(std::fabs(r), std::numeric_limits<double>::infinity()) - std::fabs(r);
  return static_cast<double>(std::fabs(static_cast<long double>(got) - ref) / ulp);
}

template <class F, class G>
double worst_ulps(int samples, double lo, double hi, F f, G ref, unsigned seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  double worst = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double x = u(rng);
    worst = std::max(worst, ulps(f(x), ref(x)));
  }
  return worst;
}

bool same(double a, double b) {  // bit for bit, NaN equal to NaN
  return (std::isnan(a) && std::isnan(b)) || (a == b && std::signbit(a) == std::signbit(b));
}

}  // namespace

TEST_CASE("exp is within one ulp and handles the special values", "[core][math]") {
  using gp::math::exp;
  CHECK(worst_ulps(200000, -1.0, 1.0, [](double x) { return exp(x); }, [](double x) { return expl(x); }) <= 1.0);
  CHECK(worst_ulps(200000, -700.0, 700.0, [](double x) { return exp(x); }, [](double x) { return expl(x); }) <=
        1.0);
  CHECK(exp(0.0) == 1.0);
  CHECK(exp(-0.0) == 1.0);
  CHECK(std::isinf(exp(710.0)));
  CHECK(exp(-746.0) == 0.0);
  CHECK(exp(-740.0) > 0.0);  // subnormal
  CHECK(ulps(exp(-740.0), expl(-740.0L)) <= 1.0);
  CHECK(std::isnan(exp(std::nan(""))));
  CHECK(exp(-std::numeric_limits<double>::infinity()) == 0.0);
  CHECK(std::isinf(exp(std::numeric_limits<double>::infinity())));
}

TEST_CASE("log is within one ulp over the whole range, subnormals included", "[core][math]") {
  using gp::math::log;
  CHECK(worst_ulps(200000, 0.5, 2.0, [](double x) { return log(x); }, [](double x) { return logl(x); }) <= 1.0);
  CHECK(worst_ulps(200000, 1e-3, 1e3, [](double x) { return log(x); }, [](double x) { return logl(x); }) <= 1.0);
  // Log-uniform over every binade, subnormals included.
  CHECK(worst_ulps(
            200000, -1074.0, 1023.0, [](double e) { return log(std::exp2(e)); },
            [](double e) { return logl(std::exp2(e)); }) <= 1.0);
  CHECK(log(1.0) == 0.0);
  CHECK(std::isinf(log(0.0)));
  CHECK(log(0.0) < 0.0);
  CHECK(std::isnan(log(-1.0)));
  CHECK(std::isnan(log(std::nan(""))));
  CHECK(std::isinf(log(std::numeric_limits<double>::infinity())));
  CHECK(ulps(log(std::numeric_limits<double>::denorm_min()), logl(std::numeric_limits<double>::denorm_min())) <=
        1.0);
}

TEST_CASE("sin and cos are within one ulp for arguments up to 1e8", "[core][math]") {
  using gp::math::cos;
  using gp::math::sin;
  // Near zero and over a few turns, where long double's own reduction is exact.
  CHECK(worst_ulps(200000, -0.8, 0.8, [](double x) { return sin(x); }, [](double x) { return sinl(x); }) <= 1.0);
  CHECK(worst_ulps(200000, -0.8, 0.8, [](double x) { return cos(x); }, [](double x) { return cosl(x); }) <= 1.0);
  // Away from the zeros (ulps of a result near zero measure the reduction).
  auto away = [](auto f, auto ref) {
    return [f, ref](double x) {
      const long double r = ref(x);
      return std::fabs(static_cast<double>(r)) < 1e-3 ? 0.0 : ulps(f(x), r);
    };
  };
  double worst = 0.0;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  for (int i = 0; i < 200000; ++i) {
    const double x = u(rng);
    worst = std::max(worst, away([](double t) { return sin(t); }, [](double t) { return sinl(t); })(x));
    worst = std::max(worst, away([](double t) { return cos(t); }, [](double t) { return cosl(t); })(x));
  }
  CHECK(worst <= 1.0);
  // Large arguments: the identity, and agreement with long double to 1e-15.
  std::uniform_real_distribution<double> big(-1e8, 1e8);
  for (int i = 0; i < 20000; ++i) {
    const double x = big(rng);
    const auto [s, c] = gp::math::sincos(x);
    CHECK(std::fabs(s * s + c * c - 1.0) < 4e-16);
    CHECK(std::fabs(s - static_cast<double>(sinl(x))) < 1e-15);
  }
  // sincos is sin and cos, bit for bit.
  for (double x : {0.0, -0.0, 0.3, 1.0, 2.5, -3.9, 10.0, 1e5, -1e7}) {
    const auto [s, c] = gp::math::sincos(x);
    CHECK(same(s, sin(x)));
    CHECK(same(c, cos(x)));
  }
  CHECK(same(sin(-0.0), -0.0));
  CHECK(cos(0.0) == 1.0);
  CHECK(std::isnan(sin(std::numeric_limits<double>::infinity())));
  CHECK(std::isnan(cos(std::nan(""))));
}

TEST_CASE("atan2 is within one ulp in every quadrant and follows C99 on zeros and infinities", "[core][math]") {
  using gp::math::atan2;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  std::uniform_real_distribution<double> e(-30.0, 30.0);
  double worst = 0.0;
  for (int i = 0; i < 300000; ++i) {
    const double y = u(rng) * std::exp2(e(rng)), x = u(rng) * std::exp2(e(rng));
    worst = std::max(worst, ulps(atan2(y, x), atan2l(y, x)));
  }
  CHECK(worst <= 1.0);
  const double inf = std::numeric_limits<double>::infinity();
  for (double y : {0.0, -0.0, 1.0, -1.0, inf, -inf}) {
    for (double x : {0.0, -0.0, 1.0, -1.0, inf, -inf}) {
      INFO("y " << y << " x " << x);
      CHECK(same(atan2(y, x), std::atan2(y, x)));
    }
  }
  CHECK(std::isnan(atan2(std::nan(""), 1.0)));
  CHECK(std::isnan(atan2(1.0, std::nan(""))));
  CHECK(atan2(1e-300, 1e300) == std::atan2(1e-300, 1e300));
}

TEST_CASE("pow follows exp(y log x) within its bound and C99's special cases", "[core][math]") {
  using gp::math::pow;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(0.01, 10.0), uy(-4.0, 4.0);
  for (int i = 0; i < 100000; ++i) {
    const double x = ux(rng), y = uy(rng);
    // exp(y log x): the argument's rounding, about 1.5 ulp of |y log x|, is the result's relative error.
    const double bound = 3.0 * std::fabs(y * std::log(x)) + 1.5;
    CHECK(ulps(pow(x, y), powl(x, y)) <= bound);
  }
  const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
  for (double x : {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, 2.0, -2.0, inf, -inf, nan}) {
    for (double y : {0.0, -0.0, 1.0, -1.0, 2.0, -2.0, 0.5, -0.5, 3.0, -3.0, inf, -inf, nan}) {
      INFO("x " << x << " y " << y);
      const double want = std::pow(x, y), got = pow(x, y);
      CHECK((same(got, want) || (std::isnan(got) && std::isnan(want)) || ulps(got, powl(x, y)) <= 2.0));
    }
  }
}
