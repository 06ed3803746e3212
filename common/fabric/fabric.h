#pragma once
// A textile as the fit needs it, in SI units, and the library of named
// fabrics (fabric_library.cpp). Where each value comes from, and how the
// measured models map onto this project's Baraff-Witkin terms: README.md.
//
// The warp is the u axis of the cloth model (cloth/cloth_energy.h), the weft
// its v axis; a knit's wale (lengthwise) direction is its "warp" and its
// course (crosswise) direction its "weft".
#include <string>
#include <vector>

namespace gp::fabric {

struct Fabric {
  std::string name;         // the spec's key, e.g. "cotton-poplin"
  std::string description;  // what it is, e.g. "11 oz denim, 99% cotton 1% spandex"
  std::string source;       // where the values come from (README.md, "Sources")
  bool knit = false;        // a knit may be cut with negative ease (README.md, "Negative ease")
  double areal_density = 0.15;   // kg/m^2
  double thickness = 0.0;        // m; nominal (README.md); not used by the solver
  double k_warp = 800.0;         // N/m: membrane tension per unit strain along the warp
  double k_weft = 800.0;         // N/m: the same along the weft
  double k_shear = 200.0;        // N/m: per unit (w_u . w_v), the shear of the bias
  double k_bend = 1e-6;          // N m: bending rigidity (quadratic model, Bergou et al. 2006)
  double damping_stretch = 100.0;  // N s/m
  double damping_shear = 1.0;      // N s/m
  double damping_bend = 1e-5;      // N m s
  // The wearer's stretch limit (a stretch ratio, 1.1 = 10 % longer) along
  // the warp and along the weft. 0: the fit's own 1 + delta in both
  // directions (the paper's rule, one number for every direction).
  double limit_warp = 0.0;
  double limit_weft = 0.0;
  // Fraction of the stretch stiffness that resists compression (buckling;
  // cloth/README.md, "Compression").
  double compression_ratio = 0.1;

  bool has_own_limits() const { return limit_warp > 0.0 && limit_weft > 0.0; }
};

// Every named fabric, "paper" first (the paper's isotropic material, the
// default of every spec that names none).
const std::vector<Fabric>& fabric_library();

// The fabric called `name`, or nullptr.
const Fabric* find_fabric(const std::string& name);

// The known names, comma separated, for error messages.
std::string fabric_names();

// Throws SpecError (at `where`) for a fabric whose values are out of range:
// non-positive density, stiffness or limit below 1, and so on.
void check_fabric(const Fabric& fabric, const std::string& where);

}  // namespace gp::fabric
