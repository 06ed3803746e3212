#pragma once
// The checks the fit report states at its top, in plain words, from the
// stages' reports: what failed, what deserves a look, and what no stage has
// checked. Thresholds are those of the fit verdicts: area above 1 + delta
// under 1 %, p99 stretch at most 1 + delta + 0.02, penetration at most 2 mm.
#include <string>
#include <vector>

#include "report/fit_run.h"

namespace gp::report {

enum class CheckLevel { fail, warning, not_checked };

struct Check {
  CheckLevel level = CheckLevel::fail;
  std::string id;    // what was checked, a stable name, e.g. "penetration"
  std::string pose;  // the key pose it is about, or empty
  std::string text;  // one sentence, plain words, with the figures
};

struct FitThresholds {
  double area_above_limit = 0.01;   // fraction of the rest area
  double p99_margin = 0.02;         // p99 stretch may reach 1 + delta + this
  double penetration = 0.002;       // m
};

// Where a key pose's verification figures are, if simulate-adapt wrote them:
// "/key_poses/<i>/verification" or "/verification/key_poses/<i>"; empty if neither.
std::string verification_pointer(const StageReport& fit, size_t key_index);
// Where a key pose's crossing counts are: "/key_poses/<i>/crossings" or the
// verification's "crossings"; empty if absent.
std::string crossings_pointer(const StageReport& fit, size_t key_index);
// The sewn-fit check of the pattern: "/sewn_fit" of pattern/report.json; empty if absent.
std::string sewn_fit_pointer(const StageReport& pattern);
// "pass", "fail" or "" from an object with "verdict" (string) or "pass" (boolean).
std::string verdict_of(const Json* object);

std::vector<Check> fit_checks(const FitRun& run, const FitThresholds& thresholds = {});

const char* check_level_name(CheckLevel level);  // "fail", "warning", "not checked"

}  // namespace gp::report
