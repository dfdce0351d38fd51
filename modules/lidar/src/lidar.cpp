#include "trainsim/lidar/lidar.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <numeric>

#include "column_frames.hpp"
#include "echoes.hpp"
#include "packet_returns.hpp"
#include "ring_order.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"

namespace trainsim::lidar {
namespace {

// Random keys: (frame << 16 | laser) << 16 | column / 8 for the noise (eight columns' draws
// from one Philox block), frame << 16 | laser for the dropout.
constexpr std::uint64_t kLaserBits = 16, kGroupBits = 16;
constexpr std::size_t kNoiseGroup = 8;

// Rays handed to one task: enough for coherent packets, few enough that a scan is split into
// many tasks and can be cancelled between them.
constexpr std::size_t kTaskRays = 2048;

using detail::deskewed;
using detail::Echo;
using detail::kDeskew;
using detail::kFrameFields;
using detail::kNoReturn;
using detail::kPoseStep;
using detail::kShift;
using detail::orderRing;
using detail::ringKey;
using detail::storePoint;
using detail::SubHit;

}  // namespace

// A frame's working memory, reused from frame to frame (allocating and zeroing a few MB per
// frame cost as much as the traversal): each column's poses, every slot's point and its key
// (kNoReturn for none), slots ring by ring (ring r's from r W R on, column by column); per ring
// its returns in output order; per task the returns it found.
struct Scanner::Scratch {
  std::vector<Eigen::Isometry3d> poses;  // per column: the sensor at its firing
  std::vector<float> frames;             // per column: its ray frame and deskewing, by lane
  std::vector<LidarPoint> points;
  std::vector<float> coverage;  // with divergence only
  std::vector<float> keys;
  std::vector<std::size_t> found;                   // per task
  std::vector<std::vector<std::uint64_t>> order;    // per ring: key bits << 32 | slot
  std::vector<std::vector<std::uint32_t>> buckets;  // per ring: a counting sort's starts
  Eigen::Vector3f up = Eigen::Vector3f::UnitZ();    // the local vertical, scene axes
};

// One task's working memory: its rays, hits and draws (a few tens of kB, in the core's cache
// while its returns are worked out), reused from task to task rather than held for the frame.
struct Scanner::Block {
  std::vector<RayPacket> packets;  // one ray a pulse
  std::vector<Ray> rays;           // several
  std::vector<RayHit> hits;
  std::vector<double> noise;       // [column][return]
  std::vector<std::uint8_t> kept;  // per column: 0 where dropout takes the pulse
  std::vector<SubHit> sub;
  std::vector<Echo> echoes;
};

Eigen::Vector3d beamOrigin(const ScanPattern& pattern, int laser, double azimuth_deg,
                           double head_deg) {
  const Laser& l = pattern.lasers[static_cast<std::size_t>(laser)];
  const double a = azimuth_deg * kRadPerDeg, head = head_deg * kRadPerDeg;
  const double e = l.elevation_deg * kRadPerDeg;
  return l.vertical_offset_m *
             Eigen::Vector3d(-std::sin(e) * std::cos(a), -std::sin(e) * std::sin(a), std::cos(e)) +
         l.horizontal_offset_m * Eigen::Vector3d(-std::sin(a), std::cos(a), 0.0) +
         pattern.beam_origin_radius_m * Eigen::Vector3d(std::cos(head), std::sin(head), 0.0) +
         pattern.beam_origin_height_m * Eigen::Vector3d::UnitZ();
}

bool beamsLeaveOutside(const ScanPattern& pattern, const Eigen::Isometry3d& pose,
                       const Eigen::AlignedBox3d& box) {
  if (!pattern.offsetBeams())
    return !box.contains(pose.translation());
  for (std::size_t l = 0; l < pattern.lasers.size(); ++l)
    for (int k = 0; k < 72; ++k) {
      const double head = 5.0 * k;
      const Eigen::Vector3d o = beamOrigin(pattern, static_cast<int>(l),
                                           head + pattern.lasers[l].azimuth_offset_deg, head);
      if (box.contains(pose * o))
        return false;
    }
  return true;
}

Scanner::~Scanner() = default;

std::string_view Scanner::vectorIsa() {
  return detail::avx2Returns() ? "AVX2" : "SSE2";
}

std::unique_ptr<Scanner::Scratch> Scanner::makeScratch() const {
  auto s = std::make_unique<Scratch>();
  const auto W = static_cast<std::size_t>(params_.pattern.columns);
  const std::size_t rings = params_.pattern.lasers.size();
  s->poses.resize(W);
  s->frames.resize(kFrameFields * padded_);
  s->points.resize(static_cast<std::size_t>(pulsesPerFrame() * returnsPerPulse()));
  if (params_.sub_rays > 1)
    s->coverage.resize(s->points.size());
  s->keys.resize(s->points.size());
  s->found.resize(rings * tasksPerRing());
  s->order.resize(rings);
  for (auto& o : s->order)
    o.reserve(s->points.size() / rings);
  s->buckets.assign(rings, std::vector<std::uint32_t>(W + 1));
  return s;
}

std::size_t Scanner::tasksPerRing() const {
  const auto W = static_cast<std::size_t>(params_.pattern.columns);
  return (W + task_columns_ - 1) / task_columns_;
}

Scanner::Scanner(LidarParams params) : params_(std::move(params)) {
  const ScanPattern& p = params_.pattern;
  // The limits of LidarPoint's fields (and of the random keys' laser bits).
  static_assert((1 << kLaserBits) > std::numeric_limits<std::uint16_t>::max());
  if (p.columns < 1 || p.columns > std::numeric_limits<std::uint16_t>::max() || p.lasers.empty() ||
      p.lasers.size() > std::numeric_limits<std::uint16_t>::max())
    throw ConfigError("LiDAR pattern: columns must be 1..65535 and lasers 1..65535");
  if (scene::materials().size() > std::numeric_limits<std::uint8_t>::max() + 1u)
    throw RuntimeError("LiDAR: a point holds a material id in a byte; the table has more");
  const std::size_t L = p.lasers.size();
  const auto W = static_cast<std::size_t>(p.columns);
  directions_.resize(W * L);
  const bool offset = p.offsetBeams();
  if (offset)
    origins_.resize(W * L);
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t c = 0; c < W; ++c) {
      const double a = p.azimuthDeg(static_cast<int>(c), static_cast<int>(l)) * kRadPerDeg;
      const double e = p.lasers[l].elevation_deg * kRadPerDeg;
      directions_[l * W + c] =
          Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      if (offset)
        origins_[l * W + c] = beamOrigin(
            p, static_cast<int>(l), p.azimuthDeg(static_cast<int>(c), static_cast<int>(l)),
            p.headAzimuthDeg(static_cast<int>(c), static_cast<int>(l)));
    }
  if (params_.vehicle && !beamsLeaveOutside(p, params_.vehicle->sensor_pose, params_.vehicle->box))
    throw ConfigError("LiDAR: its beams leave the head inside its vehicle's body");
  axes_.reserve(directions_.size());
  for (const Eigen::Vector3d& d : directions_)
    axes_.push_back(d.cast<float>());
  padded_ = (W + 7) / 8 * 8;
  beams_.assign((offset ? 7 : 4) * L * padded_, 0.0f);
  for (std::size_t l = 0; l < L; ++l)
    for (std::size_t c = 0; c < W; ++c) {
      const auto i = static_cast<int>(c), j = static_cast<int>(l);
      for (std::size_t k = 0; k < 3; ++k)
        beams_[(k * L + l) * padded_ + c] = axes_[l * W + c][static_cast<Eigen::Index>(k)];
      beams_[(3 * L + l) * padded_ + c] =
          static_cast<float>(reach(directions_[l * W + c], origin(i, j)));
      if (offset)
        for (std::size_t k = 0; k < 3; ++k)
          beams_[((4 + k) * L + l) * padded_ + c] =
              static_cast<float>(origin(i, j)[static_cast<Eigen::Index>(k)]);
    }
  ring_lasers_ = p.ringLasers();
  // Columns a task casts of one ring: about kTaskRays rays, at least a packet's worth of pulses,
  // a multiple of the noise's groups, and at least 32 tasks a frame where the pattern has them
  // (a pattern of few rings is split along them).
  const std::size_t per_pulse = static_cast<std::size_t>(std::max(1, params_.sub_rays));
  std::size_t columns = std::min(W, std::max<std::size_t>(kTaskRays / per_pulse, 1));
  columns = std::min(columns, std::max<std::size_t>(W * L / 32, 1));
  task_columns_ = std::min(W, (columns + kNoiseGroup - 1) / kNoiseGroup * kNoiseGroup);
  for (const scene::Material& m : scene::materials())
    backscatter_.emplace_back(m);
  fog_ = FogModel(params_.fog);
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

LidarFrame Scanner::scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                         std::uint64_t frame) const {
  LidarFrame out;
  scan(scene, pose, random, frame, out);
  return out;
}

