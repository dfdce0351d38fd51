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

// One sub-ray's hit and its backscatter.
struct SubHit {
  const RayHit* hit;
  double range;
  double rho;
};

// One echo of a pulse: sub-ray hits closer than the echo separation to the next in range.
struct Echo {
  double range = 0.0;             // the backscatter-weighted mean of its sub-rays' ranges
  double reflectivity = 0.0;      // Σ w ρ over its sub-rays: what the intensity reports
  double coverage = 0.0;          // Σ w: the share of the pulse that hit it
  const RayHit* label = nullptr;  // the sub-ray hit with the most backscatter
};

// Groups a pulse's sub-ray hits into echoes, nearest first; `weight` is each sub-ray's share
// of the pulse's energy. One hit gives one echo at exactly its range and reflectivity.
void echoesOf(std::vector<SubHit>& sub, double separation, double weight, std::vector<Echo>& out) {
  // Insertion sort: stable, no allocation (a pulse has few sub-rays, most often one).
  for (std::size_t i = 1; i < sub.size(); ++i)
    for (std::size_t j = i; j > 0 && sub[j].range < sub[j - 1].range; --j)
      std::swap(sub[j], sub[j - 1]);
  out.clear();
  double near = 0.0, sum_offset = 0.0, best = -1.0;
  for (std::size_t i = 0; i < sub.size(); ++i) {
    if (i == 0 || sub[i].range - sub[i - 1].range > separation) {
      out.emplace_back();
      near = sub[i].range;
      sum_offset = 0.0;
      best = -1.0;
    }
    Echo& e = out.back();
    const double backscatter = weight * sub[i].rho;
    e.reflectivity += backscatter;
    e.coverage += weight;
    sum_offset += (backscatter > 0.0 ? backscatter : 0.0) * (sub[i].range - near);
    e.range = near + (e.reflectivity > 0.0 ? sum_offset / e.reflectivity : 0.0);
    if (backscatter > best) {
      best = backscatter;
      e.label = sub[i].hit;
    }
  }
}

// Moves the echoes the pulse reports to the front (strongest by received power ∝ ρ / R², the
// last, or both) and returns how many; 0 when none is bright enough.
std::size_t selectReturns(std::vector<Echo>& echoes, const LidarParams& params) {
  std::size_t strongest = echoes.size(), last = echoes.size();
  double power = 0.0;
  for (std::size_t i = 0; i < echoes.size(); ++i) {
    const Echo& e = echoes[i];
    if (!(e.reflectivity > 0.0) || e.reflectivity < params.intensity_threshold)
      continue;
    const double p = e.reflectivity / (e.range * e.range);
    if (strongest == echoes.size() || p > power) {
      strongest = i;
      power = p;
    }
    last = i;  // nearest first, so the last bright one is the farthest
  }
  if (strongest == echoes.size())
    return 0;
  const Echo s = echoes[strongest], l = echoes[last];
  switch (params.returns) {
    case LidarParams::Returns::kStrongest:
      echoes[0] = s;
      return 1;
    case LidarParams::Returns::kLast:
      echoes[0] = l;
      return 1;
    case LidarParams::Returns::kDual:
      echoes[0] = s;
      if (last == strongest)
        return 1;
      echoes[1] = l;
      return 2;
  }
  return 0;
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
  std::vector<std::vector<std::pair<double, std::uint32_t>>> order;  // per ring: (key, slot)
  std::vector<std::vector<std::uint32_t>> buckets;  // per ring: a counting sort's starts
};

Scanner::~Scanner() = default;

std::unique_ptr<Scanner::Scratch> Scanner::makeScratch() const {
  auto s = std::make_unique<Scratch>();
  const auto rays = static_cast<std::size_t>(raysPerFrame());
  const auto slots = static_cast<std::size_t>(pulsesPerFrame() * returnsPerPulse());
  s->rays.resize(rays);
  s->hits.resize(rays);
  s->points.resize(slots);
  s->valid.resize(slots);
  s->azimuth.resize(slots);
  s->order.resize(params_.pattern.lasers.size());
  for (auto& o : s->order)
    o.reserve(slots / params_.pattern.lasers.size());
  s->buckets.assign(
      params_.pattern.lasers.size(),
      std::vector<std::uint32_t>(static_cast<std::size_t>(params_.pattern.columns) + 1));
  return s;
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
  if (params_.sub_rays < 1 || params_.sub_rays > 1024 || !(params_.divergence_rad >= 0.0))
    throw ConfigError("LiDAR: sub_rays must be 1..1024 and the divergence not negative");
  // Sub-ray offsets over the footprint's disc of radius divergence / 2: a sunflower (Vogel)
  // pattern, each sub-ray the centre of an equal area; one sub-ray is the beam's axis.
  const int n = params_.sub_rays;
  for (int k = 0; k < n; ++k) {
    if (n == 1) {
      footprint_.emplace_back(0.0, 0.0);
      break;
    }
    const double r = 0.5 * params_.divergence_rad * std::sqrt((k + 0.5) / n);
    const double phi = k * std::numbers::pi * (3.0 - std::sqrt(5.0));
    footprint_.emplace_back(r * std::cos(phi), r * std::sin(phi));
  }
}

