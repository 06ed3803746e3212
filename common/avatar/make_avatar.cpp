#include "avatar/make_avatar.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "avatar/body_checks.h"
#include "avatar/flips.h"
#include "avatar/girth.h"
#include "avatar/isosurface.h"
#include "avatar/simplify.h"
#include "avatar/skinning.h"
#include "core/error.h"
#include "core/math.h"
#include "core/stopwatch.h"
#include "geometry/self_intersections.h"
#include "mesh/measures.h"
#include "mesh/topology.h"

namespace gp {
namespace {

// Moves every vertex onto the zero set along the field gradient (Newton
// steps, gradient by central differences). Steps are capped at `max_step`, so
// that a vertex never jumps to another part of the body.
void project_to_surface(const BodyShape& shape, Eigen::MatrixXd& V, double max_step) {
  const double eps = 1e-5 * shape.scale;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    Eigen::Vector3d p = V.row(v).transpose();
    for (int it = 0; it < 3; ++it) {
      const double f = body_field(shape, p);
      Eigen::Vector3d g;
      for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e(a) = eps;
        g(a) = (body_field(shape, p + e) - body_field(shape, p - e)) / (2 * eps);
      }
      const double g2 = g.squaredNorm();
      if (g2 < 1e-12) break;
      Eigen::Vector3d step = -f / g2 * g;
      const double len = step.norm();
      if (len > max_step) step *= max_step / len;
      p += step;
      if (len < 1e-7) break;
    }
    V.row(v) = p.transpose();
  }
}

// Tangential smoothing (each vertex moves half-way to its neighbours'
// centroid within its tangent plane) followed by projection onto the implicit
// surface: evens out the decimated triangles without changing the shape.
void relax(const BodyShape& shape, Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int iterations,
           double max_step) {
  const auto nb = vertex_neighbors(F, static_cast<int>(V.rows()));
  for (int it = 0; it < iterations; ++it) {
    const Eigen::MatrixXd N = vertex_normals(V, F);
    Eigen::MatrixXd U = V;
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      if (nb[v].empty()) continue;
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int u : nb[v]) c += V.row(u).transpose();
      c /= static_cast<double>(nb[v].size());
      const Eigen::Vector3d n = N.row(v).transpose();
      Eigen::Vector3d d = c - V.row(v).transpose();
      d -= d.dot(n) * n;
      U.row(v) += 0.5 * d.transpose();
    }
    V.swap(U);
    project_to_surface(shape, V, max_step);
  }
}

// Local folds left by decimation in tight places (back of the knee,
// armpit) are removed by smoothing the two-ring around every intersecting
// triangle until CGAL finds no intersection. Returns the rounds used.
int untangle(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int max_rounds) {
  const auto nb = vertex_neighbors(F, static_cast<int>(V.rows()));
  for (int round = 0; round < max_rounds; ++round) {
    const std::vector<int> faces = self_intersecting_faces(V, F);
    if (faces.empty()) return round;
    std::vector<char> mark(V.rows(), 0);
    for (int f : faces)
      for (int k = 0; k < 3; ++k) mark[F(f, k)] = 1;
    for (int ring = 0; ring < 2 + round; ++ring) {
      std::vector<char> next = mark;
      for (Eigen::Index v = 0; v < V.rows(); ++v)
        if (mark[v])
          for (int u : nb[v]) next[u] = 1;
      mark.swap(next);
    }
    for (int it = 0; it < 3; ++it) {
      Eigen::MatrixXd U = V;
      for (Eigen::Index v = 0; v < V.rows(); ++v) {
        if (!mark[v] || nb[v].empty()) continue;
        Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
        for (int u : nb[v]) c += V.row(u);
        U.row(v) = 0.5 * V.row(v) + 0.5 * c / static_cast<double>(nb[v].size());
      }
      V.swap(U);
    }
  }
  if (!self_intersecting_faces(V, F).empty())
    throw GeometryError("the generated rest pose intersects itself; try another resolution");
  return max_rounds;
}