void Scanner::scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                   std::uint64_t frame, LidarFrame& out, const std::atomic<bool>* cancel,
                   const Eigen::Vector3d& up) const {
  const ScanPattern& p = params_.pattern;
  const std::size_t W = static_cast<std::size_t>(p.columns), R = returnsPerPulse();
  std::unique_ptr<Scratch> scratch = scratch_.take([this] { return makeScratch(); });
  Scratch& w = *scratch;
  w.up = up.normalized().cast<float>();
  const Eigen::Isometry3d frame_pose = pose(0.0);
  const Eigen::Isometry3d world_to_frame = frame_pose.inverse();
  std::atomic<bool> cancelled = false;
  const auto stop = [&] {
    if (cancel == nullptr || !cancel->load(std::memory_order_relaxed))
      return false;
    cancelled.store(true, std::memory_order_relaxed);
    return true;
  };
  // Each column's pose at its firing, its rays' frame, and the deskewing from there to the
  // sensor at the frame time (in float: a point is within the sensor's range of it).
  tbb::parallel_for(tbb::blocked_range<int>(0, p.columns, 4 * kPoseStep), [&](const auto& range) {
    if (stop())
      return;
    columnPoses(pose, frame_pose, range.begin(), range.end(), &w.poses[range.begin()]);
    columnFrames(&w.poses[range.begin()], world_to_frame, scene.origin(),
                 static_cast<std::size_t>(range.begin()), static_cast<std::size_t>(range.end()),
                 w.frames.data());
  });
  // Each ring in runs of columns: a task's rays go to Embree in packets of neighbouring
  // columns of one laser (rays eight columns apart meet the same surfaces far more often than
  // eight lasers of one column do: the traversal takes about two thirds of the time).
  const std::size_t rings = ring_lasers_.size(), per_ring = tasksPerRing();
  if (!cancelled.load())
    tbb::parallel_for(std::size_t{0}, rings * per_ring, [&](std::size_t t) {
      if (stop())
        return;
      const std::size_t ring = t / per_ring, begin = t % per_ring * task_columns_;
      std::unique_ptr<Block> block = blocks_.take();
      w.found[t] = castColumns(scene, random, frame, ring, begin,
                               std::min(W, begin + task_columns_), *block, w);
      blocks_.give(std::move(block));
    });
  if (cancelled.load()) {
    scratch_.give(std::move(scratch));
    throw Cancelled("run cancelled during a LiDAR scan");
  }

  // KITTI order: ring by ring, each by the azimuth of its written coordinates counter-clockwise
  // from the front (from the rear within an azimuth window: keySign()), points whose float keys
  // are equal by slot (by column), by a sort of (key, slot) words that moves each point once;
  // not by the column walk: deskewing moves near points by many columns (4 m at 10 m is 25°).
  std::vector<std::size_t> first(rings + 1, 0);
  for (std::size_t r = 0; r < rings; ++r)
    first[r + 1] = first[r] + std::accumulate(w.found.begin() + r * per_ring,
                                              w.found.begin() + (r + 1) * per_ring, std::size_t{0});
  out.rays = raysPerFrame();
  out.points.resize(first[rings]);
  const bool divergent = !w.coverage.empty();
  out.coverage.resize(divergent ? first[rings] : 0);
  out.instances = scene.instances();
  if (fog_.on())  // the fog's echoes: "stuff", of no instance
    out.instances.push_back(0);
  tbb::parallel_for(std::size_t{0}, rings, [&](std::size_t r) {
    const std::vector<std::uint64_t>& order = w.order[r];
    // The tasks counted the ring's returns as the sort does.
    orderRing(w.keys.data() + r * W * R, w.points.data() + r * W * R, W, R, w.order[r],
              w.buckets[r], out.points.data() + first[r]);
    if (divergent) {
      const float* share = w.coverage.data() + r * W * R;
      float* into = out.coverage.data() + first[r];
      for (const std::uint64_t o : order)
        *into++ = share[o & 0xFFFFFFFFu];
    }
  });
  scratch_.give(std::move(scratch));
}

