#include "export/sewn_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "core/error.h"

namespace gp {

std::vector<cloth::TriangleRest> sewn_rest_triangles(const Pattern& pattern, const Layout& layout, int face_count,
                                                     std::vector<int>* from_rest_shape) {
  const PatternMesh& mesh = pattern.mesh;
  if (from_rest_shape) from_rest_shape->clear();
  if (face_count != mesh.rest_F.rows()) throw GeometryError("the pattern was not made from this rest shape");
  // Sheet position of pattern-mesh face g's corner k, turned by -90 degrees
  // to (y, -x): the grain (+y) becomes the warp (+u).
  std::vector<int> index_in_piece(static_cast<size_t>(mesh.F.rows()), -1);
  for (const PatternPiece& p : pattern.pieces)
    for (size_t i = 0; i < p.face_ids.size(); ++i) index_in_piece[static_cast<size_t>(p.face_ids[i])] = static_cast<int>(i);
  auto sheet = [&](int g, int k) {
    const int c = pattern.piece_of_face[static_cast<size_t>(g)];
    const PatternPiece& p = pattern.pieces[static_cast<size_t>(c)];
    const Eigen::RowVector2d x = layout.pieces[static_cast<size_t>(c)].UV.row(p.F(index_in_piece[static_cast<size_t>(g)], k));
    return Eigen::Vector2d(x.y(), -x.x());
  };
  std::vector<std::vector<int>> parts(static_cast<size_t>(face_count));
  for (int g = 0; g < mesh.F.rows(); ++g) parts[static_cast<size_t>(mesh.rest_face[static_cast<size_t>(g)])].push_back(g);
  std::vector<cloth::TriangleRest> rest(static_cast<size_t>(face_count));
  for (int f = 0; f < face_count; ++f) {
    const auto& gs = parts[static_cast<size_t>(f)];
    if (gs.empty()) throw GeometryError("the pattern does not cover every rest face");
    const Eigen::Vector3d r0 = mesh.rest_V.row(mesh.rest_F(f, 0)), r1 = mesh.rest_V.row(mesh.rest_F(f, 1)),
                          r2 = mesh.rest_V.row(mesh.rest_F(f, 2));
    const Eigen::Vector3d x = (r1 - r0).normalized(), y = (r1 - r0).cross(r2 - r0).normalized().cross(x);
    auto plane = [&](const Eigen::Vector3d& X) { return Eigen::Vector2d((X - r0).dot(x), (X - r0).dot(y)); };
    // A sliver of the rest shape that its flattening squeezed below the cloth
    // model's bound on triangle quality has no usable flat triangle: it keeps
    // the rest shape's own, turned like the cloth around it (rotation R).
    auto keep = [&](const Eigen::Matrix<double, 2, 3>& P, const Eigen::Matrix2d& R) {
      try {
        rest[static_cast<size_t>(f)] = cloth::triangle_rest_flat(P);
      } catch (const GeometryError&) {
        Eigen::Matrix<double, 2, 3> Q;
        Q.col(0).setZero();
        Q.col(1) = R * plane(r1);
        Q.col(2) = R * plane(r2);
        rest[static_cast<size_t>(f)] = cloth::triangle_rest_flat(Q);
        if (from_rest_shape) from_rest_shape->push_back(f);
      }
    };
    if (gs.size() == 1) {
      // An uncut rest face: its triangle as laid out.
      Eigen::Matrix<double, 2, 3> P;
      for (int k = 0; k < 3; ++k) P.col(k) = sheet(gs.front(), k);
      // Its rotation: that of its affine map from the face's plane to the sheet.
      const int g = gs.front();
      Eigen::Matrix2d Q, S;
      for (int k = 1; k < 3; ++k) {
        Q.col(k - 1) = plane(mesh.V.row(mesh.F(g, k)).transpose()) - plane(mesh.V.row(mesh.F(g, 0)).transpose());
        S.col(k - 1) = P.col(k) - P.col(0);
      }
      Eigen::Matrix2d R = Eigen::Matrix2d::Identity();
      if (std::abs(Q.determinant()) > 0.0) {
        const Eigen::JacobiSVD<Eigen::Matrix2d> svd(S * Q.inverse(), Eigen::ComputeFullU | Eigen::ComputeFullV);
        R = svd.matrixU() * svd.matrixV().transpose();
      }
      keep(P, R);
      continue;
    }
    // A rest face that a cut crosses is cloth from two pieces (or a piece
    // and a dart): its rest metric is the area-weighted mean of its parts'
    // metrics A^T A, A the affine map of a part from the face's plane to the
    // sheet; the warp is that of its largest part.
    Eigen::Matrix2d G = Eigen::Matrix2d::Zero(), R = Eigen::Matrix2d::Identity();
    double total = 0.0, largest = -1.0;
    for (int g : gs) {
      Eigen::Matrix2d Q, S;
      const Eigen::Vector2d q0 = plane(mesh.V.row(mesh.F(g, 0)).transpose());
      const Eigen::Vector2d s0 = sheet(g, 0);
      for (int k = 1; k < 3; ++k) {
        Q.col(k - 1) = plane(mesh.V.row(mesh.F(g, k)).transpose()) - q0;
        S.col(k - 1) = sheet(g, k) - s0;
      }
      const double area = 0.5 * std::abs(Q.determinant());
      if (!(area > 0.0)) continue;
      const Eigen::Matrix2d A = S * Q.inverse();
      G += area * A.transpose() * A;
      total += area;
      if (area > largest) {
        largest = area;
        const Eigen::JacobiSVD<Eigen::Matrix2d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
        R = svd.matrixU() * svd.matrixV().transpose();
      }
    }
    if (!(total > 0.0)) throw GeometryError("rest face " + std::to_string(f) + " has no area in the pattern");
    G /= total;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(G);
    const Eigen::Matrix2d root =
        eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eig.eigenvectors().transpose();
    const Eigen::Matrix2d M = R * root;
    Eigen::Matrix<double, 2, 3> P;
    P.col(0).setZero();
    P.col(1) = M * plane(r1);
    P.col(2) = M * plane(r2);
    keep(P, R);
  }
  return rest;
}

std::vector<int> piece_of_rest_face(const Pattern& pattern) {
  const PatternMesh& mesh = pattern.mesh;
  const int m = static_cast<int>(mesh.rest_F.rows());
  std::vector<int> piece(static_cast<size_t>(m), -1);
  std::vector<double> best(static_cast<size_t>(m), -1.0);
  for (int g = 0; g < mesh.F.rows(); ++g) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(g, 0)), b = mesh.V.row(mesh.F(g, 1)), c = mesh.V.row(mesh.F(g, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const size_t f = static_cast<size_t>(mesh.rest_face[static_cast<size_t>(g)]);
    // Ties go to the lower piece, so that the answer does not depend on face order.
    const int c_g = pattern.piece_of_face[static_cast<size_t>(g)];
    if (area > best[f] || (area == best[f] && c_g < piece[f])) {
      best[f] = area;
      piece[f] = c_g;
    }
  }
  return piece;
}

std::vector<int> piece_of_rest_vertex(const Pattern& pattern) {
  const PatternMesh& mesh = pattern.mesh;
  std::vector<int> piece(static_cast<size_t>(mesh.rest_vertex_count), -1);
  for (int g = 0; g < mesh.F.rows(); ++g) {
    const int c = pattern.piece_of_face[static_cast<size_t>(g)];
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(g, k);
      if (v >= mesh.rest_vertex_count) continue;
      int& p = piece[static_cast<size_t>(v)];
      if (p < 0 || c < p) p = c;
    }
  }
  return piece;
}