// Skinning shears a few triangles in extreme poses (front of the shoulder
// with the arms forward) into needles. Their vertices are moved half-way to
// their neighbours' centroid, which restores the angles and changes the
// pose by well under a millimetre elsewhere. Returns the vertices moved.
int smooth_needles(Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<std::vector<int>>& nb,
                   double min_angle_degrees) {
  const double limit = min_angle_degrees * M_PI / 180.0;
  int moved = 0;
  for (int pass = 0; pass < 6; ++pass) {
    std::vector<char> mark(V.rows(), 0);
    bool any = false;
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d a = V.row(F(f, k)).transpose();
        const Eigen::Vector3d u = V.row(F(f, (k + 1) % 3)).transpose() - a;
        const Eigen::Vector3d w = V.row(F(f, (k + 2) % 3)).transpose() - a;
        if (gp::math::atan2(u.cross(w).norm(), u.dot(w)) < limit) {
          for (int m = 0; m < 3; ++m) mark[F(f, m)] = 1;
          any = true;
        }
      }
    }
    if (!any) break;
    const Eigen::MatrixXd U = V;
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      if (!mark[v] || nb[v].empty()) continue;
      Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
      for (int u : nb[v]) c += U.row(u);
      V.row(v) = 0.5 * U.row(v) + 0.5 * c / static_cast<double>(nb[v].size());
      ++moved;
    }
  }
  return moved;
}

std::vector<std::string> resolve_poses(const AvatarSpec& spec, const AvatarOptions& o) {
  std::set<std::string> spec_names;
  for (const JointAnglePose& p : spec.poses) {
    if (is_builtin_pose(p.name))
      throw SpecError("pose '" + p.name + "' is a built-in pose name; choose another", "poses");
    if (!spec_names.insert(p.name).second) throw SpecError("duplicate pose '" + p.name + "'", "poses");
  }
  std::vector<std::string> names = o.poses;
  if (names.empty()) {
    names = builtin_pose_names();
    for (const JointAnglePose& p : spec.poses) names.push_back(p.name);
  }
  std::set<std::string> seen;
  for (const std::string& n : names) {
    if (!is_builtin_pose(n) && !spec_names.count(n)) {
      std::string known;
      for (const std::string& b : builtin_pose_names()) known += (known.empty() ? "" : ", ") + b;
      for (const std::string& b : spec_names) known += ", " + b;
      throw SpecError("unknown pose '" + n + "' (known: " + known + ")", "poses");
    }
    if (!seen.insert(n).second) throw SpecError("pose '" + n + "' listed twice", "poses");
  }
  // The rest pose is the reference and comes first.
  names.erase(std::remove(names.begin(), names.end(), std::string("apose")), names.end());
  names.insert(names.begin(), "apose");
  return names;
}

JointRotations pose_rotations(const AvatarSpec& spec, const Skeleton& sk, const std::string& name) {
  if (is_builtin_pose(name)) return builtin_pose(sk, name);
  for (const JointAnglePose& p : spec.poses) {
    if (p.name != name) continue;
    JointRotations r(kJointCount, Eigen::Quaterniond::Identity());
    for (const auto& [joint, angles] : p.joints) {
      const int j = avatar_joint_index(joint);
      if (j < 0) throw SpecError("unknown joint '" + joint + "'", "poses/" + name);
      r[j] = rotation_from_degrees(angles);
    }
    return r;
  }
  throw SpecError("unknown pose '" + name + "'", "poses");
}

std::vector<GirthResult> measure_girths(const BodyShape& shape, const Eigen::MatrixXd& V,
                                        const Eigen::MatrixXi& F) {
  std::vector<GirthResult> out;
  for (const GirthLandmark& g : shape.landmarks) {
    GirthResult r;
    r.name = g.name;
    r.field = g.field;
    r.target = g.target;
    r.center = g.center;
    r.normal = g.normal;
    r.measured = mesh_girth(V, F, g.center, g.normal, &r.loop);
    if (r.measured < 0) throw GeometryError("no cross-section loop around girth landmark '" + g.name + "'");
    out.push_back(r);
  }
  return out;
}

