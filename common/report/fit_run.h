#pragma once
// The stage folders of one fit, as pipelines/fit.mk lays them out under its
// OUT folder, read for the fit report:
//   body/      make-avatar        (optional: customers with measurements)
//   opened/    interp-poses       (optional: make fit's OPEN_POSE) a pose opened towards another
//   poses/     register-check     poses.json and the pose meshes
//   garment/   make-garment       garment.json, garment.ply (the design)
//   extended/  extend-boundary    (optional) the garment that was simulated
//   fit/       simulate-adapt     rest.ply, draped_<kk>_<pose>.ply
//   fit-noadapt/ simulate-adapt --no-adapt (optional) the design through the same motion
//   pattern/   export-rest        pattern.svg (and pattern.dxf, pattern-<paper>.pdf)
//   marker/    make-marker        (optional: make fit's FABRIC_WIDTH) marker.svg, marker.pdf
// Every folder's report.json is checked for its schema, and the fields the
// report needs are checked strictly (a missing or mistyped one is a SpecError
// naming the file and JSON pointer). Fields that other stages may or may not
// write yet (verification, crossings, sewn-fit verdicts) are looked up
// tolerantly by the report itself (html_report.h).
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spec/json_file.h"

namespace gp::report {

struct StageReport {
  std::string stage;            // folder name, e.g. "fit"
  std::string file;             // "<stage>/report.json", relative to the fit folder
  std::filesystem::path path;   // the file itself
  Json json;
  Json timing;                  // <stage>/timing.json, null if absent
};

// The value at `pointer` (RFC 6901) in the report, or nullptr.
const Json* lookup(const StageReport& report, const std::string& pointer);

struct KeyPoseRun {
  int key = 0;
  std::string pose;
  std::filesystem::path mesh;   // the draped garment
  std::string pointer;          // of its entry, e.g. "/key_poses/2"
  // The verification's drape (the final rest shape simulated afresh) and its
  // entry, e.g. "/verification/key_poses/2"; empty without a verification.
  std::filesystem::path verified_mesh;
  std::string verified_pointer;
  // The drape that shows the fit honestly: the verified one where it exists.
  const std::filesystem::path& shown_mesh() const { return verified_mesh.empty() ? mesh : verified_mesh; }
  const std::string& shown_pointer() const { return verified_pointer.empty() ? pointer : verified_pointer; }
};

// make fit's OPEN_POSE: `pose` replaced by the body 1/steps of the way towards `toward`.
struct OpenedPose {
  std::string pose, toward;
  long long steps = 0;
  // Opened by make fit's fallback (AUTO_OPEN): the held run's report in
  // fit-held/ proposed it, and says where the captured pose held the cloth.
  bool automatic = false;
  std::string held_at;                 // the region of the most stretched patch
  double largest_displacement_mm = 0.0;
};

// A key pose at which the body held the cloth (simulate-adapt's "held"):
// the place of each held patch and the drape where the run stopped.
struct HeldPatch {
  std::string region;                 // e.g. "body vertex 2750"
  std::array<double, 3> position{};   // the body point that holds it [m]
  double gap_mm = 0.0;                // room along the body's normal there
  double max_stretch = 0.0;
  std::vector<int> faces;             // the garment faces held
};
struct HeldPose {
  std::string folder;                 // "fit" (the run stopped there) or "fit-held" (make fit then opened it)
  std::string pose;
  int key = 0;
  long long settle_steps = 0;
  std::filesystem::path drape;        // the garment where the run stopped
  std::filesystem::path rest;         // that run's rest shape (its triangles are the drape's)
  // The body that held it: poses/ for "fit"; for "fit-held" the captured
  // pose make fit kept beside that run (body_<pose>.ply), empty if absent.
  std::filesystem::path body;
  std::vector<HeldPatch> patches;
};

struct FitRun {
  std::filesystem::path dir;
  std::optional<StageReport> body, extended, fit_no_adapt, marker;
  StageReport poses, garment, fit, pattern;
  // The key pose fitted opened (opened/), read only while the pose it wrote
  // is the one poses/ registered (same sha256), so that a folder left from an
  // earlier run claims nothing.
  std::optional<OpenedPose> opened;
  // Where the body held the cloth: fit/ when this run stopped there, else
  // fit-held/ when the opening above was automatic; nullopt otherwise.
  std::optional<HeldPose> held;
  std::filesystem::path poses_manifest;  // poses/poses.json
  std::filesystem::path garment_file;    // extended/ or garment/ garment.json
  std::filesystem::path design_mesh;     // the garment as designed (the simulated one)
  std::filesystem::path rest_mesh;       // fit/rest.ply
  std::filesystem::path pattern_svg;     // pattern/pattern.svg
  double delta = 0.1;                    // the adaptation's stretch limit is 1 + delta
  std::vector<KeyPoseRun> keys;
  std::vector<KeyPoseRun> keys_no_adapt;  // same poses as keys, or empty
  // Stage folders in pipeline order, for the timings table.
  std::vector<const StageReport*> stages() const;
};

// What dir/opened/ (make fit's OPEN_POSE) opened, from interp-poses' report
// (its motion: the pose, the pose towards which, the steps; SpecError where
// they are missing), when that pose is the one `poses_manifest` registered
// (the same sha256 as opened/poses/<pose>.ply); nullopt otherwise, as for a
// folder left from an earlier run.
std::optional<OpenedPose> read_opened_stage(const std::filesystem::path& dir,
                                            const std::filesystem::path& poses_manifest);

// The held pose of the simulate-adapt report `stage` (in dir/<stage.stage>/),
// or nullopt where it has no "held"; SpecError for a malformed one.
std::optional<HeldPose> read_held(const StageReport& stage, const std::filesystem::path& dir,
                                  const std::filesystem::path& poses_manifest);

// Reads the fit folder `dir`. Throws InputError naming the first missing
// file (report.json of poses/, garment/, fit/, pattern/, or a mesh they name),
// SpecError for a wrong schema or a missing or mistyped required field.
FitRun read_fit_run(const std::filesystem::path& dir);

// Checks that `pointer` exists in `report` and is of `kind` ("number",
// "integer", "boolean", "string", "object", "array", or "any" for one that
// may be null); SpecError otherwise.
const Json& require(const StageReport& report, const std::string& pointer, const std::string& kind);

}  // namespace gp::report
