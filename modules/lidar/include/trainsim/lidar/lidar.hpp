#pragma once
// A rotating LiDAR's frame: rays in scan order from the pose at each firing, cast into the
// scene, with range noise, dropout and Lambertian-Beckmann intensity, in KITTI point order.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/core/object_pool.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/lidar/fog.hpp"
#include "trainsim/lidar/intensity.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/lidar/scan_pattern.hpp"

namespace trainsim::lidar {

struct LidarParams {
  ScanPattern pattern;
  /// Gaussian range noise: σ = range_sigma_m + range_sigma_slope · range.
  double range_sigma_m = 0.02;
  double range_sigma_slope = 0.0;
  double dropout = 0.0;              ///< probability that a return is lost
  double intensity_threshold = 0.0;  ///< returns whose reflectivity is below this are lost
  /// How far a 10 % Lambertian target at normal incidence is detected: an echo of reflectivity
  /// ρ (its Lambertian-Beckmann backscatter, times the share of the footprint it covers) is lost
  /// beyond range_10_percent_m · √(ρ / 0.1), as received power falls as ρ / R². 0: no limit but
  /// the pattern's range_max_m.
  double range_10_percent_m = 0.0;
  /// The least ρ / R² (m⁻²) detected: 0.1 / range_10_percent_m², 0 without that limit.
  double detectable() const {
    return range_10_percent_m > 0.0 ? 0.1 / (range_10_percent_m * range_10_percent_m) : 0.0;
  }
  IntensityScale scale = IntensityScale::kUnit;
  bool range_falloff = false;  ///< intensity falls as 1/R² (raw) instead of reflectivity
  /// Each column cast from the pose at its own firing time (a spinning sensor on a moving
  /// train; PoseAt is asked at every 16th column and at the revolution's end, and interpolated
  /// in between, far below a micrometre for a train); otherwise every ray from the pose at the
  /// frame time. A column's lasers share its pose: their firing offsets within it (under 40 µs
  /// in every preset) turn their beams and their times, not where they are fired from, which
  /// lies at most 1.8 mm off at 160 km/h.
  bool motion_distortion = true;
  /// Which coordinates the dataset writes, and so orders each ring by: LidarPoint::xyz
  /// (deskewed, KITTI odometry) or Scanner::measured() (as measured); Scanner::written().
  bool motion_compensated = true;

  /// Beam divergence: each pulse is `sub_rays` rays spread evenly (a sunflower pattern, equal
  /// energy each) over its footprint, a cone of full angle `divergence_rad`; 1 is a single ray
  /// along the beam's axis. Sub-ray hits less than `echo_separation_m` apart in range form one
  /// echo, so a pulse half on a wire and half on the wall behind returns two.
  int sub_rays = 1;
  double divergence_rad = 0.003;
  double echo_separation_m = 0.3;
  /// Which echoes a pulse reports (as Velodyne's return modes): the strongest (received power
  /// ∝ reflectivity / range²), the last, or both (dual; one point when they are the same echo).
  enum class Returns { kStrongest, kLast, kDual };
  Returns returns = Returns::kStrongest;