SewnPoseWhere locate_sewn_pose(const adapt::PoseCheck& check, const Pattern& pattern,
                               const std::vector<cloth::TriangleRest>& sewn, const Eigen::MatrixXi& F,
                               double delta) {
  const adapt::KeyPoseResult& k = check.figures;
  SewnPoseWhere where;
  const std::vector<int> face_piece = piece_of_rest_face(pattern);
  const size_t n = pattern.pieces.size();
  std::vector<double> total(n, 0.0), above(n, 0.0), worst(n, 0.0);
  const double limit = 1.0 + delta;
  double largest = -1.0;
  for (int f = 0; f < F.rows(); ++f) {
    const int c = face_piece[static_cast<size_t>(f)];
    const double s = k.face_max_stretch.size() > f ? k.face_max_stretch[f] : 0.0;
    if (s > largest) {
      largest = s;
      where.worst_face = f;
      where.worst_face_piece = c;
    }
    if (c < 0) continue;
    const double a = sewn[static_cast<size_t>(f)].area;
    total[static_cast<size_t>(c)] += a;
    if (s > limit) above[static_cast<size_t>(c)] += a;
    worst[static_cast<size_t>(c)] = std::max(worst[static_cast<size_t>(c)], s);
  }
  for (size_t c = 0; c < n; ++c) {
    if (!(above[c] > 0.0)) continue;
    where.pieces.push_back({static_cast<int>(c), above[c] / total[c], worst[c]});
  }
  std::sort(where.pieces.begin(), where.pieces.end(), [](const PieceStretch& a, const PieceStretch& b) {
    return a.area_fraction_above > b.area_fraction_above ||
           (a.area_fraction_above == b.area_fraction_above && a.piece < b.piece);
  });
  if (where.worst_face >= 0 && k.V_draped.rows() > 0) {
    for (int j = 0; j < 3; ++j) where.worst_face_position += k.V_draped.row(F(where.worst_face, j)).transpose() / 3.0;
  }
  where.deepest_vertex = k.crossings.deepest_cloth_vertex_id;
  if (where.deepest_vertex >= 0) {
    const std::vector<int> vertex_piece = piece_of_rest_vertex(pattern);
    if (static_cast<size_t>(where.deepest_vertex) < vertex_piece.size())
      where.deepest_vertex_piece = vertex_piece[static_cast<size_t>(where.deepest_vertex)];
    if (where.deepest_vertex < k.V_draped.rows())
      where.deepest_vertex_position = k.V_draped.row(where.deepest_vertex).transpose();
  }
  return where;
}

