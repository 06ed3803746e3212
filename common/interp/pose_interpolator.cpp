#include "interp/pose_interpolator.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/math.h"
#include "interp/deformation_gradient.h"
#include "interp/polar_decomposition.h"
#include "interp/rotation_log.h"

namespace gp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// exp([w]_x) v by Rodrigues' formula, without forming the matrix.
inline Eigen::Vector3d rotate(const Eigen::Vector3d& w, double theta, double c, double s,
                              const Eigen::Vector3d& v) {
  if (theta < 1e-12) return v + w.cross(v);
  const Eigen::Vector3d k = w / theta;
  return c * v + s * k.cross(v) + ((1.0 - c) * k.dot(v)) * k;
}

}  // namespace

const char* to_string(InterpolationMethod method) {
  return method == InterpolationMethod::linear ? "linear" : "nonlinear";
}

InterpolationMethod parse_interpolation_method(const std::string& name) {
  if (name == "nonlinear") return InterpolationMethod::nonlinear;
  if (name == "linear") return InterpolationMethod::linear;
  throw UsageError("unknown interpolation method '" + name + "' (nonlinear or linear)");
}

PoseInterpolator::PoseInterpolator(const PoseSet& poses, const InterpolationOptions& options)
    : options_(options), names_(poses.names), V_(poses.V), F_(poses.F) {
  if (V_.empty()) throw GeometryError("pose set is empty");
  if (names_.size() != V_.size()) names_.resize(V_.size());
  for (size_t i = 0; i < names_.size(); ++i)
    if (names_[i].empty()) names_[i] = "pose" + std::to_string(i);
  const Eigen::Index nv = V_[0].rows();
  if (nv == 0 || F_.rows() == 0) throw GeometryError("pose set has no vertices or no triangles");
  if (F_.cols() != 3) throw GeometryError("faces must be triangles");
  if (F_.minCoeff() < 0 || F_.maxCoeff() >= nv)
    throw GeometryError("face index out of range (" + std::to_string(nv) + " vertices)");
  for (size_t i = 0; i < V_.size(); ++i) {
    if (V_[i].rows() != nv || V_[i].cols() != 3)
      throw GeometryError("poses not in correspondence: pose has " + std::to_string(V_[i].rows()) +
                              " vertices, the first has " + std::to_string(nv),
                          "pose '" + names_[i] + "'");
    for (Eigen::Index v = 0; v < nv; ++v)
      if (!V_[i].row(v).allFinite())
        throw GeometryError("non-finite vertex coordinate",
                            "pose '" + names_[i] + "', vertex " + std::to_string(v));
  }
  reference_ = 0;
  for (size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == poses.reference) reference_ = static_cast<int>(i);

  // Anchor vertices.
  if (!options_.anchor.vertex_ids.empty()) {
    for (int id : options_.anchor.vertex_ids)
      if (id < 0 || id >= nv)
        throw SpecError("anchor vertex id " + std::to_string(id) + " out of range [0, " +
                        std::to_string(nv) + ")");
    anchor_ids_ = options_.anchor.vertex_ids;
  } else {
    const double fraction = options_.anchor.fraction;
    if (!(fraction > 0.0 && fraction <= 1.0))
      throw SpecError("anchor fraction must lie in (0, 1], got " + std::to_string(fraction));
    const Eigen::MatrixXd& V_ref = V_[static_cast<size_t>(reference_)];
    const Eigen::RowVector3d centroid = V_ref.colwise().mean();
    const Eigen::VectorXd dist = (V_ref.rowwise() - centroid).rowwise().squaredNorm();
    std::vector<int> ids(static_cast<size_t>(nv));
    std::iota(ids.begin(), ids.end(), 0);
    const auto count = static_cast<size_t>(
        std::max<double>(1.0, std::ceil(fraction * static_cast<double>(nv))));
    std::stable_sort(ids.begin(), ids.end(), [&](int x, int y) { return dist(x) < dist(y); });
    anchor_ids_.assign(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(std::min(count, ids.size())));
  }
  std::sort(anchor_ids_.begin(), anchor_ids_.end());
  anchor_ids_.erase(std::unique(anchor_ids_.begin(), anchor_ids_.end()), anchor_ids_.end());

  if (options_.method == InterpolationMethod::nonlinear) {
    poisson_ = std::make_unique<GradientPoissonSolver>(V_[static_cast<size_t>(reference_)], F_,
                                                       options_.solver);
    const Eigen::VectorXi& comp = poisson_->vertex_component();
    component_anchor_ids_.assign(static_cast<size_t>(poisson_->component_count()), {});
    for (int id : anchor_ids_)
      if (comp(id) >= 0) component_anchor_ids_[static_cast<size_t>(comp(id))].push_back(id);
    // A component without anchor vertices (a separate button, an eye) follows
    // its own centroid.
    std::vector<std::vector<int>> members(component_anchor_ids_.size());
    for (int v = 0; v < nv; ++v)
      if (comp(v) >= 0) members[static_cast<size_t>(comp(v))].push_back(v);
    for (size_t c = 0; c < members.size(); ++c)
      if (component_anchor_ids_[c].empty()) component_anchor_ids_[c] = members[c];
  }
}

double PoseInterpolator::factorization_seconds() const {
  return poisson_ ? poisson_->factorization_seconds() : 0.0;
}

void PoseInterpolator::prepare(int a, int b) { transition(a, b); }

const TransitionInfo& PoseInterpolator::transition_info(int a, int b) { return transition(a, b).info; }

