#pragma once
// Elementary functions that give the same bits on every x86-64 CPU.
//
// glibc picks its exp, log, pow, sin, cos and atan2 at run time by CPU: with
// FMA (Haswell and later, Zen) or without (Sandy Bridge, or a virtual machine
// that hides FMA), and the two paths differ in the last bit for about one
// argument in a thousand. The cloth simulation amplifies such a bit into a
// different fit. These versions use only +, -, *, /, sqrt, rint, frexp and
// ldexp, which IEEE 754 defines exactly, so their results depend on the
// argument alone (compiled without contraction into FMA: see CMakeLists.txt).
//
// Accuracy: within 1 ulp of the exact result over the ranges tested in
// core/tests/test_math.cpp (sin and cos for |x| <= 1e8, beyond which the
// argument reduction loses bits; pow to (|y log x| + 2) ulp). Special values
// follow C99 Annex F (NaN in, NaN out; exp(-inf) = 0; log(0) = -inf; ...).
#include <utility>

namespace gp::math {

double exp(double x);
double log(double x);
// x^y for x > 0 as exp(y log x); x = 0, negative x with integer y, and the
// other C99 special cases as std::pow.
double pow(double x, double y);
double sin(double x);
double cos(double x);
// {sin x, cos x}, sharing one argument reduction.
std::pair<double, double> sincos(double x);
// The angle of (x, y) in [-pi, pi], as std::atan2 (signed zeros included).
double atan2(double y, double x);

}  // namespace gp::math