  /// The vehicle the sensor rides on: a box in the vehicle's own axes and the sensor's pose in
  /// them. A ray that meets the box ends there with no return (a sensor's driver drops the
  /// echoes of its own vehicle), so nothing the vehicle hides is seen through it. The box is
  /// rigid with the sensor, so each beam's reach is cut once, when the scanner is made, and
  /// Embree never traverses the hidden part of a ray. Empty: nothing around the sensor.
  struct Vehicle {
    Eigen::AlignedBox3d box;
    Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();
  };
  std::optional<Vehicle> vehicle;
  /// Fog (FogModel): every echo dimmed by its two-way transmission, and the fog's own
  /// backscatter an echo of its own at a range drawn per pulse, from the share of the footprint
  /// no nearer surface covers, labelled scene::cls::kFog (an object of instance 0). It competes
  /// with the surfaces' echoes as they compete with each other (LidarParams::returns): in thick fog
  /// the strongest return is the fog's for all but near, bright surfaces, and the last return still
  /// reaches those the fog lets be detected.
  FogParams fog;
};

/// One return, in 32 bytes (two to a cache line: a frame is written, ordered and read back
/// through memory, so its size is much of its cost). What follows from these fields is not
/// stored: the firing time and the coordinates as measured are Scanner::time() and
/// Scanner::measured(), the instance id LidarFrame::instance().
struct alignas(32) LidarPoint {
  /// Sensor frame at the frame time (deskewed to it with motion distortion on; KITTI's .bin).
  Eigen::Vector3f xyz = Eigen::Vector3f::Zero();
  float intensity = 0.0f;    ///< scaled as LidarParams::scale says
  float range_m = 0.0f;      ///< measured (noisy) range
  std::uint32_t object = 0;  ///< the surface's object: an index into LidarFrame::instances
  std::uint16_t column = 0;  ///< the firing's column
  std::uint16_t ring = 0;    ///< 0 = the highest laser
  scene::ClassId cls = 0;
  std::uint8_t material = 0;  ///< scene::MaterialId (the table has fewer than 256)
  /// 0: the strongest (or last, or only) return; 1: the last of a dual-return pulse.
  std::uint8_t return_index = 0;
};
static_assert(sizeof(LidarPoint) == 32);

struct LidarFrame {
  /// Ring by ring from ring 0 (the highest); within a ring by the azimuth of the written
  /// coordinates (LidarParams::motion_compensated), counter-clockwise from the +x axis: KITTI's
  /// order, in which the community's ring recovery (a new ring where the azimuth crosses +x
  /// from quadrant 4 to 1) never splits a ring, even where deskewing moves a point across +x.
  std::vector<LidarPoint> points;
  /// With beam divergence (sub_rays > 1), each point's share of its pulse's energy (the thin
  /// wire in a footprint returns a fraction, and a fainter point: the intensity is the echo's
  /// footprint-weighted reflectivity); empty otherwise (every share is 1).
  std::vector<float> coverage;
  /// Instance ids by LidarPoint::object (0 for "stuff" without instances).
  std::vector<scene::InstanceId> instances;
  std::int64_t rays = 0;

  scene::InstanceId instance(const LidarPoint& p) const { return instances[p.object]; }
};

/// The sensor's world pose (sensor → world) at `t` seconds after the frame time.
using PoseAt = std::function<Eigen::Isometry3d(double t)>;

/// Where laser `laser` of `pattern` leaves the head, sensor frame, when its beam points at
/// `azimuth_deg` and the head at `head_deg` (ScanPattern::azimuthDeg(), headAzimuthDeg()): its
/// Laser::vertical_offset_m and horizontal_offset_m across the beam and the pattern's
/// beam_origin_radius_m and beam_origin_height_m.
Eigen::Vector3d beamOrigin(const ScanPattern& pattern, int laser, double azimuth_deg,
                           double head_deg);
/// Whether every beam of `pattern` leaves the head outside `box` (whichever way the head
/// points, every 5°), the sensor at `pose` in the box's axes: a sensor whose housing stands on a
/// roof has its origin on the roof and its beams above it.
bool beamsLeaveOutside(const ScanPattern& pattern, const Eigen::Isometry3d& pose,
                       const Eigen::AlignedBox3d& box);

/// A LiDAR with its beam directions worked out once (the table of every column's and laser's
/// direction in the sensor frame).
class Scanner {
 public:
  explicit Scanner(LidarParams params);
  ~Scanner();
  Scanner(const Scanner&) = delete;
  Scanner& operator=(const Scanner&) = delete;
  const LidarParams& params() const { return params_; }
  /// The vector instructions each return's work runs on, on this processor: "AVX2" where it has
  /// them, "SSE2" (the x86-64 baseline) otherwise. The output is the same bytes on either.
  static std::string_view vectorIsa();
  /// Pulses (column × laser) and rays (pulses × sub-rays) of a frame.
  std::int64_t pulsesPerFrame() const {
    return static_cast<std::int64_t>(params_.pattern.columns) *
           static_cast<std::int64_t>(params_.pattern.lasers.size());
  }
  std::int64_t raysPerFrame() const { return pulsesPerFrame() * params_.sub_rays; }
  /// Returns a pulse can report: 2 in dual mode, else 1.
  int returnsPerPulse() const { return params_.returns == LidarParams::Returns::kDual ? 2 : 1; }
  /// Direction of laser l's ray in column c, sensor frame, unit.
  const Eigen::Vector3d& direction(int column, int laser) const {
    return directions_[static_cast<std::size_t>(laser) *
                           static_cast<std::size_t>(params_.pattern.columns) +
                       static_cast<std::size_t>(column)];
  }