void Scanner::columnRays(int c, const Eigen::Isometry3d& T, const Eigen::Vector3d& origin,
                         Ray* out) const {
  const ScanPattern& p = params_.pattern;
  const Eigen::Vector3f o = (T.translation() - origin).cast<float>();
  const std::size_t n = footprint_.size();
  for (std::size_t l = 0; l < p.lasers.size(); ++l) {
    const Eigen::Vector3d& d = direction(c, static_cast<int>(l));
    if (n == 1) {  // the beam's axis
      Ray& r = out[l];
      r.origin = o;
      r.direction = (T.linear() * d).cast<float>().normalized();
      r.t_near = static_cast<float>(p.range_min_m);
      r.t_far = static_cast<float>(p.range_max_m);
      continue;
    }
    // Across the beam: v horizontal (azimuth increasing), u = d × v (elevation increasing).
    Eigen::Vector3d v(-d.y(), d.x(), 0.0);
    v = v.norm() > 1e-9 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d u = d.cross(v);
    for (std::size_t k = 0; k < n; ++k) {
      Ray& r = out[l * n + k];
      const Eigen::Vector2d& f = footprint_[k];
      const double angle = f.norm();
      const Eigen::Vector3d sub =
          angle == 0.0 ? d
                       : Eigen::Vector3d(std::cos(angle) * d +
                                         std::sin(angle) / angle * (f.x() * v + f.y() * u));
      r.origin = o;
      r.direction = (T.linear() * sub).cast<float>().normalized();
      r.t_near = static_cast<float>(p.range_min_m);
      r.t_far = static_cast<float>(p.range_max_m);
    }
  }
}

Eigen::Isometry3d Scanner::columnPose(const PoseAt& pose, int c,
                                      const Eigen::Isometry3d& frame_pose) const {
  return params_.motion_distortion ? pose(c * params_.pattern.columnPeriod()) : frame_pose;
}

std::vector<Ray> Scanner::rays(const RayScene& scene, const PoseAt& pose) const {
  const std::size_t per_column = params_.pattern.lasers.size() * footprint_.size();
  std::vector<Ray> out(static_cast<std::size_t>(params_.pattern.columns) * per_column);
  const Eigen::Isometry3d frame_pose = pose(0.0);
  for (int c = 0; c < params_.pattern.columns; ++c)
    columnRays(c, columnPose(pose, c, frame_pose), scene.origin(),
               &out[static_cast<std::size_t>(c) * per_column]);
  return out;
}

LidarFrame Scanner::scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                         std::uint64_t frame) const {
  LidarFrame out;
  scan(scene, pose, random, frame, out);
  return out;
}

