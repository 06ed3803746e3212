#pragma once
// Library entry point of make-avatar: a posable body from tailoring
// measurements, in memory. Other modules call it in their tests to get a body
// without ../shared/avatars:
//
//   gp::AvatarOptions o;
//   o.target_vertices = gp::kAvatarSmallVertices;      // ~2k vertices, fast
//   o.poses = {"apose", "tpose", "armsup"};
//   const gp::AvatarResult body = gp::make_avatar(gp::default_avatar_spec(), o);
//   body.poses.V[1];   // #V by 3, T-pose, metres, +y up, facing +z, feet at y = 0
//   body.poses.F;      // #F by 3, shared by every pose, outward orientation
//
// Construction (see body_shape.h): the measurements set up an implicit body
// made of smooth-blended parts; its girth parameters are fitted (ray-cast
// cross-sections, fixed-point iteration); the zero set is polygonized by
// marching tetrahedra on a fine grid, decimated to the vertex budget by
// quadric edge collapse, projected back onto the implicit surface and
// relaxed; girths are then measured on the mesh by plane slicing
// (convex-hull perimeter) and corrected by scaling around each landmark.
// Poses are made by dual-quaternion skinning with smooth part-derived
// weights, so every pose shares the rest pose's triangles (vertex i is the
// same body point).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "avatar/avatar_spec.h"
#include "avatar/body_shape.h"
#include "avatar/skeleton.h"
#include "avatar/skinning.h"
#include "pose/pose_set.h"
#include "spec/json_file.h"

namespace gp {

constexpr int kAvatarSmallVertices = 2000;
constexpr int kAvatarDefaultVertices = 12000;
constexpr int kAvatarLargeVertices = 40000;

struct AvatarOptions {
  // Vertex budget of the body (the result has at most about this many).
  int target_vertices = kAvatarDefaultVertices;
  // Poses to produce, in order: built-in names (builtin_pose_names()) or
  // names of poses given in the spec. Empty = all built-in poses followed by
  // the spec's poses. "apose" (the rest pose) is always the reference; it is
  // added first if missing.
  std::vector<std::string> poses;
  // Marching-tetrahedra cell [m at height 1.70 m; scaled with the height].
  double cell = 0.009;
  // Girth correction passes on the mesh (measure, scale around the landmark).
  int girth_correction_iterations = 4;
  // Triangles that skinning shears below this angle in a pose get their
  // corners smoothed locally [degrees].
  double posed_min_angle = 3.0;
  // Skinning weights (transition width, smoothing).
  SkinningOptions skinning;
  // Tangential relaxation passes after decimation (triangle shape).
  int relax_iterations = 3;
  // Verify that the rest pose has no self-intersection (CGAL, a few tens of
  // ms), smoothing away local folds where there are any.
  bool check_self_intersection = true;
};

// The options as a report records them (spec/option_fields.h); the poses,
// a list, are recorded beside them as produced.
struct AvatarOptionFields {
  template <class Fields>
  void operator()(AvatarOptions& o, Fields& f) const {
    f.integer("target_vertices", o.target_vertices, Range::between(100, 1e7));
    f.number("cell_m_at_1_70", o.cell, Range::positive());
    f.integer("girth_correction_iterations", o.girth_correction_iterations, Range::between(0, 1000));
    f.number("posed_min_angle_degrees", o.posed_min_angle, Range::between(0.0, 60.0));
    f.group("skinning", o.skinning, SkinningOptionFields{});
    f.integer("relax_iterations", o.relax_iterations, Range::between(0, 1000));
    f.flag("check_self_intersection", o.check_self_intersection);
  }
};

struct GirthResult {
  std::string name;                                  // landmark ("chest", "wrist_left", ...)
  std::string field;                                 // measurement ("chest", "wrist", ...)
  double target = 0.0;                               // [m]
  double measured = 0.0;                             // convex-hull perimeter of the mesh slice [m]
  double loop = 0.0;                                 // length of the slice loop itself [m]
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // plane point in the rest pose [m]
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
};

struct AvatarTiming {
  double fit = 0, polygonize = 0, simplify = 0, project = 0, measure = 0, skin = 0, pose = 0, check = 0;
  double total = 0;  // [s]
};

struct AvatarResult {
  Measurements measurements;              // effective (defaults filled in)
  PoseSet poses;                          // names, V per pose, shared F, reference "apose"
  Skeleton skeleton;                      // rest joints (rest pose floor-aligned like the mesh)
  std::vector<Eigen::MatrixXd> joints;    // per pose, kJointCount by 3 [m]
  std::vector<JointRotations> rotations;  // per pose, local joint rotations
  Eigen::MatrixXd weights;                // #V by kJointCount skinning weights
  std::vector<GirthResult> girths;
  std::vector<double> volumes;        // per pose [m^3]
  double height = 0.0;                // measured top of the rest pose [m]
  int correction_rounds = 0;          // girth correction passes applied to the mesh
  long long isosurface_vertices = 0;  // before decimation
  int needle_vertices_smoothed = 0;   // over all posed meshes (see posed_min_angle)
  int flips = 0;                      // edge flips for better angles
  int untangle_rounds = 0;            // local smoothing rounds that removed folds
  int specks_removed = 0;             // tiny isosurface pieces dropped (thin tips)
  AvatarTiming timing;
};

// Builds the body. Throws SpecError for an unknown or duplicate pose name (or
// a spec pose that shadows a built-in one), GeometryError if the construction
// fails its own checks (not closed, not one genus-0 component, rest pose
// self-intersecting).
AvatarResult make_avatar(const AvatarSpec& spec, const AvatarOptions& options = {});

// The "make-avatar-report/1" JSON for a result (deterministic: no timings).
OrderedJson avatar_report(const AvatarSpec& spec, const AvatarOptions& options, const AvatarResult& result);

// The "skeleton/1" JSON: joint names and parents, positions per pose.
OrderedJson skeleton_json(const AvatarResult& result);

}  // namespace gp