  /// Casts one frame, each ring's columns split across the TBB workers of the calling arena.
  /// Random draws come from `random` keyed by (frame, laser, column), so the frame is the same
  /// for any number of threads.
  LidarFrame scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
                  std::uint64_t frame) const;
  /// The same into `out`, reusing its memory: a caller that scans frame after frame keeps one
  /// LidarFrame (a few MB) instead of allocating and initialising it every time. Once `cancel`
  /// (optional) is set, the columns not yet cast are skipped and Cancelled is thrown: a scan of
  /// many sub-rays can take minutes, and Ctrl-C should not wait for it.
  /// `up` is the local vertical in the scene's axes, which the fog's layer thins along.
  void scan(const RayScene& scene, const PoseAt& pose, const RandomStream& random,
            std::uint64_t frame, LidarFrame& out, const std::atomic<bool>* cancel = nullptr,
            const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ()) const;
  /// The fog the scanner casts through (LidarParams::fog).
  const FogModel& fog() const { return fog_; }
  /// Tasks a ring is cast in (each of columnsPerTask() columns, the last what is left).
  std::size_t tasksPerRing() const;
  std::size_t columnsPerTask() const { return task_columns_; }
  /// The rays scan() casts, in the same order (ring by ring, each ring's columns in firing
  /// order, each pulse's sub-rays): for the benchmark's raw traversal of exactly the same rays.
  std::vector<Ray> rays(const RayScene& scene, const PoseAt& pose) const;
  /// A point's firing time after the frame time, seconds.
  float time(const LidarPoint& p) const {
    return static_cast<float>(params_.pattern.firingTime(p.column, laser(p)));
  }
  /// Where laser l's beam leaves the head in column c, sensor frame (ScanPattern's beam
  /// offsets; the origin for a pattern without them). A ray starts there, and its range is
  /// measured from there.
  Eigen::Vector3d origin(int column, int laser) const {
    if (origins_.empty())
      return Eigen::Vector3d::Zero();
    return origins_[static_cast<std::size_t>(laser) *
                        static_cast<std::size_t>(params_.pattern.columns) +
                    static_cast<std::size_t>(column)];
  }
  /// A point in the sensor frame at its firing time (as the sensor measures it, not deskewed):
  /// its beam's origin plus its axis times its range.
  Eigen::Vector3f measured(const LidarPoint& p) const {
    const int l = laser(p);
    const Eigen::Vector3d along = direction(p.column, l) * static_cast<double>(p.range_m);
    return (origins_.empty() ? along : Eigen::Vector3d(origin(p.column, l) + along)).cast<float>();
  }
  /// The coordinates a dataset writes for `p` (LidarParams::motion_compensated).
  Eigen::Vector3f written(const LidarPoint& p) const {
    return params_.motion_compensated ? p.xyz : measured(p);
  }
  /// How far a ray from `from` along `direction` (sensor frame, unit) reaches: the range limit,
  /// or less where the vehicle (LidarParams::vehicle) is in the way.
  double reach(const Eigen::Vector3d& direction,
               const Eigen::Vector3d& from = Eigen::Vector3d::Zero()) const;

