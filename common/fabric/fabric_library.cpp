#include <cmath>

#include "core/error.h"
#include "fabric/fabric.h"

namespace gp::fabric {
namespace {

// Wang, O'Brien, Ramamoorthi 2011 ("Data-driven elastic models for cloth",
// ACM TOG 30(4) 71), as distributed with ARCSim: the membrane and bending
// columns below are converted from their tables by the rules of README.md,
// "From the measured models to Baraff-Witkin terms":
//   k_warp  = c22(0) + c22(warp row)      (twice the mean of the table over 0-16.7 % strain)
//   k_weft  = c11(0) + c11(weft row)
//   k_shear = (c33(0) + c33(bias row)) / 4
//   k_bend  = mean of the 15 bending samples
// The wearer's limits are not measurements: README.md, "Stretch limits".
Fabric make(const char* name, const char* description, const char* source, bool knit, double density,
            double thickness, double k_warp, double k_weft, double k_shear, double k_bend, double limit_warp,
            double limit_weft) {
  Fabric f;
  f.name = name;
  f.description = description;
  f.source = source;
  f.knit = knit;
  f.areal_density = density;
  f.thickness = thickness;
  f.k_warp = k_warp;
  f.k_weft = k_weft;
  f.k_shear = k_shear;
  f.k_bend = k_bend;
  f.limit_warp = limit_warp;
  f.limit_weft = limit_weft;
  return f;
}

std::vector<Fabric> build_library() {
  std::vector<Fabric> lib;
  // The paper's material (Wolff et al. 2023): isotropic, one limit 1 + delta for every direction.
  Fabric paper;
  paper.name = "paper";
  paper.description = "the paper's isotropic material (Wolff et al. 2023), 0.15 kg/m^2";
  paper.source = "Wolff et al. 2023, sec. 6";
  paper.thickness = 0.0;
  lib.push_back(paper);
  //        name                      description                                                    source                         knit   kg/m^2  m        warp    weft    shear  bend      limits
  lib.push_back(make("cotton-poplin", "poplin-weight plain weave shirting (measured sample: white-dots-on-blk, 100% polyester)",
                     "Wang et al. 2011, white-dots-on-blk", false, 0.128, 0.20e-3, 4177.96, 4109.31, 30.163, 3.1071e-5, 1.10, 1.10));
  lib.push_back(make("denim-11oz", "11 oz denim, 99% cotton 1% spandex (11oz-black-denim)",
                     "Wang et al. 2011, 11oz-black-denim", false, 0.324, 0.75e-3, 2065.44, 437.38, 34.345, 7.2287e-5, 1.10, 1.15));
  lib.push_back(make("cotton-polyester-twill", "trouser twill, 65% cotton 35% polyester (royal-target)",
                     "Wang et al. 2011, royal-target", false, 0.220, 0.45e-3, 4187.71, 4126.07, 56.561, 1.7097e-4, 1.10, 1.10));
  lib.push_back(make("jersey-interlock", "T-shirt interlock knit, 60% cotton 40% polyester (gray-interlock)",
                     "Wang et al. 2011, gray-interlock", true, 0.187, 0.70e-3, 440.35, 62.96, 20.269, 2.1769e-5, 1.15, 1.30));
  lib.push_back(make("rib-knit", "underwear rib knit, 95% cotton 5% spandex (ivory-rib-knit)",
                     "Wang et al. 2011, ivory-rib-knit", true, 0.276, 0.90e-3, 319.76, 95.29, 27.696, 4.6342e-5, 1.15, 1.40));
  lib.push_back(make("swimwear-knit", "swimsuit knit, 87% nylon 13% spandex (white-swim-solid)",
                     "Wang et al. 2011, white-swim-solid", true, 0.204, 0.50e-3, 229.08, 88.34, 24.187, 5.0257e-5, 1.30, 1.40));
  lib.push_back(make("polyester-jet-set", "jacket fabric, 100% polyester (tango-red-jet-set); the drapey polyester "
                     "in the place of the paper's crepe",
                     "Wang et al. 2011, tango-red-jet-set", false, 0.113, 0.40e-3, 576.29, 118.22, 13.925, 1.8796e-5, 1.10, 1.15));
  return lib;
}

}  // namespace

const std::vector<Fabric>& fabric_library() {
  static const std::vector<Fabric> lib = build_library();
  return lib;
}

const Fabric* find_fabric(const std::string& name) {
  for (const Fabric& f : fabric_library())
    if (f.name == name) return &f;
  return nullptr;
}

std::string fabric_names() {
  std::string s;
  for (const Fabric& f : fabric_library()) s += (s.empty() ? "" : ", ") + f.name;
  return s;
}

void check_fabric(const Fabric& f, const std::string& where) {
  auto positive = [&](double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v)) throw SpecError(std::string(what) + " must be positive and finite", where);
  };
  auto non_negative = [&](double v, const char* what) {
    if (!(v >= 0.0) || !std::isfinite(v)) throw SpecError(std::string(what) + " must be non-negative and finite", where);
  };
  positive(f.areal_density, "areal_density");
  non_negative(f.thickness, "thickness");
  positive(f.k_warp, "k_warp");
  positive(f.k_weft, "k_weft");
  non_negative(f.k_shear, "k_shear");
  non_negative(f.k_bend, "k_bend");
  non_negative(f.damping_stretch, "damping_stretch");
  non_negative(f.damping_shear, "damping_shear");
  non_negative(f.damping_bend, "damping_bend");
  if (!(f.compression_ratio >= 1e-3 && f.compression_ratio <= 1.0))
    throw SpecError("compression_ratio must be within [0.001, 1]", where);
  const bool none = f.limit_warp == 0.0 && f.limit_weft == 0.0;
  const bool both = f.limit_warp >= 1.0 && f.limit_weft >= 1.0 && f.limit_warp <= 3.0 && f.limit_weft <= 3.0;
  if (!none && !both)
    throw SpecError("stretch limits must both be stretch ratios within [1, 3] (1.1: 10 % longer), or both absent", where);
}

}  // namespace gp::fabric
