#include "collision/triangle_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

#include <CGAL/Intersections_3/Ray_3_Triangle_3.h>
#include <CGAL/Simple_cartesian.h>
#include <Eigen/Geometry>
#include <embree3/rtcore.h>

#include "core/error.h"
#include "mesh/point_triangle.h"

namespace gp::collision {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Corners = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Embree works in single precision. Boxes are grown by this much relative to
// their coordinates (plus as much in metres), far more than the rounding of a
// box, a query point or a ray to floats, so that no box holding a candidate is
// culled; a query radius is grown by the same factor for the rounding of
// Embree's own distance arithmetic.
constexpr double kBoxGrowth = 1e-6;

float round_down(double x) { return std::nextafter(static_cast<float>(x), -std::numeric_limits<float>::infinity()); }
float round_up(double x) { return std::nextafter(static_cast<float>(x), std::numeric_limits<float>::infinity()); }

// A radius Embree may cull with that keeps every triangle within `distance`.
float culling_radius(double distance) {
  return std::isfinite(distance) ? round_up(distance * (1.0 + kBoxGrowth)) : std::numeric_limits<float>::infinity();
}

// One Embree device for the process, with one thread: builds and refits run
// on the caller's thread (simulate-adapt prepares frames on its own worker).
RTCDevice device() {
  static const struct Holder {
    RTCDevice handle = rtcNewDevice("threads=1,set_affinity=0,verbose=0");
    ~Holder() { rtcReleaseDevice(handle); }
  } holder;
  if (!holder.handle) throw Error(ExitCode::internal, "Embree device could not be created");
  return holder.handle;
}

void check_device(const char* what) {
  const RTCError e = rtcGetDeviceError(device());
  if (e != RTC_ERROR_NONE) throw Error(ExitCode::internal, std::string("Embree failed: ") + what, "error " + std::to_string(e));
}

}  // namespace

struct TriangleBvh::Impl {
  Corners corners;
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;
  bool built = false;

  Eigen::Vector3d corner(int i, int k) const {
    return Eigen::Vector3d(corners(i, 3 * k), corners(i, 3 * k + 1), corners(i, 3 * k + 2));
  }

  double squared_distance(const Eigen::Vector3d& p, int i) const {
    return (p - closest_point_on_triangle(p, corner(i, 0), corner(i, 1), corner(i, 2)).point).squaredNorm();
  }

