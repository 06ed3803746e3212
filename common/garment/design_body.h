#pragma once
// The body a garment was designed on, found from its garment file: for the
// stages after make-garment that need it (extend-boundary keeps the extension
// off it, export-rest maps seams given on the body).
#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "garment/garment_file.h"

namespace gp {

struct DesignBody {
  Eigen::MatrixXd V;  // #Vb by 3, metres
  Eigen::MatrixXi F;  // #Fb by 3
};

// Loads the design-pose body named by the garment file: `source` (a pose-set
// manifest or a mesh) if not empty, else the garment's body.source as given or
// relative to the garment file's folder. InputError if it cannot be found,
// GeometryError if its counts differ from the garment file's.
DesignBody load_design_body(const GarmentFile& garment, const std::filesystem::path& garment_path,
                            const std::string& source);

}  // namespace gp