SewnFitResult sewn_fit_check(PoseInterpolator& interpolator, const MotionSpec& motion, const Eigen::MatrixXd& V_start,
                             const Eigen::MatrixXi& F, const GarmentFile& garment, const Pattern& pattern,
                             const Layout& layout, const adapt::MotionRunOptions& options,
                             const adapt::FitCriteria& criteria, const adapt::ProgressCallback& progress) {
  if (V_start.rows() != pattern.mesh.rest_V.rows() || V_start.cols() != 3)
    throw GeometryError("sewn-fit check: the start positions do not match the rest shape");
  SewnFitResult result;
  const std::vector<cloth::TriangleRest> sewn =
      sewn_rest_triangles(pattern, layout, static_cast<int>(F.rows()), &result.faces_from_rest_shape);
  result.delta = options.adaptation.adapter.delta;
  for (const cloth::TriangleRest& t : sewn) result.sewn_rest_area += t.area;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = pattern.mesh.rest_V.row(F(f, 0)), b = pattern.mesh.rest_V.row(F(f, 1)),
                          c = pattern.mesh.rest_V.row(F(f, 2));
    result.rest_area += 0.5 * (b - a).cross(c - a).norm();
  }
  result.verification = adapt::verify_fit(interpolator, motion, V_start, F, garment, sewn, options, criteria, progress);
  // The in-between frames (options.frame_stride) are judged as the key poses are.
  for (const adapt::PoseCheck& check : result.verification.poses)
    result.where.push_back(locate_sewn_pose(check, pattern, sewn, F, result.delta));
  return result;
}