// Marching tetrahedra may leave specks where a thin part (finger tips) is
// thinner than the grid; they are dropped if they are tiny, otherwise the
// construction failed.
int drop_specks(Mesh& mesh) {
  Eigen::VectorXi comp;
  const int n = face_components(mesh.F, comp);
  if (n <= 1) return 0;
  std::vector<int> count(n, 0);
  for (Eigen::Index f = 0; f < comp.size(); ++f) ++count[comp(f)];
  const int keep = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
  if (count[keep] < 0.99 * mesh.F.rows())
    throw GeometryError("isosurface of the body falls apart into " + std::to_string(n) + " pieces");
  std::vector<int> remap(mesh.V.rows(), -1);
  Eigen::MatrixXi F(count[keep], 3);
  int k = 0, nv = 0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (comp(f) != keep) continue;
    for (int c = 0; c < 3; ++c) {
      int& r = remap[mesh.F(f, c)];
      if (r < 0) r = nv++;
      F(k, c) = r;
    }
    ++k;
  }
  Eigen::MatrixXd V(nv, 3);
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
    if (remap[v] >= 0) V.row(remap[v]) = mesh.V.row(v);
  mesh.V = V;
  mesh.F = F;
  return n - 1;
}

// Direct girth correction on the mesh: around each landmark, vertices are
// scaled within the landmark plane about its centre by target / measured,
// blended by their skinning weight on the landmark's part and by a smooth
// profile along the plane normal, so the body stays smooth. Torso girths
// share one piecewise-linear profile over the height.
void correct_girths(const BodyShape& shape, const std::vector<GirthResult>& girths, const Eigen::MatrixXd& W,
                    Eigen::MatrixXd& V) {
  const double k = shape.scale;
  std::vector<std::pair<double, double>> torso;  // (height, factor), ascending
  for (const GirthResult& g : girths)
    if (g.field == "chest" || g.field == "under_bust" || g.field == "waist" || g.field == "hip")
      torso.emplace_back(g.center.y(), g.target / g.measured);
  std::sort(torso.begin(), torso.end());
  const double fade = 0.08 * k;
  torso.insert(torso.begin(), {torso.front().first - fade, 1.0});
  torso.emplace_back(torso.back().first + fade, 1.0);
  auto torso_factor = [&](double y) {
    if (y <= torso.front().first || y >= torso.back().first) return 1.0;
    size_t i = 0;
    while (torso[i + 1].first < y) ++i;
    const double t = (y - torso[i].first) / (torso[i + 1].first - torso[i].first);
    return torso[i].second + t * (torso[i + 1].second - torso[i].second);
  };
  auto hat = [](double t, double w) {
    const double u = std::abs(t) / w;
    return u >= 1 ? 0.0 : 0.5 * (1 + gp::math::cos(M_PI * u));
  };
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    Eigen::Vector3d p = V.row(v).transpose();
    const double m_torso = W(v, kPelvis) + W(v, kSpine) + W(v, kChest);
    const double ft = torso_factor(p.y());
    if (ft != 1.0) {
      const double f = 1.0 + m_torso * (ft - 1.0);
      p.x() *= f;
      p.z() *= f;
    }
    for (const GirthResult& g : girths) {
      double member = 0.0, width = 0.0;
      const bool left = g.name.find("left") != std::string::npos;
      if (g.field == "neck") {
        member = W(v, kNeck) + W(v, kHead) + W(v, kChest);
        width = 0.04 * k;
      } else if (g.field == "upper_arm") {
        member = left ? W(v, kLShoulder) : W(v, kRShoulder);
        width = 0.08 * k;
      } else if (g.field == "wrist") {
        member = left ? W(v, kLElbow) + W(v, kLWrist) : W(v, kRElbow) + W(v, kRWrist);
        width = 0.04 * k;
      } else if (g.field == "thigh") {
        member = left ? W(v, kLHip) : W(v, kRHip);
        width = 0.06 * k;
      } else {
        continue;
      }
      const Eigen::Vector3d n = g.normal.normalized();
      const Eigen::Vector3d r = p - g.center;
      const double along = r.dot(n);
      const double f = 1.0 + member * hat(along, width) * (g.target / g.measured - 1.0);
      if (f == 1.0) continue;
      p += (f - 1.0) * (r - along * n);
    }
    V.row(v) = p.transpose();
  }
}

