#pragma once
// export-rest's command line: every option of the stage (the inputs, the cutter's limit, darts,
// panels and seams, the flattening, the sewn-fit check's drape bounds, the layout and the DXF) with
// its default and unit in --help, written to ExportRestOptions and the named choices below.
#include <string>

#include <CLI/CLI.hpp>

#include "export/export_rest.h"

namespace gp {

// The options given by name or as negated flags; apply_choices() turns them into ExportRestOptions.
struct ExportRestChoices {
  std::string limit = "one-sided";     // --limit: one-sided or symmetric
  std::string placement = "curvature";  // --dart-placement: curvature or conformal
  std::string dxf_profile = "astm";    // --dxf-profile: astm, aama or plain
  bool no_tip_inward = false, no_mirror = false, no_armholes = false, edge_cuts = false;
};

void add_export_rest_options(CLI::App& app, ExportRestOptions& options, ExportRestChoices& choices);
// Also fills the DXF's default creation date and the seam tolerance of the report. Throws
// UsageError for a symmetric limit whose p95 bound exceeds its max bound.
void apply_choices(const ExportRestChoices& choices, ExportRestOptions& options);

}  // namespace gp