adapt::FitVerification rest_shape_drapes(PoseInterpolator& interpolator, const MotionSpec& motion,
                                         const Eigen::MatrixXd& V_start, const Eigen::MatrixXd& V_rest,
                                         const Eigen::MatrixXi& F, const GarmentFile& garment,
                                         const adapt::MotionRunOptions& options, const adapt::FitCriteria& criteria,
                                         const adapt::ProgressCallback& progress) {
  if (V_rest.rows() != V_start.rows() || V_rest.cols() != 3)
    throw GeometryError("the rest shape has " + std::to_string(V_rest.rows()) + " vertices, the design " +
                        std::to_string(V_start.rows()));
  return adapt::verify_fit(interpolator, motion, V_start, F, garment, adapt::rest_triangles_of(V_rest, F), options,
                           criteria, progress);
}

std::vector<Eigen::MatrixXd> settle_from_reference(PoseInterpolator& interpolator, const MotionSpec& motion,
                                                   const std::vector<Eigen::MatrixXd>& reference,
                                                   const Eigen::MatrixXi& F, const GarmentFile& garment,
                                                   const std::vector<cloth::TriangleRest>& rest_triangles,
                                                   const adapt::MotionRunOptions& options,
                                                   const adapt::FitCriteria& criteria) {
  if (reference.size() != motion.keys.size())
    throw GeometryError("the motion has " + std::to_string(motion.keys.size()) + " key poses, the reference " +
                        std::to_string(reference.size()) + " drapes");
  std::vector<Eigen::MatrixXd> out;
  for (size_t i = 0; i < motion.keys.size(); ++i) {
    MotionSpec one = motion;
    one.keys = {motion.keys[i]};
    one.keys[0].steps = 0;
    const adapt::FitVerification v =
        adapt::verify_fit(interpolator, one, reference[i], F, garment, rest_triangles, options, criteria);
    out.push_back(v.poses.front().figures.V_draped);
  }
  return out;
}

DrapeDistance drape_distance(const Eigen::MatrixXd& V_sewn, const Eigen::MatrixXd& V_verified,
                             const Eigen::MatrixXi& F, const DrapeCriteria& criteria) {
  if (V_sewn.rows() != V_verified.rows() || V_sewn.cols() != 3 || V_verified.cols() != 3)
    throw GeometryError("the sewn drape has " + std::to_string(V_sewn.rows()) + " vertices, the verified drape " +
                        std::to_string(V_verified.rows()));
  DrapeDistance d;
  const Eigen::Index n = V_sewn.rows();
  d.vertex_distance = (V_sewn - V_verified).rowwise().norm();
  // Vertex weights: a third of the verified drape's area of every face
  // around it (the distance is a field on the cloth, so a dense patch of
  // small triangles counts by its area, not its vertex count).
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(n);
  for (int f = 0; f < F.rows(); ++f) {
    auto area = [&](const Eigen::MatrixXd& V) {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      return 0.5 * (b - a).cross(c - a).norm();
    };
    const double av = area(V_verified);
    d.verified_area += av;
    d.sewn_area += area(V_sewn);
    for (int k = 0; k < 3; ++k) weight[F(f, k)] += av / 3.0;
  }
  const double total = weight.sum();
  if (n == 0 || !(total > 0.0)) return d;
  d.mean = weight.dot(d.vertex_distance) / total;
  std::vector<Eigen::Index> order(static_cast<size_t>(n));
  for (Eigen::Index v = 0; v < n; ++v) order[static_cast<size_t>(v)] = v;
  // Ascending distance, ties by vertex id (deterministic).
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    return d.vertex_distance[a] < d.vertex_distance[b] || (d.vertex_distance[a] == d.vertex_distance[b] && a < b);
  });
  double acc = 0.0;
  d.p95 = d.vertex_distance[order.back()];
  for (Eigen::Index v : order) {
    acc += weight[v];
    if (acc >= 0.95 * total) {
      d.p95 = d.vertex_distance[v];
      break;
    }
  }
  d.max_vertex = static_cast<int>(order.back());
  d.max = d.vertex_distance[order.back()];
  d.max_position = V_sewn.row(d.max_vertex).transpose();
  char buf[160];
  if (criteria.max_mean > 0.0 && d.mean > criteria.max_mean) {
    std::snprintf(buf, sizeof(buf), "mean distance to the verified drape %.1f mm above %.1f mm", 1e3 * d.mean,
                  1e3 * criteria.max_mean);
    d.failures.push_back(buf);
  }
  if (criteria.max_p95 > 0.0 && d.p95 > criteria.max_p95) {
    std::snprintf(buf, sizeof(buf), "p95 distance to the verified drape %.1f mm above %.1f mm", 1e3 * d.p95,
                  1e3 * criteria.max_p95);
    d.failures.push_back(buf);
  }
  return d;
}

