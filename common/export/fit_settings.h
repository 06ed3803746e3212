#pragma once
// The settings of a fit, read back from the fit's own report
// (simulate-adapt's report.json, "simulate-adapt-report/1"): which poses and
// motion it ran, how it simulated them (time step, settling, contact, solver)
// and how its verification judged a key pose. The sewn-fit check
// (sewn_fit.h) simulates the sewn pattern with exactly these, so that its
// verdict and the fit's verification mean the same thing.
#include <filesystem>
#include <string>
#include <vector>

#include "adapt/fit_verification.h"
#include "adapt/garment_motion.h"

namespace gp {

struct FitSettings {
  std::string report;                 // the report read
  std::string poses;                  // pose set of the fit (poses.json), as the fit was given it
  std::string motion;                 // motion spec of the fit (motion/1), as the fit was given it
  adapt::MotionRunOptions run;        // the simulation's settings; adapt is false, threads 1
  // The fit's verification also judged every frame_stride-th in-between frame
  // (adapt::FitOptions::frame_stride; 0: key poses only): the sewn-fit check
  // judges the same frames.
  int frame_stride = 0;
  adapt::FitCriteria criteria;        // the verification's bounds (the defaults when the fit skipped it)
  // The verification's drape of every key pose (verification/key_poses/*/mesh),
  // paths beside the report; empty when the fit ran without verification.
  struct VerifiedDrape {
    int key = -1;
    std::string pose;
    std::string mesh;  // as the report names it
    std::filesystem::path path;
  };
  std::vector<VerifiedDrape> verified;
  double delta() const { return run.adaptation.adapter.delta; }
};

// Reads `report` (simulate-adapt's report.json). Throws InputError when it
// cannot be read or parsed, SpecError naming the file and JSON pointer of a
// missing, mistyped or out-of-range field or of another schema.
FitSettings read_fit_settings(const std::filesystem::path& report);

}  // namespace gp