OrderedJson vec_json(const Eigen::Vector3d& v) { return OrderedJson::array({v.x(), v.y(), v.z()}); }

}  // namespace

AvatarResult make_avatar(const AvatarSpec& spec, const AvatarOptions& o) {
  const auto t_start = Clock::now();
  validate_measurements(spec.measurements, "measurements");
  if (o.target_vertices < 500 || o.target_vertices > 2000000)
    throw SpecError("vertex budget " + std::to_string(o.target_vertices) + " outside 500 to 2000000",
                    "target_vertices");
  const std::vector<std::string> pose_names = resolve_poses(spec, o);

  AvatarResult res;
  res.measurements = spec.measurements;
  auto t = Clock::now();
  BodyShape shape = build_body_shape(spec.measurements);
  fit_girths(shape);
  res.timing.fit += seconds_since(t);

  // The grid resolves the thinnest parts (finger tips, wrists); decimation
  // then meets the budget. Small budgets start from a coarser grid (faster,
  // and less to decimate), large ones from a finer one.
  double cell_used = o.cell * shape.scale;
  if (o.target_vertices <= kAvatarDefaultVertices / 3) cell_used *= 1.4;
  if (o.target_vertices > 2 * kAvatarDefaultVertices)
    cell_used *= std::sqrt(2.0 * kAvatarDefaultVertices / o.target_vertices);
  t = Clock::now();
  IsosurfaceOptions io;
  io.cell = cell_used;
  Mesh iso = marching_tetrahedra([&](const Eigen::Vector3d& p) { return body_field(shape, p); },
                                 shape.box_min, shape.box_max, io);
  // Marching tetrahedra gives a closed oriented manifold by construction;
  // only specks need removing (the decimated mesh is checked below).
  res.specks_removed = drop_specks(iso);
  res.isosurface_vertices = iso.V.rows();
  res.timing.polygonize += seconds_since(t);
  t = Clock::now();
  Mesh mesh = simplify_mesh(iso, o.target_vertices);
  res.timing.simplify += seconds_since(t);
  t = Clock::now();
  project_to_surface(shape, mesh.V, 0.5 * cell_used);
  res.flips = flip_for_angles(mesh.V, mesh.F);
  relax(shape, mesh.V, mesh.F, o.relax_iterations, 0.5 * cell_used);
  res.flips += flip_for_angles(mesh.V, mesh.F);
  res.timing.project += seconds_since(t);
  t = Clock::now();
  check_closed_genus0(mesh.F, "decimated body");
  res.timing.check += seconds_since(t);

  t = Clock::now();
  res.weights = skinning_weights(shape, mesh.V, mesh.F, o.skinning);
  res.timing.skin += seconds_since(t);

  // Correct the girths, then remove any local fold; smoothing a fold away can
  // move a girth again, so repeat while folds were found.
  for (int pass = 0; pass < 3; ++pass) {
    t = Clock::now();
    for (int it = 0; it < o.girth_correction_iterations; ++it) {
      res.girths = measure_girths(shape, mesh.V, mesh.F);
      double worst = 0.0;
      for (const GirthResult& g : res.girths) worst = std::max(worst, std::abs(g.measured - g.target));
      if (worst < 1e-4) break;
      correct_girths(shape, res.girths, res.weights, mesh.V);
      ++res.correction_rounds;
    }
    res.timing.measure += seconds_since(t);
    if (!o.check_self_intersection) break;
    t = Clock::now();
    const int rounds = untangle(mesh.V, mesh.F, 8);
    res.untangle_rounds += rounds;
    res.timing.check += seconds_since(t);
    if (rounds == 0) break;
  }
  res.girths = measure_girths(shape, mesh.V, mesh.F);

  t = Clock::now();
  const double floor_rest = mesh.V.col(1).minCoeff();
  res.skeleton = shape.skeleton;
  res.skeleton.rest.col(1).array() -= floor_rest;
  res.poses.F = mesh.F;
  res.poses.reference = "apose";
  const auto neighbours = vertex_neighbors(mesh.F, static_cast<int>(mesh.V.rows()));
  // Skins the rest mesh into a pose; returns the needle vertices smoothed.
  auto skin = [&](const std::vector<RigidTransform>& bones, Eigen::MatrixXd& V) {
    V = dual_quaternion_skinning(mesh.V, res.weights, bones);
    Eigen::MatrixXd smoothed = V;
    const int moved = smooth_needles(smoothed, mesh.F, neighbours, o.posed_min_angle);
    // Keep the smoothing unless it makes the pose intersect itself (a
    // needle in a tight fold); a needle is the lesser defect.
    if (moved > 0 && (!o.check_self_intersection || !has_self_intersection(smoothed, mesh.F) ||
                      has_self_intersection(V, mesh.F))) {
      V = smoothed;
      return moved;
    }
    return 0;
  };
  for (const std::string& name : pose_names) {
    JointRotations rot = pose_rotations(spec, shape.skeleton, name);
    std::vector<RigidTransform> bones = forward_kinematics(shape.skeleton, rot);
    Eigen::MatrixXd V = mesh.V;
    if (name != "apose") res.needle_vertices_smoothed += skin(bones, V);
    // The hands rest beside the thighs, not in them: on wider hips the elbows
    // bend less (skeleton.h: hands_on_thighs_pose).
    for (double bend = kHandsOnThighsBend - 2.5;
         name == "handsonthighs" && o.check_self_intersection && bend >= 20.0 && has_self_intersection(V, mesh.F);
         bend -= 2.5) {
      rot = hands_on_thighs_pose(shape.skeleton, bend);
      bones = forward_kinematics(shape.skeleton, rot);
      res.needle_vertices_smoothed += skin(bones, V);
    }
    Eigen::MatrixXd J = posed_joints(shape.skeleton, bones);
    const double floor = V.col(1).minCoeff();
    V.col(1).array() -= floor;
    J.col(1).array() -= floor;
    res.poses.names.push_back(name);
    res.poses.V.push_back(V);
    res.joints.push_back(J);
    res.rotations.push_back(rot);
    res.volumes.push_back(signed_volume(V, mesh.F));
  }
  for (GirthResult& g : res.girths) g.center.y() -= floor_rest;
  res.height = res.poses.V[0].col(1).maxCoeff();
  res.timing.pose += seconds_since(t);
  res.timing.total = seconds_since(t_start);
  return res;
}

