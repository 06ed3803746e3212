#include "avatar/body_checks.h"

#include <algorithm>
#include <vector>

#include "core/error.h"
#include "mesh/topology.h"

namespace gp {

void check_closed_genus0(const Eigen::MatrixXi& F, const std::string& what) {
  if (F.rows() == 0) throw GeometryError(what + " has no triangles");
  // Every directed edge must appear once and its reverse once: closed,
  // manifold and consistently oriented in one test.
  std::vector<std::pair<int, int>> directed;
  directed.reserve(static_cast<size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) directed.emplace_back(F(f, k), F(f, (k + 1) % 3));
  std::sort(directed.begin(), directed.end());
  for (size_t i = 0; i < directed.size(); ++i) {
    const auto& e = directed[i];
    auto name = [&] { return "(" + std::to_string(e.first) + ", " + std::to_string(e.second) + ")"; };
    if (i + 1 < directed.size() && directed[i + 1] == e)
      throw GeometryError(what + ": edge " + name() + " is used twice in the same direction");
    if (!std::binary_search(directed.begin(), directed.end(), std::make_pair(e.second, e.first)))
      throw GeometryError(what + ": edge " + name() + " is a boundary edge");
  }
  Eigen::VectorXi comp;
  const int n = face_components(F, comp);
  if (n != 1) throw GeometryError(what + " has " + std::to_string(n) + " components, expected 1");
  const int chi = euler_characteristic(F);
  if (chi != 2)
    throw GeometryError(what + " has Euler characteristic " + std::to_string(chi) +
                        ", expected 2 (a sphere)");
}

}  // namespace gp
