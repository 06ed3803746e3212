#include "pattern/pattern.h"

#include <algorithm>

#include <Eigen/Dense>

#include "core/error.h"
#include "mesh/barycentric.h"
#include "mesh/topology.h"
#include "pattern/curve_insertion.h"
#include "pattern/piece_names.h"

namespace gp {
namespace {

std::vector<CutPath> cut_paths(const std::vector<PatternSeam>& seams) {
  std::vector<CutPath> paths;
  for (size_t i = 0; i < seams.size(); ++i) paths.push_back({static_cast<int>(i), seams[i].vertex_ids, seams[i].closed});
  return paths;
}

}  // namespace

PatternMesh pattern_mesh_of_rest(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  PatternMesh m;
  m.rest_V = V;
  m.rest_F = F;
  m.V = V;
  m.F = F;
  m.rest_vertex_count = static_cast<int>(V.rows());
  m.rest_face.resize(static_cast<size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f) m.rest_face[static_cast<size_t>(f)] = f;
  const auto vf = vertex_faces(F, static_cast<int>(V.rows()));
  m.rest_point.resize(static_cast<size_t>(V.rows()));
  for (int v = 0; v < V.rows(); ++v) {
    SurfacePoint& s = m.rest_point[static_cast<size_t>(v)];
    if (vf[static_cast<size_t>(v)].empty()) continue;
    s.face = vf[static_cast<size_t>(v)].front();
    for (int k = 0; k < 3; ++k) s.bary[k] = F(s.face, k) == v ? 1.0 : 0.0;
  }
  return m;
}

void assemble_pieces(Pattern& pattern) {
  const PatternMesh& mesh = pattern.mesh;
  pattern.cut = cut_mesh(mesh.V, mesh.F, cut_paths(pattern.seams));
  const CutMesh& cut = pattern.cut;
  Eigen::VectorXi component;
  const int count = face_components(cut.F, component);
  pattern.pieces.assign(static_cast<size_t>(count), PatternPiece{});
  pattern.piece_of_face.assign(static_cast<size_t>(mesh.F.rows()), -1);
  pattern.local_vertex.assign(static_cast<size_t>(cut.V.rows()), -1);
  for (int f = 0; f < mesh.F.rows(); ++f) {
    const int c = component[f];
    pattern.piece_of_face[static_cast<size_t>(f)] = c;
    pattern.pieces[static_cast<size_t>(c)].face_ids.push_back(f);
  }
  for (int c = 0; c < count; ++c) {
    PatternPiece& p = pattern.pieces[static_cast<size_t>(c)];
    p.name = "P" + std::to_string(c + 1);
    std::vector<int> cut_ids;
    for (int f : p.face_ids)
      for (int k = 0; k < 3; ++k) cut_ids.push_back(cut.F(f, k));
    std::sort(cut_ids.begin(), cut_ids.end());
    cut_ids.erase(std::unique(cut_ids.begin(), cut_ids.end()), cut_ids.end());
    // Local ids in ascending cut-vertex order, for a stable numbering.
    for (size_t i = 0; i < cut_ids.size(); ++i) pattern.local_vertex[static_cast<size_t>(cut_ids[i])] = static_cast<int>(i);
    const int nv = static_cast<int>(cut_ids.size());
    p.V.resize(nv, 3);
    p.cut_vertex_ids.resize(nv);
    p.mesh_vertex_ids.resize(nv);
    for (int i = 0; i < nv; ++i) {
      p.cut_vertex_ids[i] = cut_ids[static_cast<size_t>(i)];
      p.mesh_vertex_ids[i] = cut.origin[cut_ids[static_cast<size_t>(i)]];
      p.V.row(i) = cut.V.row(cut_ids[static_cast<size_t>(i)]);
    }
    p.F.resize(static_cast<int>(p.face_ids.size()), 3);
    for (size_t i = 0; i < p.face_ids.size(); ++i)
      for (int k = 0; k < 3; ++k)
        p.F(static_cast<int>(i), k) = pattern.local_vertex[static_cast<size_t>(cut.F(p.face_ids[i], k))];
    const auto loops = boundary_loops(p.F);
    if (loops.size() == 1) p.boundary = loops.front();
  }
  name_pieces(pattern);
  // Darts belong to the piece on both their sides.
  for (size_t s = 0; s < pattern.seams.size(); ++s) {
    if (pattern.seams[s].kind != "dart") continue;
    for (const CutEdge& e : cut.edges)
      if (e.seam == static_cast<int>(s)) {
        const int l = pattern.piece_of_face[static_cast<size_t>(e.left_face)];
        if (l == pattern.piece_of_face[static_cast<size_t>(e.right_face)])
          pattern.pieces[static_cast<size_t>(l)].dart_seams.push_back(static_cast<int>(s));
        break;
      }
  }
}

std::vector<MaterialFace> material_faces(const Pattern& pattern, size_t c) {
  const PatternMesh& mesh = pattern.mesh;
  const PatternPiece& p = pattern.pieces[c];
  // Parts of every rest face in the piece.
  std::vector<std::pair<int, int>> parts;  // (rest face, index in the piece)
  for (size_t i = 0; i < p.face_ids.size(); ++i)
    parts.push_back({mesh.rest_face[static_cast<size_t>(p.face_ids[i])], static_cast<int>(i)});
  std::sort(parts.begin(), parts.end());
  std::vector<MaterialFace> out;
  for (size_t a = 0; a < parts.size();) {
    size_t b = a;
    while (b < parts.size() && parts[b].first == parts[a].first) ++b;
    const int f = parts[a].first;
    const Eigen::Vector3d r0 = mesh.rest_V.row(mesh.rest_F(f, 0)), r1 = mesh.rest_V.row(mesh.rest_F(f, 1)),
                          r2 = mesh.rest_V.row(mesh.rest_F(f, 2));
    const Eigen::Vector3d normal = (r1 - r0).cross(r2 - r0);
    MaterialFace m;
    m.rest_face = f;
    Eigen::Matrix2d G = Eigen::Matrix2d::Zero();
    if (normal.norm() > 0.0 && (r1 - r0).norm() > 0.0) {
      const Eigen::Vector3d x = (r1 - r0).normalized(), y = normal.normalized().cross(x);
      auto plane = [&](int v) {
        const Eigen::Vector3d d = p.V.row(v).transpose() - r0;
        return Eigen::Vector2d(d.dot(x), d.dot(y));
      };
      for (size_t k = a; k < b; ++k) {
        const int i = parts[k].second;
        Eigen::Matrix2d Q, S;
        for (int j = 1; j < 3; ++j) {
          Q.col(j - 1) = plane(p.F(i, j)) - plane(p.F(i, 0));
          S.col(j - 1) = (p.flat.UV.row(p.F(i, j)) - p.flat.UV.row(p.F(i, 0))).transpose();
        }
        const double part = 0.5 * std::abs(Q.determinant());
        if (!(part > 0.0)) continue;
        const Eigen::Matrix2d A = S * Q.inverse();
        G += part * A.transpose() * A;
        m.area += part;
        m.flat_area += 0.5 * S.determinant();
        m.centroid += part * (p.V.row(p.F(i, 0)) + p.V.row(p.F(i, 1)) + p.V.row(p.F(i, 2))).transpose() / 3.0;
      }
    }
    if (m.area > 0.0) {
      G /= m.area;
      m.centroid /= m.area;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(G);
      const Eigen::Vector2d ev = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
      m.stretch = Eigen::Vector2d(ev[1], ev[0]);
      out.push_back(m);
    }
    a = b;
  }
  return out;
}

DistortionStats material_distortion(const Pattern& pattern, size_t c) {
  const std::vector<MaterialFace> faces = material_faces(pattern, c);
  Eigen::MatrixXd S(static_cast<int>(faces.size()), 2);
  Eigen::VectorXd A3(static_cast<int>(faces.size())), A2(static_cast<int>(faces.size()));
  for (size_t i = 0; i < faces.size(); ++i) {
    S.row(static_cast<int>(i)) = faces[i].stretch.transpose();
    A3[static_cast<int>(i)] = faces[i].area;
    A2[static_cast<int>(i)] = faces[i].flat_area;
  }
  return distortion_stats(S, A3, A2);
}

bool is_disk(const PatternPiece& piece) {
  return boundary_loops(piece.F).size() == 1 && euler_characteristic(piece.F) == 1;
}

void insert_cuts(Pattern& pattern, std::vector<PatternSeam> seams, const std::vector<SurfaceCurve>& curves) {
  if (seams.size() != curves.size()) throw GeometryError("insert_cuts: one curve per seam");
  PatternMesh& mesh = pattern.mesh;
  std::vector<std::vector<int>> carried;
  for (const PatternSeam& s : pattern.seams) {
    std::vector<int> path = s.vertex_ids;
    if (s.closed && !path.empty()) path.push_back(path.front());
    carried.push_back(path);
  }
  RefinedMesh r;
  try {
    r = insert_curves(mesh.V, mesh.F, curves, carried);
  } catch (const GeometryError& e) {
    std::string names;
    for (const PatternSeam& s : seams) names += (names.empty() ? "" : ", ") + s.name;
    throw GeometryError(std::string(e.what()) + " (cutting " + names + ")");
  }
  std::vector<int> rest_face(static_cast<size_t>(r.F.rows()));
  for (int f = 0; f < r.F.rows(); ++f) rest_face[static_cast<size_t>(f)] = mesh.rest_face[static_cast<size_t>(r.parent_face[static_cast<size_t>(f)])];
  std::vector<SurfacePoint> rest_point = mesh.rest_point;
  for (int v = static_cast<int>(mesh.V.rows()); v < r.V.rows(); ++v) {
    const int f = mesh.rest_face[static_cast<size_t>(r.origin[static_cast<size_t>(v)].face)];
    const Eigen::Vector3d a = mesh.rest_V.row(mesh.rest_F(f, 0)), b = mesh.rest_V.row(mesh.rest_F(f, 1)),
                          c = mesh.rest_V.row(mesh.rest_F(f, 2));
    rest_point.push_back({f, barycentric(r.V.row(v).transpose(), a, b, c)});
  }
  mesh.V = r.V;
  mesh.F = r.F;
  mesh.rest_face = rest_face;
  mesh.rest_point = rest_point;
  for (size_t i = 0; i < pattern.seams.size(); ++i) {
    std::vector<int> path = r.carried[i];
    if (pattern.seams[i].closed && path.size() > 1) path.pop_back();
    pattern.seams[i].vertex_ids = path;
  }
  for (size_t i = 0; i < seams.size(); ++i) {
    seams[i].vertex_ids = r.paths[i];
    if (seams[i].closed && seams[i].vertex_ids.size() > 1 && seams[i].vertex_ids.back() == seams[i].vertex_ids.front())
      seams[i].vertex_ids.pop_back();
    pattern.seams.push_back(seams[i]);
  }
  assemble_pieces(pattern);
}

}  // namespace gp
