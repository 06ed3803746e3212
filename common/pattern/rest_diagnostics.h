#pragma once
// Why a rest shape may not flatten within the limit: figures of the rest
// shape against the garment as designed (same connectivity).
//
// Adaptation stores the grown rest shape as one 3D mesh (ARAP-stitched rest
// triangles). Where the growth has no room in 3D it forms tucks: faces turned
// over against the design, and where a tuck ends inside the cloth, a cone
// point (a vertex whose angle defect |2 pi - sum of its angles| is large).
// No flat piece reproduces a cone point: an affine map whose principal
// stretches lie within 1 +- e changes each corner angle by at most about 2e,
// so a vertex with n corners and defect K needs e >= |K| / (2n) unless a cut
// passes through it (with n = 6 and e = 5 %: |K| > 34 degrees).
#include <Eigen/Core>

namespace gp {

struct RestShapeDiagnostics {
  double area_growth = 1.0;            // rest area / design area
  double growth_p95 = 1.0;             // largest principal growth of a face (rest against design), 95th percentile by design area
  double growth_max = 1.0;             // ... largest
  int turned_faces = 0;                // faces whose rest normal opposes their design normal (in a tuck)
  double turned_area_fraction = 0.0;   // their share of the rest area
  double cone_angle = 0.0;             // radians: threshold for counting cone points
  int cone_points = 0;                 // inner vertices with |angle defect| >= cone_angle (rest shape)
  int cone_points_design = 0;          // the same on the design
  double max_abs_defect = 0.0;         // radians, rest shape
  double abs_defect_sum = 0.0;         // radians, sum over inner vertices, rest shape
  double abs_defect_sum_design = 0.0;  // radians, the same on the design
};

// V_design, V_rest: #V by 3 (metres), F: #F by 3. Degenerate faces count as
// growth 1 and are not turned.
RestShapeDiagnostics diagnose_rest_shape(const Eigen::MatrixXd& V_design, const Eigen::MatrixXd& V_rest,
                                         const Eigen::MatrixXi& F, double cone_angle);

// Cone points of V_design and V_rest (inner vertices with |angle defect| >=
// cone_angle, as above) that lie inside the pieces: at least `margin` [m] in
// 3D from every boundary edge of the cut mesh (V_cut #Vc by 3 over the rest
// shape, F_cut its faces: the seams and the garment's boundary). A cone on a
// seam or at a seam junction (an armhole ring's underarm point) is where
// pieces meet, not a tuck inside one.
struct InnerCones {
  int rest = 0;
  int design = 0;
};
InnerCones cone_points_inside_pieces(const Eigen::MatrixXd& V_design, const Eigen::MatrixXd& V_rest,
                                     const Eigen::MatrixXi& F, double cone_angle, const Eigen::MatrixXd& V_cut,
                                     const Eigen::MatrixXi& F_cut, double margin);

}  // namespace gp
