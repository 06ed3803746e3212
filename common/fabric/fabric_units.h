#pragma once
// Quantities with units, as a spec gives a fabric in full: "0.2 kg/m^2",
// "200 g/m^2", "0.5 mm", "800 N/m", "20 uN m". The number is converted to the
// SI unit of fabric.h.
#include <string>
#include <vector>

namespace gp::fabric {

enum class Dimension {
  areal_density,  // kg/m^2   (also g/m^2, oz/yd^2)
  length,         // m        (also mm, um)
  tension,        // N/m      (also N/cm, gf/cm)
  bending,        // N m      (also mN m, uN m, gf cm^2/cm)
  damping_tension,  // N s/m
  damping_bending,  // N m s
};

// The accepted unit names of a dimension, the SI one first.
std::vector<std::string> unit_names(Dimension d);

// "<number> <unit>" to the SI value. Throws SpecError (no location: the caller
// names the field) for a malformed text or a unit of another dimension,
// listing the accepted units.
double parse_quantity(const std::string& text, Dimension d);

}  // namespace gp::fabric
