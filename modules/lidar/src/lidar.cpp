#include "trainsim/lidar/lidar.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"

namespace trainsim::lidar {
namespace {

constexpr std::uint64_t kColumnBits = 20;  // random keys: frame << 20 | column

// Columns handed to one task: enough rays for coherent packets and little scheduling.
constexpr int kColumnGrain = 16;

struct Slot {
  bool valid = false;
  LidarPoint point;
};

}  // namespace

Scanner::Scanner(LidarParams params) : params_(std::move(params)) {
  const ScanPattern& p = params_.pattern;
  if (p.columns < 1 || p.columns >= (1 << kColumnBits) || p.lasers.empty())
    throw ConfigError("LiDAR pattern: columns must be 1..1048575 and there must be lasers");
  const std::size_t L = p.lasers.size();
  directions_.resize(static_cast<std::size_t>(p.columns) * L);
  for (int c = 0; c < p.columns; ++c)
    for (std::size_t l = 0; l < L; ++l) {
      const double a = p.azimuthDeg(c, static_cast<int>(l)) * kRadPerDeg;
      const double e = p.lasers[l].elevation_deg * kRadPerDeg;
      directions_[static_cast<std::size_t>(c) * L + l] =
          Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
    }
  ring_lasers_ = p.ringLasers();
}

void Scanner::columnRays(int c, const Eigen::Isometry3d& T, const Eigen::Vector3d& origin,
                         Ray* out) const {
  const ScanPattern& p = params_.pattern;
  const Eigen::Vector3f o = (T.translation() - origin).cast<float>();
  for (std::size_t l = 0; l < p.lasers.size(); ++l) {
    Ray& r = out[l];
    r.origin = o;
    r.direction = (T.linear() * direction(c, static_cast<int>(l))).cast<float>().normalized();
    r.t_near = static_cast<float>(p.range_min_m);
    r.t_far = static_cast<float>(p.range_max_m);
  }
}

Eigen::Isometry3d Scanner::columnPose(const PoseAt& pose, int c,
                                      const Eigen::Isometry3d& frame_pose) const {
  return params_.motion_distortion ? pose(c * params_.pattern.columnPeriod()) : frame_pose;
}

LidarFrame Scanner::scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                         std::uint64_t frame) const {
  const ScanPattern& p = params_.pattern;
  const std::size_t L = p.lasers.size();
  const Eigen::Isometry3d frame_pose = pose(0.0);
  const Eigen::Isometry3d world_to_frame = frame_pose.inverse();
  const RandomStream dropout_random(random.seed(), random.stream() ^ 0x5bd1e995u);
  std::vector<Slot> slots(static_cast<std::size_t>(p.columns) * L);

  tbb::parallel_for(tbb::blocked_range<int>(0, p.columns, kColumnGrain), [&](const auto& range) {
    const std::size_t n = static_cast<std::size_t>(range.size()) * L;
    std::vector<Ray> rays(n);
    std::vector<RayHit> hits(n);
    std::vector<Eigen::Isometry3d> poses;
    poses.reserve(static_cast<std::size_t>(range.size()));
    for (int c = range.begin(); c < range.end(); ++c) {
      poses.push_back(columnPose(pose, c, frame_pose));
      columnRays(c, poses.back(), scene.origin(),
                 &rays[static_cast<std::size_t>(c - range.begin()) * L]);
    }
    scene.intersect(rays, hits);
    std::vector<double> noise(L, 0.0);
    for (int c = range.begin(); c < range.end(); ++c) {
      const std::uint64_t key = (frame << kColumnBits) | static_cast<std::uint64_t>(c);
      if (params_.range_sigma_m > 0.0 || params_.range_sigma_slope > 0.0)
        random.normals(key, noise.data(), L);
      const Eigen::Isometry3d& T = poses[static_cast<std::size_t>(c - range.begin())];
      for (std::size_t l = 0; l < L; ++l) {
        const std::size_t i = static_cast<std::size_t>(c - range.begin()) * L + l;
        const RayHit& h = hits[i];
        if (!h.hit())
          continue;
        const Eigen::Vector3d& d_sensor = direction(c, static_cast<int>(l));
        const double cos_theta = std::abs(h.normal.cast<double>().dot(T.linear() * d_sensor));
        const double rho = reflectivity(scene::material(h.material), cos_theta);
        if (rho <= 0.0 || rho < params_.intensity_threshold)
          continue;  // past the material's maximum incidence angle, or too faint
        if (params_.dropout > 0.0 && dropout_random.uniform4(key, l / 4)[l % 4] <= params_.dropout)
          continue;
        const double truth = h.range;
        const double range_m =
            truth + (params_.range_sigma_m + params_.range_sigma_slope * truth) * noise[l];
        if (range_m < p.range_min_m || range_m > p.range_max_m)
          continue;
        Slot& s = slots[static_cast<std::size_t>(c) * L + l];
        s.valid = true;
        LidarPoint& pt = s.point;
        const Eigen::Vector3d world = T * (d_sensor * range_m);
        pt.xyz = (world_to_frame * world).cast<float>();
        pt.xyz_raw = (d_sensor * range_m).cast<float>();
        pt.intensity =
            static_cast<float>(scaledIntensity(rho, range_m, params_.range_falloff, params_.scale));
        pt.range_m = static_cast<float>(range_m);
        pt.time_s = static_cast<float>(p.firingTime(c, static_cast<int>(l)));
        pt.ring = static_cast<std::uint16_t>(p.lasers[l].ring);
        pt.cls = h.cls;
        pt.material = h.material;
        pt.instance = h.instance;
      }
    }
  });

  // KITTI order: ring by ring, each by the azimuth of its written coordinates in [0, 2π)
  // (ties, which only coincident points make, by column).
  LidarFrame out;
  out.rays = static_cast<std::int64_t>(slots.size());
  std::vector<std::pair<double, int>> ring;
  ring.reserve(static_cast<std::size_t>(p.columns));
  for (const int l : ring_lasers_) {
    ring.clear();
    for (int c = 0; c < p.columns; ++c) {
      const Slot& s = slots[static_cast<std::size_t>(c) * L + static_cast<std::size_t>(l)];
      if (!s.valid)
        continue;
      const Eigen::Vector3f& xyz = params_.motion_compensated ? s.point.xyz : s.point.xyz_raw;
      double a = std::atan2(static_cast<double>(xyz.y()), static_cast<double>(xyz.x()));
      if (a < 0.0)
        a += 2.0 * std::numbers::pi;
      ring.emplace_back(a, c);
    }
    std::sort(ring.begin(), ring.end());
    for (const auto& [azimuth, c] : ring)
      out.points.push_back(
          slots[static_cast<std::size_t>(c) * L + static_cast<std::size_t>(l)].point);
  }
  return out;
}

}  // namespace trainsim::lidar