void Scanner::draw(const RandomStream& random, std::uint64_t frame, std::size_t laser,
                   std::size_t begin, std::size_t end, Block& b) const {
  // Keyed by frame, laser and column (so the same for any split into tasks: a task begins on a
  // noise group); padded with zeros to whole packets of columns.
  const std::size_t R = static_cast<std::size_t>(returnsPerPulse());
  const std::size_t columns = end - begin, padded = (columns + 7) / 8 * 8;
  const std::uint64_t key = (frame << kLaserBits) | laser;
  b.noise.assign(padded * R, 0.0);
  if (params_.range_sigma_m > 0.0 || params_.range_sigma_slope > 0.0)
    for (std::size_t c = begin; c < end; c += kNoiseGroup)
      random.compactNormals((key << kGroupBits) | (c / kNoiseGroup), &b.noise[(c - begin) * R],
                            std::min(kNoiseGroup, end - c) * R);
  b.kept.assign(padded, 0);
  std::fill_n(b.kept.begin(), columns, 1);
  if (params_.dropout > 0.0) {  // one draw of four uniforms serves four columns
    const RandomStream dropout_random(random.seed(), random.stream() ^ 0x5bd1e995u);
    for (std::size_t c = begin; c < end; c += 4) {
      const std::array<double, 4> u = dropout_random.uniform4(key, c / 4);
      for (std::size_t k = 0; k < 4 && c + k < end; ++k)
        b.kept[c - begin + k] = u[k] > params_.dropout;
    }
  }
}