  static void bounds(const RTCBoundsFunctionArguments* args) {
    const Impl& s = *static_cast<const Impl*>(args->geometryUserPtr);
    const auto row = s.corners.row(args->primID);
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min({row(d), row(3 + d), row(6 + d)});
      hi[d] = std::max({row(d), row(3 + d), row(6 + d)});
      const double grow = kBoxGrowth * (1.0 + std::max(std::abs(lo[d]), std::abs(hi[d])));
      lo[d] -= grow;
      hi[d] += grow;
    }
    RTCBounds& b = *args->bounds_o;
    b.lower_x = round_down(lo[0]);
    b.lower_y = round_down(lo[1]);
    b.lower_z = round_down(lo[2]);
    b.upper_x = round_up(hi[0]);
    b.upper_y = round_up(hi[1]);
    b.upper_z = round_up(hi[2]);
  }

  // A closest-point search: the best (squared distance, index) so far.
  struct Search {
    const Impl* bvh;
    Eigen::Vector3d p;
    int best;
    double best_d2;
  };

  static bool closest_callback(RTCPointQueryFunctionArguments* args) {
    Search& s = *static_cast<Search*>(args->userPtr);
    const int i = static_cast<int>(args->primID);
    const double d2 = s.bvh->squared_distance(s.p, i);
    if (!(d2 < s.best_d2 || (d2 == s.best_d2 && i < s.best))) return false;
    s.best = i;
    s.best_d2 = d2;
    const float r = culling_radius(std::sqrt(d2));
    if (!(r < args->query->radius)) return false;
    args->query->radius = r;
    return true;
  }

  // A ball search: every index within the radius.
  struct Ball {
    const Impl* bvh;
    Eigen::Vector3d p;
    double radius2;
    std::vector<int>* out;
  };

  static bool ball_callback(RTCPointQueryFunctionArguments* args) {
    Ball& b = *static_cast<Ball*>(args->userPtr);
    const int i = static_cast<int>(args->primID);
    if (b.bvh->squared_distance(b.p, i) <= b.radius2) b.out->push_back(i);
    return false;
  }

  // A ray search; Embree passes the context back to the intersect callback,
  // so the double-precision ray and the best hit ride on it.
  struct RayContext {
    RTCIntersectContext context;  // first: Embree's pointer to it is a pointer to this
    const Impl* bvh;
    Kernel::Ray_3 ray;
    int max_axis;  // the direction's largest component, CGAL's ray parameter
    int skip;
    int best;
    double best_t;
  };

  // CGAL's parameter of a point on the ray (AABB_tree's ray traversal):
  // the offset over the direction along its largest component.
  static double parameter(const RayContext& r, const Kernel::Point_3& x) {
    const int k = r.max_axis;
    return (x[k] - r.ray.source()[k]) / r.ray.to_vector()[k];
  }

  static void intersect_callback(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    RayContext& r = *reinterpret_cast<RayContext*>(args->context);
    const int i = static_cast<int>(args->primID);
    if (i == r.skip) return;
    const Eigen::Vector3d a = r.bvh->corner(i, 0), b = r.bvh->corner(i, 1), c = r.bvh->corner(i, 2);
    // Zero area: CGAL's inexact ray/triangle intersection takes it for a
    // coplanar case and may answer a point the ray does not pass through.
    if ((b - a).cross(c - a).isZero(0.0)) return;
    auto point = [&](const Eigen::Vector3d& x) { return Kernel::Point_3(x.x(), x.y(), x.z()); };
    const auto hit = CGAL::intersection(r.ray, Kernel::Triangle_3(point(a), point(b), point(c)));
    if (!hit) return;
    double t;
    if (const Kernel::Point_3* x = boost::get<Kernel::Point_3>(&*hit)) {
      t = parameter(r, *x);
    } else {
      const Kernel::Segment_3& s = boost::get<Kernel::Segment_3>(*hit);
      t = std::min(parameter(r, s.source()), parameter(r, s.target()));
    }
    if (!(t < r.best_t || (t == r.best_t && i < r.best))) return;
    r.best = i;
    r.best_t = t;
    RTCRayHit* rayhit = reinterpret_cast<RTCRayHit*>(args->rayhit);
    const float far = culling_radius(t);
    if (far < rayhit->ray.tfar) rayhit->ray.tfar = far;
    rayhit->hit.geomID = args->geomID;
    rayhit->hit.primID = args->primID;
  }

  static void occluded_callback(const RTCOccludedFunctionNArguments*) {}
};

TriangleBvh::TriangleBvh(int triangles) : impl_(std::make_unique<Impl>()) {
  if (triangles < 1) throw UsageError("a triangle hierarchy needs at least one triangle");
  Impl& s = *impl_;
  s.corners.setZero(triangles, 9);
  const RTCDevice dev = device();
  s.scene = rtcNewScene(dev);
  // A refit needs Embree's dynamic (low quality) builder: with the default
  // scene quality every commit rebuilds the tree from scratch (README: cost).
  rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_LOW);
  s.geometry = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(s.geometry, static_cast<unsigned>(triangles));
  rtcSetGeometryUserData(s.geometry, &s);
  rtcSetGeometryBoundsFunction(s.geometry, &Impl::bounds, nullptr);
  rtcSetGeometryIntersectFunction(s.geometry, &Impl::intersect_callback);
  rtcSetGeometryOccludedFunction(s.geometry, &Impl::occluded_callback);
  rtcSetGeometryBuildQuality(s.geometry, RTC_BUILD_QUALITY_REFIT);
  rtcAttachGeometry(s.scene, s.geometry);
  check_device("creating the scene");
}

TriangleBvh::~TriangleBvh() {
  if (impl_->geometry) rtcReleaseGeometry(impl_->geometry);
  if (impl_->scene) rtcReleaseScene(impl_->scene);
}

