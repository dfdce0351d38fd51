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

// A monotonic stand-in for the azimuth atan2(y, x) mapped to [0, 2π): 0 on +x, rising
// counter-clockwise to 4 just before it (the "diamond angle"). It orders points exactly as
// the azimuth does, with one division instead of an atan2. y = −0 counts as on +x, as the
// quadrant rule (y ≥ 0) counts it.
double pseudoAzimuth(float xf, float yf) {
  const double x = xf, y = yf;
  const double d = std::abs(x) + std::abs(y);
  if (d == 0.0)
    return 0.0;
  const double r = y / d;
  const double a = x >= 0.0 ? r : 2.0 - r;
  return a < 0.0 ? a + 4.0 : a;
}

}  // namespace

// A frame's working memory, reused from frame to frame (allocating and zeroing a few MB per
// frame cost as much as the traversal): every slot's point, whether it holds a return, and its
// azimuth key; per ring its returns in output order.
struct Scanner::Scratch {
  std::vector<Ray> rays;
  std::vector<RayHit> hits;
  std::vector<LidarPoint> points;
  std::vector<std::uint8_t> valid;
  std::vector<double> azimuth;                                       // by slot
  std::vector<std::vector<std::pair<double, std::uint32_t>>> order;  // per ring: (key, column)
  std::vector<std::vector<std::uint32_t>> buckets;  // per ring: a counting sort's starts
};

Scanner::~Scanner() = default;

std::unique_ptr<Scanner::Scratch> Scanner::acquire() const {
  {
    const std::lock_guard lock(pool_mutex_);
    if (!pool_.empty()) {
      auto s = std::move(pool_.back());
      pool_.pop_back();
      return s;
    }
  }
  auto s = std::make_unique<Scratch>();
  const std::size_t n = static_cast<std::size_t>(raysPerFrame());
  s->rays.resize(n);
  s->hits.resize(n);
  s->points.resize(n);
  s->valid.resize(n);
  s->azimuth.resize(n);
  s->order.resize(params_.pattern.lasers.size());
  for (auto& o : s->order)
    o.reserve(static_cast<std::size_t>(params_.pattern.columns));
  s->buckets.assign(
      params_.pattern.lasers.size(),
      std::vector<std::uint32_t>(static_cast<std::size_t>(params_.pattern.columns) + 1));
  return s;
}

void Scanner::release(std::unique_ptr<Scratch> scratch) const {
  const std::lock_guard lock(pool_mutex_);
  pool_.push_back(std::move(scratch));
}

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

std::vector<Ray> Scanner::rays(const RayScene& scene, const PoseAt& pose) const {
  const std::size_t L = params_.pattern.lasers.size();
  std::vector<Ray> out(static_cast<std::size_t>(params_.pattern.columns) * L);
  const Eigen::Isometry3d frame_pose = pose(0.0);
  for (int c = 0; c < params_.pattern.columns; ++c)
    columnRays(c, columnPose(pose, c, frame_pose), scene.origin(),
               &out[static_cast<std::size_t>(c) * L]);
  return out;
}

