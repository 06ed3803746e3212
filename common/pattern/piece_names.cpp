#include "pattern/piece_names.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

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
      // A sleeve cut into parts: named after how they lie against each other
      // (front to back by centroid), not after where each faces on its own,
      // which on an arm held out sideways is "side" for both halves of one
      // sleeve and front / back for the other's.
      std::vector<size_t> parts;
      for (size_t o = 0; o < frames.size(); ++o)
        if (frames[o].limb == fr.limb) parts.push_back(o);
      std::stable_sort(parts.begin(), parts.end(),
                       [&](size_t a, size_t b) { return frames[a].centroid.z() > frames[b].centroid.z(); });
      const size_t rank = static_cast<size_t>(std::find(parts.begin(), parts.end(), c) - parts.begin());
      std::string part;
      if (parts.size() == 2) part = rank == 0 ? " front" : " back";
      if (parts.size() == 4) {
        // Two across the arm, twice along it: the two nearer the body (by
        // distance from the garment's centroid, for an arm held out or
        // down) are the upper sleeve, each pair front and back.
        std::vector<size_t> along = parts;
        std::stable_sort(along.begin(), along.end(), [&](size_t a, size_t b) {
          return (frames[a].centroid - axis).norm() < (frames[b].centroid - axis).norm();
        });
        const bool upper = std::find(along.begin(), along.begin() + 2, c) != along.begin() + 2;
        const size_t other = upper ? (along[0] == c ? along[1] : along[0]) : (along[2] == c ? along[3] : along[2]);
        names[c] = std::string(upper ? "upper " : "lower ") + side + " sleeve" +
                   (frames[c].centroid.z() >= frames[other].centroid.z() ? " front" : " back");
        continue;
      }
      if (parts.size() > 2) part = " " + std::to_string(rank + 1);
      names[c] = side + " sleeve" + part;
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
  // Pieces that still share a name: two are told apart along the axis on
  // which they lie farther apart, front / back or upper / lower; more by
  // numbers. The axis is chosen once for a name and its mirror image ("left
  // side" and "right side" together), so that mirrored pieces get mirrored
  // names and are laid out side by side.
  auto mirror_free = [](const std::string& n) {
    for (const char* prefix : {"left ", "right "})
      if (n.rfind(prefix, 0) == 0) return n.substr(std::string(prefix).size());
    return n;
  };
  std::map<std::string, Eigen::Vector2d> spread;  // mirror-free name -> (|dy|, |dz|) summed over its pairs
  for (size_t c = 0; c < names.size(); ++c)
    for (size_t o = c + 1; o < names.size(); ++o)
      if (names[o] == names[c]) {
        const Eigen::Vector3d d = frames[o].centroid - frames[c].centroid;
        auto it = spread.emplace(mirror_free(names[c]), Eigen::Vector2d::Zero()).first;
        it->second += Eigen::Vector2d(std::abs(d.y()), std::abs(d.z()));
      }
  const std::vector<std::string> before = names;
  for (size_t c = 0; c < names.size(); ++c) {
    std::vector<size_t> group;
    for (size_t o = 0; o < before.size(); ++o)
      if (before[o] == before[c]) group.push_back(o);
    if (group.size() < 2 || group.front() != c) continue;
    const std::string base = before[c];
    const Eigen::Vector2d s = spread.at(mirror_free(base));
    const bool by_depth = group.size() == 2 && s.y() > s.x();
    std::stable_sort(group.begin(), group.end(), [&](size_t a, size_t b) {
      return by_depth ? frames[a].centroid.z() > frames[b].centroid.z() : frames[a].centroid.y() > frames[b].centroid.y();
    });
    if (by_depth) {
      names[group[0]] = base + " front";
      names[group[1]] = base + " back";
    } else if (group.size() == 2) {
      names[group[0]] = "upper " + base;
      names[group[1]] = "lower " + base;
    } else {
      for (size_t k = 0; k < group.size(); ++k) names[group[k]] = base + " " + std::to_string(k + 1);
    }
  }
  for (size_t c = 0; c < names.size(); ++c) pattern.pieces[c].name = names[c];
}

std::string mirror_name(const std::string& name) {
  std::istringstream words(name);
  std::string word, out;
  while (words >> word) {
    if (word == "left") word = "right";
    else if (word == "right") word = "left";
    out += (out.empty() ? "" : " ") + word;
  }
  return out;
}

bool is_left(const std::string& name) {
  std::istringstream words(name);
  std::string word;
  while (words >> word)
    if (word == "left") return true;
  return false;
}

}  // namespace gp
