#include "io/mesh.h"

namespace gp {

const ScalarField* find_field(const std::vector<ScalarField>& fields, const std::string& name) {
  for (const ScalarField& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

}  // namespace gp
