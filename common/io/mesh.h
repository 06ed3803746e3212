#pragma once
// The triangle mesh every stage exchanges: vertex positions, triangles, and
// optional named scalar fields per vertex or per face (stretch maps, paint).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gp {

// A named scalar field: one value per vertex or per face.
struct ScalarField {
  std::string name;
  Eigen::VectorXd values;
};

struct Mesh {
  Eigen::MatrixXd V;  // #V by 3 positions (metres, +y up once normalized)
  Eigen::MatrixXi F;  // #F by 3 vertex indices, counter-clockwise seen from outside
  std::vector<ScalarField> vertex_fields;  // each with #V values
  std::vector<ScalarField> face_fields;    // each with #F values
};

// The field named `name`, or nullptr.
const ScalarField* find_field(const std::vector<ScalarField>& fields, const std::string& name);

}  // namespace gp