void Scanner::scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                   std::uint64_t frame, LidarFrame& out) const {
  const ScanPattern& p = params_.pattern;
  const std::size_t L = p.lasers.size();
  const auto W = static_cast<std::size_t>(p.columns);
  const Eigen::Isometry3d frame_pose = pose(0.0);
  const Eigen::Isometry3d world_to_frame = frame_pose.inverse();
  const RandomStream dropout_random(random.seed(), random.stream() ^ 0x5bd1e995u);
  std::unique_ptr<Scratch> scratch = scratch_.take([this] { return makeScratch(); });
  Scratch& w = *scratch;

  const std::size_t N = footprint_.size();
  const auto R = static_cast<std::size_t>(returnsPerPulse());
  const bool noisy = params_.range_sigma_m > 0.0 || params_.range_sigma_slope > 0.0;
  tbb::parallel_for(tbb::blocked_range<int>(0, p.columns, kColumnGrain), [&](const auto& range) {
    const std::size_t n = static_cast<std::size_t>(range.size()) * L * N;
    const std::size_t first = static_cast<std::size_t>(range.begin()) * L * N;
    const std::span<Ray> rays(w.rays.data() + first, n);
    const std::span<RayHit> hits(w.hits.data() + first, n);
    std::vector<Eigen::Isometry3d> poses;
    poses.reserve(static_cast<std::size_t>(range.size()));
    for (int c = range.begin(); c < range.end(); ++c) {
      poses.push_back(columnPose(pose, c, frame_pose));
      columnRays(c, poses.back(), scene.origin(),
                 &rays[static_cast<std::size_t>(c - range.begin()) * L * N]);
    }
    scene.intersect(std::span<const Ray>(rays), hits);
    std::vector<double> noise(L * R, 0.0);
    std::vector<SubHit> sub;
    std::vector<Echo> echoes;
    for (int c = range.begin(); c < range.end(); ++c) {
      const std::uint64_t key = (frame << kColumnBits) | static_cast<std::uint64_t>(c);
      if (noisy)
        random.normals(key, noise.data(), L * R);
      const Eigen::Isometry3d& T = poses[static_cast<std::size_t>(c - range.begin())];
      // From the sensor at this column's firing to the sensor at the frame time.
      const Eigen::Isometry3d deskew = world_to_frame * T;
      for (std::size_t l = 0; l < L; ++l) {
        // Slots ring by ring, so that ordering reads each ring straight through.
        const std::size_t slot0 = (static_cast<std::size_t>(p.lasers[l].ring) * W + c) * R;
        for (std::size_t j = 0; j < R; ++j)
          w.valid[slot0 + j] = 0;
        const std::size_t base = (static_cast<std::size_t>(c - range.begin()) * L + l) * N;
        std::size_t chosen = 0;
        if (N == 1) {
          // One ray a pulse (no divergence), the common case: its hit is the only echo.
          const RayHit& h = hits[base];
          if (!h.hit())
            continue;
          const double cos_theta =
              std::abs(h.normal.cast<double>().dot(T.linear() * direction(c, static_cast<int>(l))));
          const double rho = reflectivity(scene::material(h.material), cos_theta);
          if (!(rho > 0.0) || rho < params_.intensity_threshold)
            continue;  // past the material's maximum incidence angle, or too faint
          echoes.resize(1);
          echoes[0] = {h.range, rho, 1.0, &h};
          chosen = 1;
        } else {
          // The pulse's sub-ray hits with their backscatter, grouped into echoes.
          sub.clear();
          for (std::size_t k = 0; k < N; ++k) {
            const RayHit& h = hits[base + k];
            if (!h.hit())
              continue;
            const double cos_theta =
                std::abs(h.normal.cast<double>().dot(rays[base + k].direction.cast<double>()));
            sub.push_back({&h, h.range, reflectivity(scene::material(h.material), cos_theta)});
          }
          if (sub.empty())
            continue;
          echoesOf(sub, params_.echo_separation_m, 1.0 / static_cast<double>(N), echoes);
          chosen = selectReturns(echoes, params_);
          if (chosen == 0)
            continue;  // none bright enough
        }
        if (params_.dropout > 0.0 && dropout_random.uniform4(key, l / 4)[l % 4] <= params_.dropout)
          continue;
        const Eigen::Vector3d& d_sensor = direction(c, static_cast<int>(l));
        for (std::size_t j = 0; j < chosen; ++j) {
          const Echo& e = echoes[j];
          const double truth = e.range;
          const double range_m =
              truth +
              (params_.range_sigma_m + params_.range_sigma_slope * truth) * noise[j * L + l];
          if (range_m < p.range_min_m || range_m > p.range_max_m)
            continue;
          const std::size_t slot = slot0 + j;
          LidarPoint& pt = w.points[slot];
          const Eigen::Vector3d raw = d_sensor * range_m;
          pt.xyz = (deskew * raw).cast<float>();
          pt.xyz_raw = raw.cast<float>();
          pt.intensity = static_cast<float>(
              scaledIntensity(e.reflectivity, range_m, params_.range_falloff, params_.scale));
          pt.range_m = static_cast<float>(range_m);
          pt.time_s = static_cast<float>(p.firingTime(c, static_cast<int>(l)));
          pt.ring = static_cast<std::uint16_t>(p.lasers[l].ring);
          pt.return_index = static_cast<std::uint8_t>(j);
          pt.coverage = static_cast<float>(e.coverage);
          pt.cls = e.label->cls;
          pt.material = e.label->material;
          pt.instance = e.label->instance;
          const Eigen::Vector3f& written = params_.motion_compensated ? pt.xyz : pt.xyz_raw;
          w.azimuth[slot] = pseudoAzimuth(written.x(), written.y());
          w.valid[slot] = 1;
        }
      }
    }
  });

  // KITTI order: ring by ring, each by the azimuth of its written coordinates (ties, which only
  // coincident points make, by column). Each ring sorts (key, column) pairs, not the points, and
  // not by the column walk: deskewing moves near points by many columns (4 m at 10 m is 25°).
  const std::size_t rings = ring_lasers_.size();
  const std::size_t per_ring = W * R;  // a ring's slots: column by column, its returns
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
    const std::size_t ring0 = r * per_ring;
    std::size_t n = 0;
    for (std::size_t s = 0; s < per_ring; ++s)
      if (w.valid[ring0 + s]) {
        ++start[bucket(w.azimuth[ring0 + s]) + 1];
        ++n;
      }
    for (std::size_t b = 0; b < W; ++b)
      start[b + 1] += start[b];
    order.resize(n);
    for (std::size_t s = 0; s < per_ring; ++s)
      if (w.valid[ring0 + s]) {
        const double key = w.azimuth[ring0 + s];
        order[start[bucket(key)]++] = {key, static_cast<std::uint32_t>(s)};
      }
    for (std::size_t i = 1; i < n; ++i)
      for (std::size_t j = i; j > 0 && order[j] < order[j - 1]; --j)
        std::swap(order[j], order[j - 1]);
    first[r + 1] = n;
  });
  for (std::size_t r = 0; r < rings; ++r)
    first[r + 1] += first[r];
  out.rays = raysPerFrame();
  out.points.resize(first[rings]);
  tbb::parallel_for(std::size_t{0}, rings, [&](std::size_t r) {
    LidarPoint* points = out.points.data() + first[r];
    for (const auto& [key, s] : w.order[r])
      *points++ = w.points[r * per_ring + s];
  });
  scratch_.give(std::move(scratch));
}

}  // namespace trainsim::lidar