void compare_with_verified(SewnFitResult& result, const std::vector<Eigen::MatrixXd>& verified,
                           const std::vector<std::string>& verified_meshes, const Eigen::MatrixXi& F,
                           const DrapeCriteria& criteria) {
  const auto& poses = result.verification.poses;
  if (verified.size() != poses.size() || verified_meshes.size() != poses.size())
    throw GeometryError("the fit verified " + std::to_string(verified.size()) + " key poses, the sewn garment has " +
                        std::to_string(poses.size()));
  result.drape_criteria = criteria;
  result.drape.clear();
  for (size_t i = 0; i < poses.size(); ++i) {
    DrapeDistance d = drape_distance(poses[i].figures.V_draped, verified[i], F, criteria);
    d.key = poses[i].figures.key;
    d.pose = poses[i].figures.pose;
    d.verified_mesh = verified_meshes[i];
    result.drape.push_back(std::move(d));
  }
}

std::string sewn_fit_failure(const SewnFitResult& result, const Pattern& pattern) {
  // A pose that fits but drapes away from the verified drape: the sewn
  // garment is not the designed one (stretch failures are named first).
  if (result.verification.passed())
    for (const DrapeDistance& d : result.judged()) {
      if (d.passed()) continue;
      std::string line = "key pose " + std::to_string(d.key) + " (" + d.pose + "): ";
      if (!result.settled.empty()) line += "settled at this pose alone from the verified drape, ";
      for (size_t j = 0; j < d.failures.size(); ++j) line += (j ? "; " : "") + d.failures[j];
      const std::vector<int> vertex_piece = piece_of_rest_vertex(pattern);
      if (d.max_vertex >= 0 && static_cast<size_t>(d.max_vertex) < vertex_piece.size() &&
          vertex_piece[static_cast<size_t>(d.max_vertex)] >= 0) {
        char buf[160];
        std::snprintf(buf, sizeof(buf), "; farthest in %s (%.1f mm, vertex %d)",
                      pattern.pieces[static_cast<size_t>(vertex_piece[static_cast<size_t>(d.max_vertex)])].name.c_str(),
                      1e3 * d.max, d.max_vertex);
        line += buf;
      }
      return line;
    }
  for (size_t i = 0; i < result.verification.poses.size(); ++i) {
    const adapt::PoseCheck& check = result.verification.poses[i];
    if (check.passed()) continue;
    const SewnPoseWhere& w = result.where[i];
    std::string line = "key pose " + std::to_string(check.figures.key) + " (" + check.figures.pose + "): ";
    for (size_t j = 0; j < check.failures.size(); ++j) line += (j ? "; " : "") + check.failures[j];
    auto name = [&pattern](int c) { return c >= 0 ? pattern.pieces[static_cast<size_t>(c)].name : std::string("?"); };
    char buf[200];
    if (!w.pieces.empty()) {
      std::snprintf(buf, sizeof(buf), "; worst in %s (%.1f %% of its area above %.3f, up to %.3f)",
                    name(w.pieces.front().piece).c_str(), 100.0 * w.pieces.front().area_fraction_above,
                    1.0 + result.delta, w.pieces.front().max_stretch);
      line += buf;
    } else if (w.worst_face >= 0) {
      line += "; largest stretch in " + name(w.worst_face_piece);
    }
    if (w.deepest_vertex >= 0 && check.figures.deepest_penetration > 0.0)
      line += "; deepest inside the body in " + name(w.deepest_vertex_piece) + " (vertex " +
              std::to_string(w.deepest_vertex) + ")";
    return line;
  }
  for (const adapt::TransitionCheck& t : result.verification.transitions) {
    if (!t.passed()) return adapt::failure_line(t);
  }
  return "";
}

}  // namespace gp