std::size_t Scanner::castPulses(const RayScene& scene, const RandomStream& random,
                                std::uint64_t frame, std::size_t ring, std::size_t begin,
                                std::size_t end, Block& b, Scratch& w) const {
  const ScanPattern& p = params_.pattern;
  const auto l = static_cast<std::size_t>(ring_lasers_[ring]);
  const std::size_t W = static_cast<std::size_t>(p.columns), P = padded_, L = ring_lasers_.size();
  const std::size_t R = static_cast<std::size_t>(returnsPerPulse()), columns = end - begin;
  const std::size_t packets = (columns + 7) / 8;
  if (b.packets.size() < packets)
    b.packets.resize(packets);
  fillPackets(static_cast<int>(l), begin, end, w.frames.data(), b.packets.data());
  scene.cast(std::span<RayPacket>(b.packets.data(), packets), columns);
  draw(random, frame, l, begin, end, b);

  detail::PacketSetup setup;
  setup.backscatter = backscatter_.data();
  setup.sigma0 = params_.range_sigma_m;
  setup.sigma1 = params_.range_sigma_slope;
  setup.threshold = params_.intensity_threshold;
  setup.detectable = params_.detectable();
  setup.range_min = static_cast<float>(p.range_min_m);
  setup.range_max = static_cast<float>(p.range_max_m);
  setup.falloff = params_.range_falloff;
  setup.scale = params_.scale;
  setup.frames = w.frames.data();
  setup.padded = P;
  setup.deskew = kDeskew;
  setup.shift = kShift;
  setup.ax = &beams_[l * P];
  setup.ay = &beams_[(L + l) * P];
  setup.az = &beams_[(2 * L + l) * P];
  if (!origins_.empty()) {
    setup.bx = &beams_[(4 * L + l) * P];
    setup.by = &beams_[(5 * L + l) * P];
    setup.bz = &beams_[(6 * L + l) * P];
  }
  setup.directions = params_.motion_compensated ? nullptr : &directions_[l * W];
  setup.origins = params_.motion_compensated || origins_.empty() ? nullptr : &origins_[l * W];
  setup.key_sign = keySign();
  setup.ring = static_cast<std::uint16_t>(ring);
  setup.returns = R;
  LidarPoint* points = w.points.data() + ring * W * R;
  float* keys = w.keys.data() + ring * W * R;
  std::size_t found = 0;
  for (std::size_t i = 0; i < packets; ++i) {
    const std::size_t c0 = begin + 8 * i;
    found += detail::packetReturns(setup, b.packets[i], c0, std::min<std::size_t>(8, end - c0),
                                   &b.noise[8 * i * R], &b.kept[8 * i], points, keys);
  }
  if (R > 1)  // one ray a pulse has one echo: the second slot is always empty
    for (std::size_t c = begin; c < end; ++c)
      keys[c * R + 1] = kNoReturn;
  return found;
}

