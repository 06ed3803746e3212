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

struct UnitsAndUp {
  std::string units = "m";     // "m", "cm", "mm" or "in"
  double scale_to_metres = 1;  // multiply coordinates by this
  UpAxis up;
  double height = 0;           // body height in the input's units (extent along up)
  bool up_ambiguous = false;   // the sign of the up axis could not be told reliably
  std::string up_reason;       // how the up axis was chosen (for the report)
};

// Scale factor for a unit name; UsageError for an unknown name.
double metres_per_unit(const std::string& units);

// Up axis of a standing body: the axis with the largest area-weighted variance
// of surface position (a standing body is long along it in every pose, while
// outstretched arms add little area far from the centre). Its sign puts the
// flat soles of the feet at the low end; where that cue is weak, the side
// holding the surface centroid is up (the upper body carries more surface than
// the legs). V and F of the reference pose; `ambiguous` is set when neither
// cue is clear.
UpAxis detect_up_axis(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, bool* ambiguous = nullptr,
                      std::string* reason = nullptr);

// Units from the body's height along `up`: 0.5-2.5 is metres, 50-250
// centimetres, 500-2500 millimetres. GeometryError for any other height.
std::string detect_units(double height);

// Rotation (proper, det +1) that takes `up` to +y, applied to row vectors:
// V_out = V_in * R^T.
Eigen::Matrix3d rotation_to_y_up(const UpAxis& up);

// Converts to metres, +y up.
Eigen::MatrixXd to_metres_y_up(const Eigen::MatrixXd& V, const UnitsAndUp& u);

}  // namespace gp