OrderedJson avatar_report(const AvatarSpec& spec, const AvatarOptions& o, const AvatarResult& r) {
  OrderedJson j;
  j["schema"] = schema_tag("make-avatar-report", 1);
  j["name"] = spec.name;
  OrderedJson opt = write_options(o, AvatarOptionFields{});
  opt["poses"] = r.poses.names;
  j["options"] = opt;
  j["measurements"] = to_json(r.measurements);
  OrderedJson mesh;
  mesh["vertex_count"] = r.poses.V.empty() ? 0 : r.poses.V[0].rows();
  mesh["face_count"] = r.poses.F.rows();
  mesh["isosurface_vertex_count"] = r.isosurface_vertices;
  mesh["correction_rounds"] = r.correction_rounds;
  mesh["isosurface_specks_removed"] = r.specks_removed;
  mesh["untangle_rounds"] = r.untangle_rounds;
  mesh["edge_flips"] = r.flips;
  mesh["posed_needle_vertices_smoothed"] = r.needle_vertices_smoothed;
  double min_angle = 180.0;
  if (!r.poses.V.empty())
    for (Eigen::Index f = 0; f < r.poses.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d a = r.poses.V[0].row(r.poses.F(f, k)).transpose();
        const Eigen::Vector3d u = r.poses.V[0].row(r.poses.F(f, (k + 1) % 3)).transpose() - a;
        const Eigen::Vector3d v = r.poses.V[0].row(r.poses.F(f, (k + 2) % 3)).transpose() - a;
        min_angle = std::min(min_angle, gp::math::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI);
      }
  mesh["min_angle_degrees"] = min_angle;
  mesh["height_m"] = r.height;
  mesh["topology_sha256"] = topology_checksum(r.poses.F);
  j["mesh"] = mesh;
  j["girth_method"] =
      "perimeter of the convex hull of the mesh's cross-section loop around the landmark, as a tape "
      "measure takes it; horizontal planes for neck, chest, under_bust, waist, hip and thigh, planes "
      "perpendicular to the arm for upper_arm and wrist (rest pose)";
  OrderedJson girths = OrderedJson::array();
  double worst = 0.0;
  for (const GirthResult& g : r.girths) {
    OrderedJson e;
    e["name"] = g.name;
    e["measurement"] = g.field;
    e["target_m"] = g.target;
    e["measured_m"] = g.measured;
    e["error_m"] = g.measured - g.target;
    e["loop_length_m"] = g.loop;
    e["plane_point_m"] = vec_json(g.center);
    e["plane_normal"] = vec_json(g.normal);
    girths.push_back(e);
    worst = std::max(worst, std::abs(g.measured - g.target));
  }
  j["girths"] = girths;
  j["max_girth_error_m"] = worst;
  OrderedJson poses = OrderedJson::array();
  const double v_ref = r.volumes.empty() ? 0.0 : r.volumes[0];
  double vmin = 1e300, vmax = -1e300;
  for (size_t i = 0; i < r.poses.names.size(); ++i) {
    OrderedJson e;
    e["name"] = r.poses.names[i];
    e["file"] = r.poses.names[i] + ".ply";
    e["volume_m3"] = r.volumes[i];
    e["volume_change_vs_reference"] = r.volumes[i] / v_ref - 1.0;
    poses.push_back(e);
    vmin = std::min(vmin, r.volumes[i]);
    vmax = std::max(vmax, r.volumes[i]);
  }
  j["poses"] = poses;
  j["max_pairwise_volume_change"] = vmax / vmin - 1.0;
  return j;
}

