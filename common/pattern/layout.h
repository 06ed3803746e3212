#pragma once
// Layout of the flat pieces on one sheet: each piece turned so that its
// grain line (the warp: the body's vertical, +y of the rest shape, as seen on
// the flat piece, turned where the garment turns its grain) points up the sheet, then packed in shelves without overlap; and
// everything a pattern sheet carries besides the outlines: seam allowance,
// notches (every `notch_spacing` along each seam and at its ends, at the same
// material points on both sides), labels.
//
// All coordinates in metres, sheet frame: x to the right, y up, origin at the
// lower left corner of the sheet. Pieces are seen from the outside (the right
// side of the fabric) and keep their orientation (rotations only).
#include <string>
#include <vector>
#include <Eigen/Core>

#include "pattern/cut_instructions.h"
#include "pattern/pattern.h"
#include "pattern/seam_allowance.h"
#include "spec/option_fields.h"

namespace gp {

struct LayoutOptions {
  std::string title = "pattern";  // the garment's name, on every piece's label
  double seam_allowance = 0.01;  // metres; 0 for none
  double gap = 0.01;             // metres between the cutting lines of neighbouring pieces
  double sheet_width = 1.5;      // metres: width of the fabric / paper roll
  double margin = 0.01;          // metres around the layout
  double notch_spacing = 0.1;    // metres along a seam
  double notch_length = 0.006;   // metres, into the seam allowance
  double simplify_tolerance = 1e-4;  // metres, outline simplification before offsetting
};

// The options as a report records them (the title aside: it is the garment's name).
struct LayoutOptionFields {
  template <class Fields>
  void operator()(LayoutOptions& o, Fields& f) const {
    f.number("seam_allowance_m", o.seam_allowance, Range::non_negative());
    f.number("gap_m", o.gap, Range::non_negative());
    f.number("sheet_width_m", o.sheet_width, Range::positive());
    f.number("margin_m", o.margin, Range::non_negative());
    f.number("notch_spacing_m", o.notch_spacing, Range::positive());
    f.number("notch_length_m", o.notch_length, Range::non_negative());
    f.number("simplify_tolerance_m", o.simplify_tolerance, Range::non_negative());
  }
};

struct Notch {
  int seam = -1;
  int piece = -1;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();       // on the sewing line
  Eigen::Vector2d outward = Eigen::Vector2d::Zero();  // unit, away from the piece
  Eigen::Vector2d tip = Eigen::Vector2d::Zero();      // at + notch_length * outward
  double arc = 0.0;  // 3D arc length along the seam, metres
  int side = 0;      // 0: left of the seam's direction, 1: right
  // Both notches of a pair (the same material point on the two sides of a
  // seam) carry the same label: the seam's name and the notch's number along
  // it from 1 ("side_left 3").
  std::string label;
  double flat_arc = 0.0;  // arc length along this side's sewing line on the flat piece, metres
};

struct SeamLabel {
  int seam = -1;
  int piece = -1;
  int side = 0;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // inside the piece, near the middle of its side
};

// A dart as drawn: its legs meet the outline at mouth_left / mouth_right
// (notched there), its fold line runs from their midpoint to the tip, and a
// drill hole marks a centimetre short of the tip.
struct DartMark {
  int seam = -1;
  int piece = -1;
  Eigen::Vector2d mouth_left = Eigen::Vector2d::Zero(), mouth_right = Eigen::Vector2d::Zero();
  Eigen::Vector2d tip = Eigen::Vector2d::Zero();
  Eigen::Vector2d drill = Eigen::Vector2d::Zero();
};

struct LaidOutPiece {
  Eigen::MatrixXd UV;             // #Vp by 2, sheet positions (metres)
  Polygon2 outline;               // sewing line, counter-clockwise (the piece's boundary loop)
  std::vector<Polygon2> allowance;  // cutting line(s), empty when seam_allowance is 0
  double rotation = 0.0;          // radians applied to the flattening
  Eigen::Vector2d label_at = Eigen::Vector2d::Zero();
  double label_room = 0.0;        // radius of a disc inside the piece around label_at
  Eigen::Vector2d grain_from = Eigen::Vector2d::Zero(), grain_to = Eigen::Vector2d::Zero();
  bool grain_from_body_vertical = true;  // false: the piece is horizontal, grain along its longest axis
  double grain_turn = 0.0;  // radians: the area-weighted mean grain angle of its faces (0: straight grain)
};

struct Layout {
  std::vector<LaidOutPiece> pieces;
  std::vector<Notch> notches;
  std::vector<SeamLabel> seam_labels;  // none overlaps another label
  std::vector<DartMark> darts;
  double width = 0.0, height = 0.0;  // sheet size, metres
};

// Lays the pieces out: mirrored pairs ("left X", "right X") side by side,
// seam labels where they overlap no other label. rest_grain_angles (#F of
// the rest shape, radians, or empty: every face on the straight grain) turn
// each face's warp as the cloth model does (Material::grain_angles): a
// piece's grain line is then the area-weighted mean of its faces' turned
// warps. Throws UsageError for a count other than the rest shape's faces.
Layout layout_pattern(const Pattern& pattern, const LayoutOptions& options,
                      const std::vector<double>& rest_grain_angles = {});

// Axis-aligned box on the sheet (metres).
struct Box2 {
  Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
};
// A piece's label as the writers set it: two lines centred on label_at
// (line 1 "<title> <piece name>", line 2 what to cut (cut_instructions.h)
// and the grain: "cut 1 self, face up, pair of right sleeve, grain vertical"), their font sizes
// (metres) as large as 10 mm but small enough for both lines to fit the
// disc of radius label_room; `box` bounds both (widths estimated at 0.6 of
// the font size per character).
struct PieceLabel {
  std::string line1, line2;
  Eigen::Vector2d line1_at = Eigen::Vector2d::Zero(), line2_at = Eigen::Vector2d::Zero();  // baseline centres
  double size1 = 0.0, size2 = 0.0;
  Box2 box;
};
PieceLabel piece_label(const LaidOutPiece& piece, const std::string& title, const std::string& name,
                       const CutInstruction& cut);
// The box a seam's name (`characters` long, 3 mm text centred on `at`) takes.
Box2 seam_label_box(const Eigen::Vector2d& at, size_t characters);

}  // namespace gp
