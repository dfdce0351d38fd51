// Scene geometry handed to Embree (embree_geometry.hpp).
#include "embree_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "trainsim/core/error.hpp"

namespace trainsim::lidar::detail {
namespace {

// Gives `g` the mesh's vertices v, placed at offset + level · (linear · v) (summed in double).
void setVertices(RTCGeometry g, const scene::Mesh& mesh, const Eigen::Vector3d& offset,
                 const Eigen::Matrix3f& linear, const Eigen::Matrix3d& level) {
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
  const bool identity = linear.isIdentity(0.0f), level_identity = level.isIdentity(0.0);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3d q =
        (identity ? mesh.vertices[i] : Eigen::Vector3f(linear * mesh.vertices[i])).cast<double>();
    const Eigen::Vector3d p = offset + (level_identity ? q : Eigen::Vector3d(level * q));
    v[3 * i] = static_cast<float>(p.x());
    v[3 * i + 1] = static_cast<float>(p.y());
    v[3 * i + 2] = static_cast<float>(p.z());
  }
}

// A wire's segments as exact capsules (a cylinder of the wire's radius between two points,
// spheres at the ends), intersected in double by a user geometry: Embree's round linear curve
// approximates the cylinder and is off by millimetres across a 6 mm wire at a grazing angle,
// which is the wire's whole size (sensors-reference.md 5; the footprint test needs it exact).
void wireBounds(const RTCBoundsFunctionArguments* args) {
  const auto& w = *static_cast<const WireData*>(args->geometryUserPtr);
  const Eigen::Vector3d& a = w.points[args->primID];
  const Eigen::Vector3d& b = w.points[args->primID + 1];
  // Widened by a float's rounding so the box holds the double capsule.
  const double pad = w.radius + 1e-6 * (1.0 + a.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff());
  const Eigen::Vector3d lo = a.cwiseMin(b).array() - pad, hi = a.cwiseMax(b).array() + pad;
  RTCBounds& box = *args->bounds_o;
  box.lower_x = static_cast<float>(lo.x());
  box.lower_y = static_cast<float>(lo.y());
  box.lower_z = static_cast<float>(lo.z());
  box.upper_x = static_cast<float>(hi.x());
  box.upper_y = static_cast<float>(hi.y());
  box.upper_z = static_cast<float>(hi.z());
}

// The entry distance of the ray o + t d (d unit) into the capsule a–b of radius r, with the
// outward normal there; NaN for a miss.
double capsuleHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                  const Eigen::Vector3d& b, double r, Eigen::Vector3d& normal) {
  constexpr double kMiss = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d ba = b - a, oa = o - a;
  const double baba = ba.dot(ba), bard = ba.dot(d), baoa = ba.dot(oa), rdoa = d.dot(oa),
               oaoa = oa.dot(oa);
  const double qa = baba - bard * bard, qb = baba * rdoa - baoa * bard,
               qc = baba * oaoa - baoa * baoa - r * r * baba;
  const double h = qb * qb - qa * qc;
  if (h < 0.0)
    return kMiss;
  if (qa > 0.0) {
    // The cylinder's near root, in the form without cancellation: qc / (−qb + √h).
    const double root = -qb + std::sqrt(h);
    const double t = root != 0.0 ? qc / root : -qb / qa;
    const double y = baoa + t * bard;
    if (y > 0.0 && y < baba) {
      normal = (oa + t * d - ba * (y / baba)) / r;
      return t;
    }
  }
  // The end sphere the ray meets first (the body missed).
  const double y = baoa + (qa > 0.0 ? (-qb - std::sqrt(h)) / qa : 0.0) * bard;
  const Eigen::Vector3d centre = y <= 0.0 ? a : b;
  const Eigen::Vector3d oc = o - centre;
  const double sb = d.dot(oc), sc = oc.dot(oc) - r * r, sh = sb * sb - sc;
  if (sh < 0.0)
    return kMiss;
  const double t = sc / (-sb + std::sqrt(sh));
  normal = (oc + t * d) / r;
  return t;
}

void wireIntersect(const RTCIntersectFunctionNArguments* args) {
  const auto& w = *static_cast<const WireData*>(args->geometryUserPtr);
  const Eigen::Vector3d& a = w.points[args->primID];
  const Eigen::Vector3d& b = w.points[args->primID + 1];
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  const unsigned N = args->N;
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] == 0)
      continue;
    const Eigen::Vector3d o(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i),
                            RTCRayN_org_z(ray, N, i));
    Eigen::Vector3d d(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
    const double scale = d.norm();  // 1 unless an instance scales the ray
    d /= scale;
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    const double t = capsuleHit(o, d, a, b, w.radius, n) / scale;
    if (!(t >= RTCRayN_tnear(ray, N, i) && t <= RTCRayN_tfar(ray, N, i)))
      continue;
    RTCRayN_tfar(ray, N, i) = static_cast<float>(t);
    RTCHitN_Ng_x(hit, N, i) = static_cast<float>(n.x());
    RTCHitN_Ng_y(hit, N, i) = static_cast<float>(n.y());
    RTCHitN_Ng_z(hit, N, i) = static_cast<float>(n.z());
    RTCHitN_u(hit, N, i) = 0.0f;
    RTCHitN_v(hit, N, i) = 0.0f;
    RTCHitN_primID(hit, N, i) = args->primID;
    RTCHitN_geomID(hit, N, i) = args->geomID;
    for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
      RTCHitN_instID(hit, N, i, l) = args->context->instID[l];
  }
}

}  // namespace

void addTriangles(RTCDevice device, RTCScene scene, const scene::Mesh& mesh,
                  const Eigen::Vector3d& offset, const Eigen::Matrix3f& linear,
                  const Eigen::Matrix3d& level) {
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  setVertices(g, mesh, offset, linear, level);
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k)
      t[3 * i + k] = mesh.triangles[i][static_cast<std::size_t>(k)];
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
}

void addGrid(RTCDevice device, RTCScene scene, const scene::Mesh& mesh,
             const Eigen::Vector3d& offset, const Eigen::Matrix3d& level) {
  const std::size_t n = mesh.vertices.size(), width = mesh.grid_columns;
  if (width < 2 || n % width != 0 || n / width < 2 || width > 32767 || n / width > 32767 ||
      mesh.parts.size() != 1)
    throw RuntimeError("Embree grid: a height field must be 2..32767 vertices a side, one part");
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_GRID);
  setVertices(g, mesh, offset, Eigen::Matrix3f::Identity(), level);
  auto* grid = static_cast<RTCGrid*>(
      rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid), 1));
  grid->startVertexID = 0;
  grid->stride = static_cast<unsigned>(width);
  grid->width = static_cast<unsigned short>(width);
  grid->height = static_cast<unsigned short>(n / width);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
}

void addWire(RTCDevice device, RTCScene scene, const scene::Wire& wire,
             const Eigen::Matrix3d& level, WireData& data) {
  const bool identity = level.isIdentity(0.0);
  for (const Eigen::Vector3f& p : wire.points)
    data.points.push_back(identity ? Eigen::Vector3d(p.cast<double>())
                                   : Eigen::Vector3d(level * p.cast<double>()));
  data.radius = wire.radius_m;
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(wire.points.size() - 1));
  rtcSetGeometryUserData(g, &data);
  rtcSetGeometryBoundsFunction(g, &wireBounds, nullptr);
  rtcSetGeometryIntersectFunction(g, &wireIntersect);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
}

}  // namespace trainsim::lidar::detail
