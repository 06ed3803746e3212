#include "pattern/piece_names.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

#include <Eigen/Geometry>

#include "mesh/measures.h"
#include "pattern/cutter_helpers.h"

namespace gp {
namespace {

struct PieceFrame {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // area-weighted, not normalized
  double left_share = 0.0;                           // fraction of its area on the body's left
  int limb = -1;
};

// A piece with at least this share of its area on either side of the body's
// axis lies across it (a whole front or back); otherwise it is on the side
// where most of it lies.
constexpr double kAcrossShare = 0.25;

// The name of part c of a sleeve cut into `parts` (frames' indices, c among
// them) on the `side` ("left" or "right") of the body, whose vertical axis
// runs through `axis`. The parts are named after how they lie against each
// other, not after where each faces on its own, which on an arm held out
// sideways is "side" for both halves of one sleeve and front / back for the
// other's. Along the arm is the distance from the axis (for an arm held out
// or down); across it, front to back, is z.
std::string sleeve_part_name(const std::vector<PieceFrame>& frames, std::vector<size_t> parts, size_t c,
                             const Eigen::Vector3d& axis, const std::string& side) {
  auto along = [&](size_t o) { return (frames[o].centroid - axis).norm(); };
  auto z = [&](size_t o) { return frames[o].centroid.z(); };
  const std::string sleeve = side + " sleeve";
  if (parts.size() == 4) {
    // Two across the arm, twice along it: the two nearer the body are the
    // upper sleeve, each pair front and back.
    std::stable_sort(parts.begin(), parts.end(), [&](size_t a, size_t b) { return along(a) < along(b); });
    const bool upper = std::find(parts.begin(), parts.begin() + 2, c) != parts.begin() + 2;
    const size_t other = upper ? (parts[0] == c ? parts[1] : parts[0]) : (parts[2] == c ? parts[3] : parts[2]);
    return std::string(upper ? "upper " : "lower ") + sleeve + (z(c) >= z(other) ? " front" : " back");
  }
  if (parts.size() == 3) {
    // One part the length of the sleeve on one side, two along it on the
    // other (a sleeve cut by one panel seam across half of it): the two are
    // the pair lying farthest apart along the arm and least across.
    size_t lone = parts[0];
    double best = -1e300;
    for (size_t k = 0; k < 3; ++k) {
      const size_t a = parts[(k + 1) % 3], b = parts[(k + 2) % 3];
      const double score = std::abs(along(a) - along(b)) - std::abs(z(a) - z(b));
      if (score > best) best = score, lone = parts[k];
    }
    std::vector<size_t> pair;
    for (size_t o : parts)
      if (o != lone) pair.push_back(o);
    const bool lone_in_front = z(lone) >= 0.5 * (z(pair[0]) + z(pair[1]));
    if (c == lone) return sleeve + (lone_in_front ? " front" : " back");
    const size_t other = pair[0] == c ? pair[1] : pair[0];
    return std::string(along(c) <= along(other) ? "upper " : "lower ") + sleeve + (lone_in_front ? " back" : " front");
  }
  // Otherwise front to back: two are front and back, more are numbered.
  std::stable_sort(parts.begin(), parts.end(), [&](size_t a, size_t b) { return z(a) > z(b); });
  const size_t rank = static_cast<size_t>(std::find(parts.begin(), parts.end(), c) - parts.begin());
  if (parts.size() == 2) return sleeve + (rank == 0 ? " front" : " back");
  if (parts.size() > 2) return sleeve + " " + std::to_string(rank + 1);
  return sleeve;
}

}  // namespace

void name_pieces(Pattern& pattern, const PieceMirror& mirror) {
  const PatternMesh& mesh = pattern.mesh;
  // The garment's area centroid: the body's vertical axis runs through it.
  const Eigen::Vector3d axis = area_centroid(mesh.rest_V, mesh.rest_F);
  std::vector<PieceFrame> frames(pattern.pieces.size());
  for (size_t c = 0; c < pattern.pieces.size(); ++c) {
    const PatternPiece& p = pattern.pieces[c];
    PieceFrame& fr = frames[c];
    double area = 0.0;
    for (size_t i = 0; i < p.face_ids.size(); ++i) {
      const Eigen::Vector3d a = p.V.row(p.F(static_cast<int>(i), 0)), b = p.V.row(p.F(static_cast<int>(i), 1)),
                            d = p.V.row(p.F(static_cast<int>(i), 2));
      const Eigen::Vector3d n = 0.5 * (b - a).cross(d - a);
      const double w = n.norm();
      fr.centroid += w * (a + b + d) / 3.0;
      fr.left_share += (a.x() + b.x() + d.x()) / 3.0 > axis.x() ? w : 0.0;
      fr.normal += n;
      area += w;
    }
    if (area > 0.0) {
      fr.centroid /= area;
      fr.left_share /= area;
    }
    fr.limb = piece_limb(pattern, c);
  }
  // A mirrored pair is seen as the average of the two, each the other's
  // mirror image across the mirror's plane.
  auto flip = [](Eigen::Vector3d n) {
    n.x() = -n.x();
    return n;
  };
  for (size_t c = 0; c < std::min(mirror.partner.size(), frames.size()); ++c) {
    const int d = mirror.partner[c];
    if (d <= static_cast<int>(c) || static_cast<size_t>(d) >= frames.size()) continue;
    PieceFrame& a = frames[c];
    PieceFrame& b = frames[static_cast<size_t>(d)];
    a.centroid = 0.5 * (a.centroid + mirror.reflect(b.centroid));
    a.normal = 0.5 * (a.normal + flip(b.normal));
    a.left_share = 0.5 * (a.left_share + 1.0 - b.left_share);
    b.centroid = mirror.reflect(a.centroid);
    b.normal = flip(a.normal);
    b.left_share = 1.0 - a.left_share;
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
      std::vector<size_t> parts;
      for (size_t o = 0; o < frames.size(); ++o)
        if (frames[o].limb == fr.limb) parts.push_back(o);
      names[c] = sleeve_part_name(frames, parts, c, axis, side);
      continue;
    }
    int same = 0;
    for (size_t o = 0; o < frames.size(); ++o) same += frames[o].limb < 0 && facing(frames[o]) == face ? 1 : 0;
    if (same <= 1) {
      names[c] = face;
      continue;
    }
    const bool across = std::min(fr.left_share, 1.0 - fr.left_share) >= kAcrossShare;
    names[c] = across ? face : (fr.left_share > 0.5 ? "left " : "right ") + face;
  }
  // Pieces that still share a name: two are told apart along the axis on
  // which they lie farther apart: centre / side across the body (panels, as
  // a centre back and a side back), front / back or upper / lower; more by
  // numbers. The axis is chosen once for a name and its mirror image ("left
  // back" and "right back" together), so that mirrored pieces get mirrored
  // names and are laid out side by side.
  auto split_side = [](const std::string& n) -> std::pair<std::string, std::string> {
    for (const char* prefix : {"left ", "right "})
      if (n.rfind(prefix, 0) == 0) return {prefix, n.substr(std::string(prefix).size())};
    return {"", n};
  };
  std::map<std::string, Eigen::Vector3d> spread;  // mirror-free name -> (|dx|, |dy|, |dz|) summed over its pairs
  for (size_t c = 0; c < names.size(); ++c)
    for (size_t o = c + 1; o < names.size(); ++o)
      if (names[o] == names[c]) {
        const Eigen::Vector3d d = frames[o].centroid - frames[c].centroid;
        auto it = spread.emplace(split_side(names[c]).second, Eigen::Vector3d::Zero()).first;
        it->second += d.cwiseAbs();
      }
  const std::vector<std::string> before = names;
  for (size_t c = 0; c < names.size(); ++c) {
    std::vector<size_t> group;
    for (size_t o = 0; o < before.size(); ++o)
      if (before[o] == before[c]) group.push_back(o);
    if (group.size() < 2 || group.front() != c) continue;
    const std::string base = before[c];
    const auto [side, rest] = split_side(base);
    const Eigen::Vector3d s = spread.at(rest);
    Eigen::Index axis_of_split = 1;
    if (group.size() == 2) s.maxCoeff(&axis_of_split);
    std::stable_sort(group.begin(), group.end(), [&](size_t a, size_t b) {
      switch (axis_of_split) {
        case 0: return std::abs(frames[a].centroid.x() - axis.x()) < std::abs(frames[b].centroid.x() - axis.x());
        case 2: return frames[a].centroid.z() > frames[b].centroid.z();
        default: return frames[a].centroid.y() > frames[b].centroid.y();
      }
    });
    if (group.size() > 2) {
      for (size_t k = 0; k < group.size(); ++k) names[group[k]] = base + " " + std::to_string(k + 1);
    } else if (axis_of_split == 0) {
      names[group[0]] = side + "centre " + rest;
      names[group[1]] = side + "side " + rest;
    } else if (axis_of_split == 2) {
      names[group[0]] = base + " front";
      names[group[1]] = base + " back";
    } else {
      names[group[0]] = "upper " + base;
      names[group[1]] = "lower " + base;
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
