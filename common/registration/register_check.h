#pragma once
// The gate every customer's scans pass before anything else: are these meshes
// one body in several poses, in correspondence, valid, and in known units?
// Produces findings (errors, failed checks, warnings), statistics for the
// report, and the poses normalized to metres, +y up, in the reference's vertex
// order.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/error.h"
#include "geometry/self_intersections.h"
#include "registration/correspondence.h"
#include "registration/edge_ratios.h"
#include "registration/surface_growth.h"
#include "registration/mesh_checks.h"
#include "registration/units.h"
#include "spec/json_file.h"

namespace gp {

struct RegisterCheckOptions {
  std::string reference;          // reference pose name; empty: the first pose
  std::string units = "auto";     // "auto", "m", "cm", "mm" or "in"
  std::string up = "auto";        // "auto" or one of +x -x +y -y +z -z
  // Metres: scale the body so that the reference pose's extent along the up
  // axis is this (a body in unknown units whose height is known); 0: off.
  // Excludes `units`.
  double height = 0;
  bool reorder = false;           // recover the common vertex order of permuted poses
  bool triangulate = false;       // split polygons instead of rejecting them
  bool allow_open = false;        // holes are warnings instead of errors
  // Fail (exit 8) when an edge changes length by more than this factor
  // (either way) against the reference. Skin stretches up to ~4x at the
  // armpits between A-pose and arms up; registration errors give far more.
  double max_edge_ratio = kDefaultMaxEdgeRatio;
  bool self_intersections = true;  // run the (slower) self-intersection test
  int threads = 1;                 // poses checked in parallel
  int worst_edges = 10;            // worst edges named per pose in the report
  // The neighbourhoods over which each pose's surface growth against the
  // reference is measured (surface_growth.h) [m]: a hand's breadth, the
  // scale of a collar or an armpit.
  double surface_radius = 0.05;
  MeshCheckOptions mesh;
};

// The options as a report records them (spec/option_fields.h).
struct RegisterCheckOptionFields {
  template <class Fields>
  void operator()(RegisterCheckOptions& o, Fields& f) const {
    f.text("reference", o.reference);
    f.text("units", o.units);
    f.number("height_m", o.height, Range::non_negative());
    f.text("up", o.up);
    f.flag("reorder", o.reorder);
    f.flag("triangulate", o.triangulate);
    f.flag("allow_open", o.allow_open);
    f.number("max_edge_ratio", o.max_edge_ratio, Range::between(1.0, 1e300));
    f.flag("self_intersections", o.self_intersections);
    f.integer("threads", o.threads, Range::between(1, 1024));
    f.integer("worst_edges", o.worst_edges, Range::between(0, 1e6));
    f.number("surface_radius_m", o.surface_radius, Range::positive());
    f.group("mesh", o.mesh, MeshCheckOptionFields{});
  }
};

struct PoseInput {
  std::string name;
  std::filesystem::path file;
};

enum class Severity { error, fail, warning };

struct Finding {
  Severity severity = Severity::warning;
  ExitCode category = ExitCode::ok;  // for errors: the exit code it maps to
  std::string pose;                  // empty for findings about the whole set
  std::string message;
};

struct PoseCheck {
  std::string name;
  std::string file;
  std::string format;
  MeshCheckResult mesh;
  std::optional<SelfIntersectionResult> self_intersections;
  Connectivity connectivity = Connectivity::identical;
  bool reordered = false;  // vertices re-indexed into the reference order
  std::string reorder_note;
  std::optional<EdgeRatioStats> edge_ratios;  // against the reference pose
  std::optional<SurfaceGrowth> surface_growth;  // against the reference pose
  Eigen::MatrixXd V;  // normalized (metres, +y up, reference vertex order) once valid
};

struct RegisterCheckResult {
  std::vector<PoseCheck> poses;
  int reference = 0;
  Eigen::MatrixXi F;  // the reference's triangle list, shared by all valid poses
  std::optional<UnitsAndUp> units;
  std::vector<Finding> findings;
  double seconds_read = 0, seconds_checks = 0, seconds_correspondence = 0,
         seconds_self_intersections = 0, seconds_total = 0;

  // Exit code for the verdict: the first error's category, else 8 if a check
  // failed, else 0.
  ExitCode exit_code() const;
  // "pass", "fail" or "error".
  std::string verdict() const;
};

// Pose inputs from command-line arguments: mesh files, or folders whose
// .ply/.obj files are taken in name order. Names are file stems.
// UsageError for an empty list, a folder without meshes or a name clash.
std::vector<PoseInput> collect_pose_inputs(const std::vector<std::string>& args);

// Runs all checks. Throws InputError when a file cannot be read or parsed;
// every problem with the geometry itself becomes a finding.
RegisterCheckResult register_check(const std::vector<PoseInput>& inputs,
                                   const RegisterCheckOptions& options);

// The report (schema "register-check-report/1"), options included. It holds
// no timings, so that the same inputs give the same bytes.
OrderedJson register_check_report(const RegisterCheckResult& result,
                                  const RegisterCheckOptions& options);

// Wall times of the phases (schema "timing/1"), written to timing.json.
OrderedJson register_check_timing(const RegisterCheckResult& result);

}  // namespace gp