LidarFrame Scanner::scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                         std::uint64_t frame) const {
  const ScanPattern& p = params_.pattern;
  const std::size_t L = p.lasers.size();
  const auto W = static_cast<std::size_t>(p.columns);
  const Eigen::Isometry3d frame_pose = pose(0.0);
  const Eigen::Isometry3d world_to_frame = frame_pose.inverse();
  const RandomStream dropout_random(random.seed(), random.stream() ^ 0x5bd1e995u);
  std::unique_ptr<Scratch> scratch = acquire();
  Scratch& w = *scratch;

  tbb::parallel_for(tbb::blocked_range<int>(0, p.columns, kColumnGrain), [&](const auto& range) {
    const std::size_t n = static_cast<std::size_t>(range.size()) * L;
    const std::size_t first = static_cast<std::size_t>(range.begin()) * L;
    const std::span<Ray> rays(w.rays.data() + first, n);
    const std::span<RayHit> hits(w.hits.data() + first, n);
    std::vector<Eigen::Isometry3d> poses;
    poses.reserve(static_cast<std::size_t>(range.size()));
    for (int c = range.begin(); c < range.end(); ++c) {
      poses.push_back(columnPose(pose, c, frame_pose));
      columnRays(c, poses.back(), scene.origin(),
                 &rays[static_cast<std::size_t>(c - range.begin()) * L]);
    }
    scene.intersect(std::span<const Ray>(rays), hits);
    std::vector<double> noise(L, 0.0);
    for (int c = range.begin(); c < range.end(); ++c) {
      const std::uint64_t key = (frame << kColumnBits) | static_cast<std::uint64_t>(c);
      if (params_.range_sigma_m > 0.0 || params_.range_sigma_slope > 0.0)
        random.normals(key, noise.data(), L);
      const Eigen::Isometry3d& T = poses[static_cast<std::size_t>(c - range.begin())];
      // From the sensor at this column's firing to the sensor at the frame time.
      const Eigen::Isometry3d deskew = world_to_frame * T;
      for (std::size_t l = 0; l < L; ++l) {
        // Slots ring by ring, so that ordering reads each ring straight through.
        const std::size_t slot = static_cast<std::size_t>(p.lasers[l].ring) * W + c;
        w.valid[slot] = 0;
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
        LidarPoint& pt = w.points[slot];
        const Eigen::Vector3d raw = d_sensor * range_m;
        pt.xyz = (deskew * raw).cast<float>();
        pt.xyz_raw = raw.cast<float>();
        pt.intensity =
            static_cast<float>(scaledIntensity(rho, range_m, params_.range_falloff, params_.scale));
        pt.range_m = static_cast<float>(range_m);
        pt.time_s = static_cast<float>(p.firingTime(c, static_cast<int>(l)));
        pt.ring = static_cast<std::uint16_t>(p.lasers[l].ring);
        pt.cls = h.cls;
        pt.material = h.material;
        pt.instance = h.instance;
        const Eigen::Vector3f& written = params_.motion_compensated ? pt.xyz : pt.xyz_raw;
        w.azimuth[slot] = pseudoAzimuth(written.x(), written.y());
        w.valid[slot] = 1;
      }
    }
  });

  // KITTI order: ring by ring, each by the azimuth of its written coordinates (ties, which only
  // coincident points make, by column). Each ring sorts (key, column) pairs, not the points, and
  // not by the column walk: deskewing moves near points by many columns (4 m at 10 m is 25°).
  const std::size_t rings = ring_lasers_.size();
  std::vector<std::size_t> first(rings + 1, 0);
  tbb::parallel_for(std::size_t{0}, rings, [&](std::size_t r) {
    // A counting sort into one bucket per column's width of azimuth, then an insertion sort
    // that only has to order the few points sharing a bucket: linear time.
    auto& order = w.order[r];
    auto& start = w.buckets[r];
    std::fill(start.begin(), start.end(), 0u);
    const auto bucket = [&](double key) {
      return std::min(W - 1, static_cast<std::size_t>(key * (static_cast<double>(W) / 4.0)));
    };
    std::size_t n = 0;
    for (std::size_t c = 0; c < W; ++c)
      if (w.valid[r * W + c]) {
        ++start[bucket(w.azimuth[r * W + c]) + 1];
        ++n;
      }
    for (std::size_t b = 0; b < W; ++b)
      start[b + 1] += start[b];
    order.resize(n);
    for (std::size_t c = 0; c < W; ++c)
      if (w.valid[r * W + c]) {
        const double key = w.azimuth[r * W + c];
        order[start[bucket(key)]++] = {key, static_cast<std::uint32_t>(c)};
      }
    for (std::size_t i = 1; i < n; ++i)
      for (std::size_t j = i; j > 0 && order[j] < order[j - 1]; --j)
        std::swap(order[j], order[j - 1]);
    first[r + 1] = n;
  });
  for (std::size_t r = 0; r < rings; ++r)
    first[r + 1] += first[r];
  LidarFrame out;
  out.rays = raysPerFrame();
  out.points.resize(first[rings]);
  tbb::parallel_for(std::size_t{0}, rings, [&](std::size_t r) {
    LidarPoint* points = out.points.data() + first[r];
    for (const auto& [key, c] : w.order[r])
      *points++ = w.points[r * W + c];
  });
  release(std::move(scratch));
  return out;
}

}  // namespace trainsim::lidar