OrderedJson skeleton_json(const AvatarResult& r) {
  OrderedJson j;
  j["schema"] = schema_tag("skeleton", 1);
  j["units"] = "m";
  j["up"] = "+y";
  j["rotation_convention"] =
      "local rotations about each joint's rest position in the rest pose's axes, composed from the root; "
      "quaternions as [w, x, y, z]";
  OrderedJson joints = OrderedJson::array();
  for (size_t i = 0; i < r.skeleton.names.size(); ++i) {
    OrderedJson e;
    e["name"] = r.skeleton.names[i];
    const int p = r.skeleton.parents[i];
    e["parent"] = p < 0 ? OrderedJson(nullptr) : OrderedJson(r.skeleton.names[p]);
    joints.push_back(e);
  }
  j["joints"] = joints;
  OrderedJson poses = OrderedJson::array();
  for (size_t k = 0; k < r.poses.names.size(); ++k) {
    OrderedJson e;
    e["name"] = r.poses.names[k];
    OrderedJson pos = OrderedJson::array(), rot = OrderedJson::array();
    for (Eigen::Index i = 0; i < r.joints[k].rows(); ++i) {
      pos.push_back(vec_json(r.joints[k].row(i).transpose()));
      const Eigen::Quaterniond& q = r.rotations[k][i];
      rot.push_back(OrderedJson::array({q.w(), q.x(), q.y(), q.z()}));
    }
    e["positions"] = pos;
    e["rotations"] = rot;
    poses.push_back(e);
  }
  j["poses"] = poses;
  return j;
}

}  // namespace gp