// Reads the scanner's settings from locals: stores into the points may alias anything, so values
// read through `this` or a captured reference would be loaded again after every store.
std::size_t Scanner::castColumns(const RayScene& scene, const RandomStream& random,
                                 std::uint64_t frame, std::size_t ring, std::size_t begin,
                                 std::size_t end, Block& b, Scratch& w) const {
  // One ray a pulse, eight pulses at a time; each pulse on its own where it may have several
  // echoes (sub-rays, or a fog's echo before the surface's).
  if (footprint_.size() == 1 && !fog_.on())
    return castPulses(scene, random, frame, ring, begin, end, b, w);
  const ScanPattern& p = params_.pattern;
  const auto l = static_cast<std::size_t>(ring_lasers_[ring]);
  const std::size_t W = static_cast<std::size_t>(p.columns), columns = end - begin;
  const std::size_t N = footprint_.size(), R = static_cast<std::size_t>(returnsPerPulse());
  const double sigma0 = params_.range_sigma_m, sigma1 = params_.range_sigma_slope;
  const auto range_min = static_cast<float>(p.range_min_m),
             range_max = static_cast<float>(p.range_max_m);
  const bool falloff = params_.range_falloff;
  const bool compensated = params_.motion_compensated;
  const IntensityScale scale = params_.scale;
  const Backscatter* backscatter = backscatter_.data();
  const auto ring_id = static_cast<std::uint16_t>(ring);
  const float key_sign = keySign();

  b.rays.resize(columns * N);
  b.hits.resize(columns * N);
  pulseRays(static_cast<int>(l), begin, end, w.poses.data(), scene.origin(), b.rays.data());
  scene.intersect(std::span<const Ray>(b.rays), std::span<RayHit>(b.hits));
  draw(random, frame, l, begin, end, b);
  const Ray* rays = b.rays.data();
  const RayHit* hits = b.hits.data();
  const double* noise = b.noise.data();
  const std::uint8_t* kept = b.kept.data();
  const float* frames = w.frames.data();
  const std::size_t padded = padded_;
  const Eigen::Vector3f* axes = &axes_[l * W];
  const Eigen::Vector3d* directions = &directions_[l * W];
  LidarPoint* points = w.points.data() + ring * W * R;
  float* keys = w.keys.data() + ring * W * R;
  float* coverages = w.coverage.empty() ? nullptr : w.coverage.data() + ring * W * R;
  const Eigen::Vector3d* origins = origins_.empty() ? nullptr : &origins_[l * W];
  const auto origin = [&](std::size_t c) -> Eigen::Vector3d {
    return origins != nullptr ? origins[c] : Eigen::Vector3d::Zero();
  };
  std::size_t found = 0;

  // Writes slot c R + j of the ring, return j of column c: the echo at `truth` m with
  // reflectivity `rho`, if its noisy range is within limits; otherwise marks the slot empty
  // (and leaves its point, which is never read).
  const auto put = [&](std::size_t c, std::size_t j, double truth, double rho,
                       const RayHit& label) {
    const std::size_t slot = c * R + j;
    const auto range_m =
        static_cast<float>(truth + (sigma0 + sigma1 * truth) * noise[(c - begin) * R + j]);
    if (!(range_m >= range_min && range_m <= range_max)) {
      keys[slot] = kNoReturn;
      return;
    }
    const Eigen::Vector3f along = axes[c] * range_m;
    const Eigen::Vector3f xyz =
        deskewed(frames, padded, c,
                 origins != nullptr ? Eigen::Vector3f(along + origin(c).cast<float>()) : along);
    storePoint(points[slot], xyz, static_cast<float>(scaledIntensity(rho, range_m, falloff, scale)),
               range_m, label.object, static_cast<std::uint16_t>(c), ring_id, label.cls,
               static_cast<std::uint8_t>(label.material), static_cast<std::uint8_t>(j));
    // Ordered by the coordinates the dataset writes: as Scanner::written() gives them.
    const Eigen::Vector3d measured = directions[c] * static_cast<double>(range_m);
    const Eigen::Vector3f written =
        compensated
            ? xyz
            : (origins != nullptr ? Eigen::Vector3d(measured + origin(c)) : measured).cast<float>();
    keys[slot] = ringKey(written.x(), written.y(), key_sign);
    ++found;
  };

  // The fog's echo: its label, and its range drawn per pulse (keyed as the dropout's draws).
  const bool foggy = fog_.on();
  // The fog's object is the one scan() appends to the scene's.
  const RayHit fog_label{0.0f, Eigen::Vector3f::Zero(), scene::cls::kFog, scene::mat::kNone,
                         static_cast<std::uint32_t>(scene.instances().size())};
  const Eigen::Vector3f up = w.up;
  std::array<double, 4> fog_u{};
  const RandomStream fog_random(random.seed(), random.stream() ^ 0x27d4eb2fu);
  const std::uint64_t fog_key = (frame << kLaserBits) | l;

  std::vector<Echo>& echoes = b.echoes;
  for (std::size_t c = begin; c < end; ++c) {
    const std::size_t base = (c - begin) * N;
    // The pulse's sub-ray hits with their backscatter, grouped into echoes; not those nearer
    // than the minimum range (the receiver is blind there: what they hit blocks those sub-rays,
    // and the rest of the footprint still returns what lies beyond).
    b.sub.clear();
    for (std::size_t k = 0; k < N; ++k) {
      const RayHit& h = hits[base + k];
      if (!h.hit() || h.range < range_min)
        continue;
      const double cos_theta =
          std::abs(h.normal.cast<double>().dot(rays[base + k].direction.cast<double>()));
      double rho = backscatter[h.material](cos_theta);
      if (foggy)  // dimmed by the fog there and back
        rho *= fog_.transmission(h.range, rays[base + k].direction.dot(up));
      b.sub.push_back({&h, rays[base + k].direction, h.range, rho});
    }
    echoes.clear();
    if (!b.sub.empty())
      echoesOf(b.sub, params_.echo_separation_m, 1.0 / static_cast<double>(N), echoes);
    if (foggy) {
      // The fog's echo, from the share of the footprint that no nearer surface covers (with one
      // ray a pulse, any nearer surface hides it), beyond where the receiver is blind and
      // before the vehicle's body ends the beam.
      if (c == begin || c % 4 == 0)
        fog_u = fog_random.uniform4(fog_key, c / 4);
      const double at = fog_.drawRange(fog_u[c % 4]);
      std::size_t before = 0;
      double open = 1.0;
      for (; before < echoes.size() && echoes[before].range <= at; ++before)
        open -= echoes[before].coverage;
      const Ray& axis = rays[base];  // one sub-ray's is as good: the fog fills the footprint
      if (at >= range_min && at < axis.t_far && open > 1e-9) {
        const double s = axis.direction.dot(up);
        const double rho = open * fog_.peakPower() * fog_.density(at, s) * at * at;
        echoes.insert(echoes.begin() + static_cast<std::ptrdiff_t>(before),
                      Echo{at, rho, open, &fog_label});
      }
    }
    std::size_t chosen = 0;
    if (!echoes.empty() && kept[c - begin] != 0)
      chosen = selectReturns(echoes, params_);  // 0 when none is bright enough
    for (std::size_t j = 0; j < R; ++j) {
      if (j < chosen) {
        put(c, j, echoes[j].range, echoes[j].reflectivity, *echoes[j].label);
        if (coverages != nullptr)
          coverages[c * R + j] = static_cast<float>(echoes[j].coverage);
      } else
        keys[c * R + j] = kNoReturn;
    }
  }
  return found;
}

}  // namespace trainsim::lidar
