#include "pattern/piece_names.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "mesh/measures.h"

namespace gp {
namespace {

struct PieceFrame {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // area-weighted, not normalized
  int limb = -1;
};

}  // namespace

void name_pieces(Pattern& pattern) {
  const PatternMesh& mesh = pattern.mesh;
  // The garment's area centroid: the body's vertical axis runs through it.
  const Eigen::Vector3d axis = area_centroid(mesh.rest_V, mesh.rest_F);
  std::vector<PieceFrame> frames(pattern.pieces.size());
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    const PatternPiece& p = pattern.pieces[c];
    PieceFrame& fr = frames[c];
    double area = 0.0;
    std::map<int, double> on_limb;
    for (size_t i = 0; i < p.face_ids.size(); ++i) {
      const Eigen::Vector3d a = p.V.row(p.F(static_cast<int>(i), 0)), b = p.V.row(p.F(static_cast<int>(i), 1)),
                            d = p.V.row(p.F(static_cast<int>(i), 2));
      const Eigen::Vector3d n = 0.5 * (b - a).cross(d - a);
      const double w = n.norm();
      fr.centroid += w * (a + b + d) / 3.0;
      fr.normal += n;
      area += w;
      const int rest = mesh.rest_face[static_cast<size_t>(p.face_ids[i])];
      const int limb = pattern.limb_of_rest_face.empty() ? -1 : pattern.limb_of_rest_face[static_cast<size_t>(rest)];
      on_limb[limb] += w;
    }
    if (area > 0.0) fr.centroid /= area;
    for (const auto& [limb, w] : on_limb)
      if (limb >= 0 && w > 0.5 * area) fr.limb = limb;
  }
  // Facing: front, back or side from the horizontal part of the normal.
  auto facing = [](const PieceFrame& fr) -> std::string {
    const double x = fr.normal.x(), z = fr.normal.z();
    if (z > std::abs(x)) return "front";
    if (-z > std::abs(x)) return "back";
    return "side";
  };
  std::vector<std::string> names(pattern.pieces.size());
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    const PieceFrame& fr = frames[c];
    const std::string face = facing(fr);
    if (fr.limb >= 0) {
      const std::string side = pattern.limbs[static_cast<size_t>(fr.limb)].left ? "left" : "right";
      // A sleeve cut into halves: its front or back half.
      int halves = 0;
      for (const PieceFrame& other : frames) halves += other.limb == fr.limb ? 1 : 0;
      names[c] = side + " sleeve" + (halves > 1 ? " " + face : "");
      continue;
    }
    int same = 0;
    for (size_t o = 0; o < frames.size(); ++o) same += frames[o].limb < 0 && facing(frames[o]) == face ? 1 : 0;
    if (same <= 1) {
      names[c] = face;
      continue;
    }
    const double dx = fr.centroid.x() - axis.x();
    names[c] = (dx > 0.04 ? "left " : dx < -0.04 ? "right " : "centre ") + face;
  }
  // Pieces that still share a name: upper and lower, then numbers.
  for (size_t c = 0; c < names.size(); ++c) {
    std::vector<size_t> group;
    for (size_t o = 0; o < names.size(); ++o)
      if (names[o] == names[c]) group.push_back(o);
    if (group.size() < 2) continue;
    std::stable_sort(group.begin(), group.end(),
                     [&](size_t a, size_t b) { return frames[a].centroid.y() > frames[b].centroid.y(); });
    const std::string base = names[c];
    if (group.size() == 2) {
      names[group[0]] = "upper " + base;
      names[group[1]] = "lower " + base;
    } else {
      for (size_t k = 0; k < group.size(); ++k) names[group[k]] = base + " " + std::to_string(k + 1);
    }
  }
  for (size_t c = 0; c < names.size(); ++c) pattern.pieces[c].name = names[c];
}

}  // namespace gp
