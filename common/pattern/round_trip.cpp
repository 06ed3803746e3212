#include "pattern/round_trip.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>

#include "adapt/garment_motion.h"
#include "core/error.h"
#include "interp/motion_spec.h"
#include "interp/pose_interpolator.h"

namespace gp {
namespace {

// Area-weighted figures of the principal stretches of every face: X (#V by 3)
// against the rest triangles.
StretchFigures stretch_figures(const Eigen::MatrixXd& X, const Eigen::MatrixXi& F,
                               const std::vector<cloth::TriangleRest>& rest) {
  StretchFigures s;
  const int m = static_cast<int>(F.rows());
  std::vector<double> s1(static_cast<size_t>(m)), area(static_cast<size_t>(m));
  double total = 0.0, weighted = 0.0;
  s.min_s2 = std::numeric_limits<double>::infinity();
  for (int f = 0; f < m; ++f) {
    Eigen::Matrix3d T;
    for (int k = 0; k < 3; ++k) T.col(k) = X.row(F(f, k)).transpose();
    const Eigen::Matrix<double, 3, 2> W = cloth::triangle_w(T, rest[static_cast<size_t>(f)]);
    const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>> svd(W);
    const size_t i = static_cast<size_t>(f);
    s1[i] = svd.singularValues()[0];
    area[i] = rest[i].area;
    s.max_s1 = std::max(s.max_s1, s1[i]);
    s.min_s2 = std::min(s.min_s2, svd.singularValues()[1]);
    weighted += area[i] * s1[i];
    total += area[i];
  }
  if (m == 0) return StretchFigures{};
  s.mean_s1 = weighted / total;
  std::vector<int> order(static_cast<size_t>(m));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return s1[static_cast<size_t>(a)] < s1[static_cast<size_t>(b)] ||
           (s1[static_cast<size_t>(a)] == s1[static_cast<size_t>(b)] && a < b);
  });
  double acc = 0.0;
  s.p95_s1 = s1[static_cast<size_t>(order.back())];
  for (int f : order) {
    acc += area[static_cast<size_t>(f)];
    if (acc >= 0.95 * total) {
      s.p95_s1 = s1[static_cast<size_t>(f)];
      break;
    }
  }
  return s;
}

}  // namespace

std::vector<cloth::TriangleRest> sewn_rest_triangles(const Pattern& pattern, const Layout& layout, int face_count) {
  const PatternMesh& mesh = pattern.mesh;
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
    if (gs.size() == 1) {
      // An uncut rest face: its triangle as laid out.
      Eigen::Matrix<double, 2, 3> P;
      for (int k = 0; k < 3; ++k) P.col(k) = sheet(gs.front(), k);
      rest[static_cast<size_t>(f)] = cloth::triangle_rest_flat(P);
      continue;
    }
    // A rest face that a cut crosses is cloth from two pieces (or a piece
    // and a dart): its rest metric is the area-weighted mean of its parts'
    // metrics A^T A, A the affine map of a part from the face's plane to the
    // sheet; the warp is that of its largest part.
    const Eigen::Vector3d r0 = mesh.rest_V.row(mesh.rest_F(f, 0)), r1 = mesh.rest_V.row(mesh.rest_F(f, 1)),
                          r2 = mesh.rest_V.row(mesh.rest_F(f, 2));
    const Eigen::Vector3d x = (r1 - r0).normalized(), y = (r1 - r0).cross(r2 - r0).normalized().cross(x);
    auto plane = [&](const Eigen::Vector3d& X) { return Eigen::Vector2d((X - r0).dot(x), (X - r0).dot(y)); };
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
    rest[static_cast<size_t>(f)] = cloth::triangle_rest_flat(P);
  }
  return rest;
}

RoundTripResult round_trip(const PoseSet& poses, const GarmentFile& garment, const Eigen::MatrixXd& V_rest,
                           const Eigen::MatrixXi& F, const Pattern& pattern, const Layout& layout,
                           const RoundTripOptions& options, const Eigen::MatrixXd* V_start) {
  if (V_start && (V_start->rows() != V_rest.rows() || V_start->cols() != 3))
    throw GeometryError("round trip: the start positions do not match the rest shape");
  const Eigen::MatrixXd& X0 = V_start ? *V_start : V_rest;
  using Clock = std::chrono::steady_clock;
  RoundTripResult result;
  result.pose = garment.body.design_pose.empty() ? poses.reference : garment.body.design_pose;
  const int pose = poses.index_of(result.pose, "garment body.design_pose");
  // One still key pose: only the design pose is needed by the interpolator.
  PoseSet still;
  still.names = {result.pose};
  still.V = {poses.V[static_cast<size_t>(pose)]};
  still.F = poses.F;
  still.reference = result.pose;
  MotionSpec motion;
  motion.keys = {MotionKey{result.pose, 0, 0}};

  adapt::MotionRunOptions run_options;
  run_options.adapt = false;
  run_options.dt = options.dt;
  run_options.settle_max_steps = options.settle_max_steps;
  run_options.settle_speed = options.settle_speed;

  std::vector<cloth::TriangleRest> own(static_cast<size_t>(F.rows()));
  for (int f = 0; f < F.rows(); ++f) {
    Eigen::Matrix3d T;
    for (int k = 0; k < 3; ++k) T.col(k) = V_rest.row(F(f, k)).transpose();
    own[static_cast<size_t>(f)] = cloth::triangle_rest(T);
  }
  const std::vector<cloth::TriangleRest> sewn = sewn_rest_triangles(pattern, layout, static_cast<int>(F.rows()));

  auto drape = [&](const std::vector<cloth::TriangleRest>* triangles, DrapeRun& run) {
    PoseInterpolator interpolator(still);
    adapt::MotionRunOptions o = run_options;
    o.rest_triangles = triangles ? *triangles : own;
    const auto start = Clock::now();
    adapt::MotionRunResult r;
    try {
      r = adapt::run_garment_motion(interpolator, motion, X0, F, garment, o);
    } catch (const NumericalError& e) {
      throw NumericalError(std::string("round trip, drape with the ") +
                               (triangles ? "flat pieces' triangles" : "rest shape's own triangles") + ": " + e.what(),
                           e.where());
    }
    run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (r.keys.empty()) throw NumericalError("the round-trip drape returned no key pose");
    run.settle_steps = r.keys.front().settle_steps;
    run.settled = r.keys.front().settled;
    return r.keys.front().V_draped;
  };
  result.V_rest_drape = drape(nullptr, result.rest_run);
  result.V_sewn_drape = drape(&sewn, result.sewn_run);

  const Eigen::VectorXd d = (result.V_rest_drape - result.V_sewn_drape).rowwise().norm();
  result.max_distance = d.size() ? d.maxCoeff() : 0.0;
  result.mean_distance = d.size() ? d.mean() : 0.0;
  std::vector<double> sorted(d.data(), d.data() + d.size());
  std::sort(sorted.begin(), sorted.end());
  if (!sorted.empty())
    result.p95_distance = sorted[std::min(sorted.size() - 1, static_cast<size_t>(std::ceil(0.95 * sorted.size())) - 1)];
  result.rest_drape_stretch = stretch_figures(result.V_rest_drape, F, own);
  result.sewn_drape_stretch = stretch_figures(result.V_sewn_drape, F, sewn);
  return result;
}

}  // namespace gp