void TriangleBvh::set_corners(const Corners& corners) {
  Impl& s = *impl_;
  if (corners.rows() != s.corners.rows()) throw UsageError("triangle corners do not match the hierarchy");
  if (!corners.allFinite()) throw GeometryError("non-finite triangle corner");
  s.corners = corners;
  rtcCommitGeometry(s.geometry);
  rtcCommitScene(s.scene);
  check_device(s.built ? "refitting the hierarchy" : "building the hierarchy");
  s.built = true;
}

TriangleBvh::Closest TriangleBvh::closest(const Eigen::Vector3d& p, int hint) const {
  const Impl& s = *impl_;
  if (!s.built) throw UsageError("TriangleBvh::closest before set_corners");
  if (!p.allFinite()) throw NumericalError("closest-point query at a non-finite point");
  Impl::Search search{&s, p, -1, kInfinity};
  RTCPointQuery query;
  query.x = static_cast<float>(p.x());
  query.y = static_cast<float>(p.y());
  query.z = static_cast<float>(p.z());
  query.time = 0.0f;
  query.radius = std::numeric_limits<float>::infinity();
  if (hint >= 0 && hint < size()) {
    search.best = hint;
    search.best_d2 = s.squared_distance(p, hint);
    query.radius = culling_radius(std::sqrt(search.best_d2));
  }
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(s.scene, &query, &context, &Impl::closest_callback, &search);
  if (search.best < 0) throw Error(ExitCode::internal, "Embree's point query visited no triangle");
  return {search.best, search.best_d2};
}

TriangleBvh::Hit TriangleBvh::first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                        int skip) const {
  const Impl& s = *impl_;
  if (!s.built) throw UsageError("TriangleBvh::first_hit before set_corners");
  if (!origin.allFinite() || !direction.allFinite() || direction.isZero(0.0)) {
    throw NumericalError("ray with a non-finite origin or direction, or a zero direction");
  }
  Impl::RayContext r{{}, &s, Kernel::Ray_3(Kernel::Point_3(origin.x(), origin.y(), origin.z()),
                                           Kernel::Vector_3(direction.x(), direction.y(), direction.z())),
                     0, skip, -1, kInfinity};
  rtcInitIntersectContext(&r.context);
  for (int k = 1; k < 3; ++k) {
    if (std::abs(direction[k]) > std::abs(direction[r.max_axis])) r.max_axis = k;
  }
  RTCRayHit rayhit;
  rayhit.ray.org_x = static_cast<float>(origin.x());
  rayhit.ray.org_y = static_cast<float>(origin.y());
  rayhit.ray.org_z = static_cast<float>(origin.z());
  rayhit.ray.dir_x = static_cast<float>(direction.x());
  rayhit.ray.dir_y = static_cast<float>(direction.y());
  rayhit.ray.dir_z = static_cast<float>(direction.z());
  rayhit.ray.tnear = 0.0f;
  rayhit.ray.tfar = std::numeric_limits<float>::infinity();
  rayhit.ray.time = 0.0f;
  rayhit.ray.mask = 0xFFFFFFFFu;
  rayhit.ray.id = 0;
  rayhit.ray.flags = 0;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(s.scene, &r.context, &rayhit);
  if (r.best < 0) return {};
  return {r.best, r.best_t};
}

std::vector<int> TriangleBvh::within(const Eigen::Vector3d& p, double radius) const {
  const Impl& s = *impl_;
  if (!s.built) throw UsageError("TriangleBvh::within before set_corners");
  if (!p.allFinite() || !(radius >= 0.0)) throw NumericalError("ball query with a non-finite centre or radius");
  std::vector<int> out;
  Impl::Ball ball{&s, p, radius * radius, &out};
  RTCPointQuery query;
  query.x = static_cast<float>(p.x());
  query.y = static_cast<float>(p.y());
  query.z = static_cast<float>(p.z());
  query.time = 0.0f;
  query.radius = culling_radius(radius);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(s.scene, &query, &context, &Impl::ball_callback, &ball);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

int TriangleBvh::size() const { return static_cast<int>(impl_->corners.rows()); }

Eigen::Vector3d TriangleBvh::corner(int i, int k) const { return impl_->corners.row(i).segment<3>(3 * k).transpose(); }

}  // namespace gp::collision