const PoseInterpolator::Transition& PoseInterpolator::transition(int a, int b) {
  check_frame_args(a, b, 0.0);
  const auto key = std::make_pair(a, b);
  auto it = transitions_.find(key);
  if (it != transitions_.end()) return it->second;

  const auto start = std::chrono::steady_clock::now();
  Transition tr;
  const Eigen::MatrixXd& V_a = V_[static_cast<size_t>(a)];
  const Eigen::MatrixXd& V_b = V_[static_cast<size_t>(b)];
  tr.E_a = face_edges(V_a, F_);
  if (options_.method == InterpolationMethod::nonlinear) {
    std::vector<Eigen::Matrix3d> Q, R;
    std::vector<bool> valid;
    deformation_gradients(V_a, V_b, F_, Q, valid);
    const int nf = static_cast<int>(F_.rows());
    R.resize(static_cast<size_t>(nf));
    Eigen::Matrix3d S;
    for (int f = 0; f < nf; ++f) {
      polar_decomposition(Q[static_cast<size_t>(f)], R[static_cast<size_t>(f)], S);
      if (!valid[static_cast<size_t>(f)]) ++tr.info.degenerate_faces;
    }
    tr.omega = consistent_rotation_logs(R, valid, F_);
    // U_b = exp(omega)^T E_b, with the rotation rebuilt from the chosen log, so
    // that t = 1 gives E_b up to round-off for every face, degenerate or not.
    const FaceEdges E_b = face_edges(V_b, F_);
    tr.U_b.resize(nf, 6);
    for (int f = 0; f < nf; ++f) {
      const Eigen::Vector3d w = tr.omega.row(f).transpose();
      const Eigen::Matrix3d Rt = rotation_exp(w).transpose();
      tr.U_b.block<1, 3>(f, 0) = (Rt * E_b.block<1, 3>(f, 0).transpose()).transpose();
      tr.U_b.block<1, 3>(f, 3) = (Rt * E_b.block<1, 3>(f, 3).transpose()).transpose();
      const double angle = w.norm();
      tr.info.max_rotation_deg = std::max(tr.info.max_rotation_deg, angle * 180.0 / kPi);
      if (angle > kPi + 1e-12) ++tr.info.faces_off_principal_branch;
    }
  }
  tr.info.prepare_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return transitions_.emplace(key, std::move(tr)).first->second;
}

void PoseInterpolator::check_frame_args(int a, int b, double t) const {
  const int n = pose_count();
  if (a < 0 || a >= n || b < 0 || b >= n)
    throw UsageError("pose index out of range: (" + std::to_string(a) + ", " + std::to_string(b) +
                     ") for " + std::to_string(n) + " poses");
  if (!(t >= 0.0 && t <= 1.0))
    throw UsageError("interpolation parameter t must lie in [0, 1], got " + std::to_string(t));
}

Eigen::MatrixXd PoseInterpolator::frame(int a, int b, double t) {
  Eigen::MatrixXd V;
  frame(a, b, t, V);
  return V;
}

void PoseInterpolator::frame(int a, int b, double t, Eigen::MatrixXd& V_out) {
  check_frame_args(a, b, t);
  const Eigen::MatrixXd& V_a = V_[static_cast<size_t>(a)];
  const Eigen::MatrixXd& V_b = V_[static_cast<size_t>(b)];
  if (options_.method == InterpolationMethod::linear) {
    V_out = (1.0 - t) * V_a + t * V_b;
    return;
  }
  const Transition& tr = transition(a, b);
  const int nf = static_cast<int>(F_.rows());
  target_.resize(nf, 6);
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d w = t * tr.omega.row(f).transpose();
    const double theta = w.norm();
    const double c = gp::math::cos(theta), s = gp::math::sin(theta);
    // Q(t) E_a = exp(t omega) ((1 - t) E_a + t S E_a), S E_a = U_b.
    const Eigen::Vector3d u1 =
        (1.0 - t) * tr.E_a.block<1, 3>(f, 0).transpose() + t * tr.U_b.block<1, 3>(f, 0).transpose();
    const Eigen::Vector3d u2 =
        (1.0 - t) * tr.E_a.block<1, 3>(f, 3).transpose() + t * tr.U_b.block<1, 3>(f, 3).transpose();
    target_.block<1, 3>(f, 0) = rotate(w, theta, c, s, u1).transpose();
    target_.block<1, 3>(f, 3) = rotate(w, theta, c, s, u2).transpose();
  }
  poisson_->solve(target_, V_out);

  // Translation: each component's anchor centroid follows the straight line
  // between its positions in the key poses.
  const Eigen::VectorXi& comp = poisson_->vertex_component();
  std::vector<Eigen::RowVector3d> shift(component_anchor_ids_.size());
  for (size_t c = 0; c < component_anchor_ids_.size(); ++c) {
    Eigen::RowVector3d now = Eigen::RowVector3d::Zero(), goal = Eigen::RowVector3d::Zero();
    for (int id : component_anchor_ids_[c]) {
      now += V_out.row(id);
      goal += (1.0 - t) * V_a.row(id) + t * V_b.row(id);
    }
    shift[c] = (goal - now) / static_cast<double>(component_anchor_ids_[c].size());
  }
  for (Eigen::Index v = 0; v < V_out.rows(); ++v) {
    if (comp(v) >= 0)
      V_out.row(v) += shift[static_cast<size_t>(comp(v))];
    else
      V_out.row(v) = (1.0 - t) * V_a.row(v) + t * V_b.row(v);  // in no triangle: nothing to keep
  }
  if (!V_out.allFinite()) throw NumericalError("interpolated frame is not finite");
}

}  // namespace gp