 private:
  int laser(const LidarPoint& p) const { return ring_lasers_[p.ring]; }
  /// Rings are ordered by azimuth counter-clockwise from the front (1: KITTI's order), or within
  /// an azimuth window from the rear (−1), so that the window's columns stay in one run.
  float keySign() const { return params_.pattern.wholeRevolution() ? 1.0f : -1.0f; }
  /// Laser `laser`'s rays in columns [begin, end), from the columns' `poses`, relative to
  /// `origin`, with several sub-rays a pulse.
  void pulseRays(int laser, std::size_t begin, std::size_t end, const Eigen::Isometry3d* poses,
                 const Eigen::Vector3d& origin, Ray* out) const;
  /// Laser `laser`'s rays in columns [begin, end) (begin a multiple of 8) into packets of
  /// eight neighbouring columns, from the columns' ray frames (Scratch::frames).
  void fillPackets(int laser, std::size_t begin, std::size_t end, const float* frames,
                   RayPacket* out) const;
  /// Each column's ray frame and deskewing (Scratch::frames) for columns [begin, end), from
  /// their poses, with ray origins relative to `origin`.
  void columnFrames(const Eigen::Isometry3d* poses, const Eigen::Isometry3d& world_to_frame,
                    const Eigen::Vector3d& origin, std::size_t begin, std::size_t end,
                    float* frames) const;
  /// The sensor's poses at the firings of columns [begin, end), into out[0, end − begin).
  void columnPoses(const PoseAt& pose, const Eigen::Isometry3d& frame_pose, int begin, int end,
                   Eigen::Isometry3d* out) const;

  LidarParams params_;
  std::vector<Eigen::Vector3d> directions_;  // laser-major: [laser][column]
  std::vector<Eigen::Vector3f> axes_;        // the same in float
  std::vector<Eigen::Vector3d> origins_;     // laser-major; empty when every beam leaves (0,0,0)
  std::size_t padded_ = 0;                   // columns rounded up to a packet's eight
  /// The beam axes and each one's reach() by lane: [x, y, z, reach][laser][padded_ columns];
  /// then, with origins_, the beams' origins: [x, y, z][laser][padded_ columns].
  std::vector<float> beams_;
  std::vector<Eigen::Vector2d> footprint_;  // sub-ray offsets (rad) across and along the beam
  std::vector<int> ring_lasers_;            // the laser of each ring
  std::size_t task_columns_ = 0;            // columns of one ring a task casts
  std::vector<Backscatter> backscatter_;    // by material id
  FogModel fog_;

  struct Scratch;
  struct Block;
  std::unique_ptr<Scratch> makeScratch() const;
  /// Casts columns [begin, end) of ring `ring` and works out their returns into the frame's
  /// slots; returns how many there are. castPulses() is the same for one ray a pulse, eight
  /// pulses at a time.
  std::size_t castPulses(const RayScene& scene, const RandomStream& random, std::uint64_t frame,
                         std::size_t ring, std::size_t begin, std::size_t end, Block& block,
                         Scratch& w) const;
  /// The random draws of columns [begin, end) of laser `laser`: range noise and dropout.
  void draw(const RandomStream& random, std::uint64_t frame, std::size_t laser, std::size_t begin,
            std::size_t end, Block& block) const;
  std::size_t castColumns(const RayScene& scene, const RandomStream& random, std::uint64_t frame,
                          std::size_t ring, std::size_t begin, std::size_t end, Block& block,
                          Scratch& w) const;
  mutable ObjectPool<Scratch> scratch_;  // one per frame scanned at once
  mutable ObjectPool<Block> blocks_;     // one per task running at once
};

}  // namespace trainsim::lidar
