#pragma once
// The garment file (schema "garment/1"), beside the garment mesh: what the
// mesh cannot hold. Written by make-garment and extend-boundary.
//
// Its fields, with an example: common/garment/README.md, "The garment file".
//
// Binding rule (how a later stage places a bound boundary vertex in pose p):
//   x = sum_k b_k V_p[F[f][k]] + offset * n,  n = normalize(sum_k b_k N_p[F[f][k]])
// with f, b from "binding", V_p the body in pose p, F the body triangles and N_p
// = gp::vertex_normals(V_p, F) (area-weighted vertex normals). The garment mesh
// itself holds the rest shape in the design pose.
#include <filesystem>
#include <string>
#include <vector>
#include <Eigen/Core>

#include "garment/surface_point.h"
#include "spec/json_file.h"
#include "spec/spec_object.h"

namespace gp {

// Grain angles are radians in memory and degrees in the files (the spec's
// "grain", the garment file's "grain"): a tailor's unit.
constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;

// Baraff-Witkin cloth parameters of the garment's fabric (common/fabric/README.md),
// defaults from the paper (Wolff et al. 2023: the fabric "paper"). Stiffnesses
// in N/m (membrane) and N m (bending), as cloth/cloth_model.h reads them.
struct Material {
  std::string fabric = "paper";   // the fabric's name (a library name, or the spec's own)
  double k_stretch = 800.0;       // stretch stiffness along the warp
  double k_stretch_weft = 800.0;  // stretch stiffness along the weft
  double k_shear = 200.0;         // shear stiffness
  double k_bend = 1e-6;           // bending stiffness
  double damping_stretch = 100.0;  // stretch damping
  double damping_shear = 1.0;      // shear damping
  double damping_bend = 1e-5;      // bend damping
  // Area density in kg/m^2. The paper gives no value; 0.15 kg/m^2 is a
  // medium-weight cotton shirting (150 g/m^2).
  double density = 0.15;
  // Fraction of k_stretch that resists compression: cloth buckles under a
  // small fraction of the load it stretches under (common/cloth/README.md,
  // "Compression"); 1 is the paper's symmetric stretch term.
  double compression_ratio = 0.1;
  // m, nominal (common/fabric/README.md): the separation the body contact
  // keeps (contact_thickness); 0: not given, the contact's default.
  double thickness = 0.0;
  bool knit = false;       // may be cut with negative ease (a comfort offset below zero)
  // The wearer's stretch limits along warp and weft (stretch ratios, 1.1 = 10 %
  // longer); both 0: the fit's 1 + delta in every direction (the paper's rule).
  double stretch_limit_warp = 0.0;
  double stretch_limit_weft = 0.0;

  // How the fabric is laid on each garment face (#F, radians, or empty: no
  // face turned): the warp turned counter-clockwise about the face's normal
  // from the body's vertical (cloth::ClothParameters::grain_angles; pi/4: a
  // bias cut). Not part of to_json(Material): the garment file writes it as
  // its own "grain" (degrees), and only where a face is turned.
  std::vector<double> grain_angles;

  bool has_own_limits() const { return stretch_limit_warp > 0.0 && stretch_limit_weft > 0.0; }
  bool turned_grain() const;  // some face's grain angle is not 0
  bool anisotropic() const { return k_stretch_weft != k_stretch; }
};
OrderedJson to_json(const Material& material);
// The separation [m] the body contact keeps between cloth and body
// (collision::ContinuousContactOptions::thickness, and a pinch's least
// offset): the fabric's thickness, or kDefaultContactThickness where the
// material gives none (the paper's, older garment files).
constexpr double kDefaultContactThickness = 1e-3;
double contact_thickness(const Material& material);
// Reads the fields present in `obj` over the defaults (strict: unknown keys fail).
Material read_material(const SpecObject& obj);
// A spec's "fabric": a library name (SpecError at `where`, listing the known
// names, for any other) or an object with the values in full and their units
// (common/garment/README.md, "Fabric").
Material read_fabric(const Json& value, const std::string& file, const std::string& pointer);

struct GarmentLoop {
  std::string name;
  bool pinned = false;
  std::vector<int> vertex_ids;          // garment vertex ids in boundary order
  std::vector<SurfacePoint> binding;    // per vertex id; empty when not on the body
  std::vector<SurfacePoint> curve;      // smoothed body curve; empty when not on the body
};

struct GarmentBodyInfo {
  std::string source;
  std::string source_sha256;
  std::string design_pose;
  long long vertex_count = 0;
  long long face_count = 0;
  std::string topology_sha256;
  // gp::vertex_checksum of the design pose, to tell that a pose set's pose of
  // that name is the same body (optional on reading).
  std::string design_pose_sha256;
};

struct GarmentExtension {
  std::string loop;
  double distance = 0.0;  // metres moved along the loop axis
  double scale = 1.0;     // scale applied to the loop
  double girth = 0.0;     // length of the new loop, metres
};

struct GarmentFile {
  std::string name;
  std::string mesh_file = "garment.ply";
  std::string mesh_sha256;
  long long vertex_count = 0;
  long long face_count = 0;
  GarmentBodyInfo body;
  std::string spec_file;
  std::string spec_sha256;
  double target_edge_length = 0.0;
  double offset = 0.0;
  std::vector<GarmentLoop> loops;
  std::vector<double> paint;  // per garment face (a knit's negative ease included)
  double ease = 0.0;          // the spec's negative ease (already in the paint); 0: none
  Material material;
  std::vector<GarmentExtension> extensions;

  // Index of the loop called `name`, or -1.
  int find_loop(const std::string& name) const;
};

OrderedJson to_json(const GarmentFile& garment);
// Strict reader: SpecError naming the field for a wrong schema, unknown,
// missing or mistyped field, ids out of range or arrays of the wrong length.
GarmentFile read_garment_file(const std::filesystem::path& path);
void write_garment_file(const std::filesystem::path& path, const GarmentFile& garment);

// Position of a bound vertex in a pose by the binding rule above; N are the
// pose's vertex normals.
Eigen::Vector3d evaluate_binding(const Eigen::MatrixXd& V, const Eigen::MatrixXd& N,
                                 const Eigen::MatrixXi& F, const SurfacePoint& p, double offset);

}  // namespace gp
