#pragma once
// Units and up axis of a body scan. Scans arrive in metres, centimetres or
// millimetres, and with y or z up; the pipeline works in metres with +y up.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gp {

// One of "+x", "-x", "+y", "-y", "+z", "-z".
struct UpAxis {
  int axis = 1;   // 0 x, 1 y, 2 z
  int sign = +1;  // +1 or -1
  std::string name() const;
  // Throws UsageError for anything but the six names above.
  static UpAxis parse(const std::string& s);
};

// One piece of evidence about the sign of the up axis.
struct UpCue {
  std::string name;    // "soles", "legs"
  int vote = 0;        // +1: the axis points up; -1: it points down; 0: this cue cannot tell
  std::string detail;  // the figures behind the vote, for the report
};

// How the up axis of a body was found.
struct UpAxisDetection {
  UpAxis up;
  bool ambiguous = false;     // the axis or its sign cannot be told: refuse, ask for --up
  std::string reason;         // one sentence naming the cues and their figures
  double spread_ratio = 0;    // second largest over largest area-weighted variance (the axis' margin)
  std::vector<UpCue> cues;    // the sign's cues along the chosen axis
};

struct UnitsAndUp {
  std::string units = "m";     // "m", "cm", "mm", "in", or "height" (scaled to --height)
  double scale_to_metres = 1;  // multiply coordinates by this
  UpAxis up;
  double height = 0;           // body height in the input's units (extent along up)
  double given_height_m = 0;   // --height: the height the body was scaled to [m]; 0 if none
  bool up_ambiguous = false;   // the up axis could not be told reliably (an error unless --up)
  std::string up_reason;       // how the up axis was chosen (for the report)
  std::vector<UpCue> up_cues;  // the sign's cues (empty when --up gave it)
};

// Scale factor for a unit name; UsageError for an unknown name.
double metres_per_unit(const std::string& units);

// Up axis of a standing human body in any pose (arms up, seated, one leg
// forward), also without feet or hands. The axis is the one with the largest
// area-weighted variance of surface position (a body is long along it in
// every pose; outstretched arms add little area far from the centre); it is
// ambiguous when another axis comes within kUpAxisSpreadMargin of it. Its sign
// combines two cues, each of which votes up, down or "cannot tell":
//  - soles: flat surface across the axis (normals within 20 degrees of it,
//    either way) in its lowest and highest 5 %: the soles of the feet (or flat
//    stumps) lie on the floor, while a head or a hand is rounded;
//  - legs: the number of cross-sections (loops at least 5 % of the height long)
//    in seven slices 4-22 % of the height from each end (the median of
//    each end's counts): two legs near the feet against one head and neck
//    near the top; or, with the arms raised, two throughout at the feet
//    against two arms with the head appearing between them (three).
// The sign is taken when at least one cue votes and none votes against it;
// otherwise (no cue can tell, or two disagree) the detection is ambiguous and
// the caller must ask for --up: a guess here would design every later stage on
// an upside-down body. V and F of the reference pose (any units).
UpAxisDetection detect_up_axis(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F);

// A second largest spread above this fraction of the largest leaves the axis ambiguous.
constexpr double kUpAxisSpreadMargin = 0.8;

// Units from the body's height along `up`: 0.5-2.5 is metres, 50-250
// centimetres, 500-2500 millimetres. GeometryError for any other height.
std::string detect_units(double height);

// Rotation (proper, det +1) that takes `up` to +y, applied to row vectors:
// V_out = V_in * R^T.
Eigen::Matrix3d rotation_to_y_up(const UpAxis& up);

// Converts to metres, +y up.
Eigen::MatrixXd to_metres_y_up(const Eigen::MatrixXd& V, const UnitsAndUp& u);

}  // namespace gp
