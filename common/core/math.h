#pragma once
// Elementary functions with the same bits on every x86-64 CPU (README.md, "Reproducibility"):
// glibc's exp, log, pow, sin, cos and atan2 differ with and without FMA in the last bit for about
// one argument in a thousand, and cloth amplifies that into another fit. These use only IEEE-exact
// +, -, *, /, sqrt, rint, frexp and ldexp (no FMA contraction: CMakeLists.txt). Within 1 ulp over
// core/tests/test_math.cpp's ranges (sin, cos for |x| <= 1e8; pow to (|y log x| + 2) ulp); special
// values follow C99 Annex F (NaN in, NaN out; exp(-inf) = 0; log(0) = -inf; ...).
#include <utility>

namespace gp::math {

double exp(double x);
double log(double x);
// x^y as exp(y log x) for x > 0; x = 0, negative x with integer y and other C99 cases as std::pow.
double pow(double x, double y);
double sin(double x);
double cos(double x);
// {sin x, cos x}, sharing one argument reduction.
std::pair<double, double> sincos(double x);
// The angle of (x, y) in [-pi, pi], as std::atan2 (signed zeros included).
double atan2(double y, double x);

}  // namespace gp::math
