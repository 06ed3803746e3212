#include "fabric/fabric_units.h"

#include <cmath>
#include <cstdlib>
#include <utility>

#include "core/error.h"

namespace gp::fabric {
namespace {

constexpr double kGramForce = 9.80665e-3;  // N
constexpr double kOunce = 28.349523125e-3;  // kg (avoirdupois)
constexpr double kYard = 0.9144;            // m

std::vector<std::pair<std::string, double>> units(Dimension d) {
  switch (d) {
    case Dimension::areal_density:
      return {{"kg/m^2", 1.0}, {"g/m^2", 1e-3}, {"oz/yd^2", kOunce / (kYard * kYard)}};
    case Dimension::length:
      return {{"m", 1.0}, {"mm", 1e-3}, {"um", 1e-6}};
    case Dimension::tension:
      return {{"N/m", 1.0}, {"N/cm", 100.0}, {"gf/cm", kGramForce / 1e-2}};
    case Dimension::bending:
      // KES-F's B is in gf cm^2/cm = gf cm.
      return {{"N m", 1.0}, {"mN m", 1e-3}, {"uN m", 1e-6}, {"gf cm^2/cm", kGramForce * 1e-2}};
    case Dimension::damping_tension:
      return {{"N s/m", 1.0}};
    case Dimension::damping_bending:
      return {{"N m s", 1.0}};
  }
  return {};
}

std::string list(Dimension d) {
  std::string s;
  for (const auto& u : units(d)) s += (s.empty() ? "" : ", ") + u.first;
  return s;
}

}  // namespace

std::vector<std::string> unit_names(Dimension d) {
  std::vector<std::string> names;
  for (const auto& u : units(d)) names.push_back(u.first);
  return names;
}

double parse_quantity(const std::string& text, Dimension d) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end == begin || !std::isfinite(value)) {
    throw SpecError("expected \"<number> <unit>\" with a unit among " + list(d) + ", got \"" + text + "\"");
  }
  std::string unit(end);
  const size_t first = unit.find_first_not_of(' ');
  unit = first == std::string::npos ? "" : unit.substr(first);
  while (!unit.empty() && unit.back() == ' ') unit.pop_back();
  for (const auto& [name, factor] : units(d)) {
    if (unit == name) return value * factor;
  }
  throw SpecError("unknown unit \"" + unit + "\" (accepted: " + list(d) + ")");
}

}  // namespace gp::fabric
