#pragma once
// Odometry metrics of an estimated trajectory against the ground truth, both in KITTI's poses
// format: the KITTI odometry devkit's segment errors (evaluate_odometry.cpp, the benchmark's
// method) and the TrainSim paper's frame-to-frame translation errors TEX and TEY and its error
// over distance EOD (docs/REFERENCES.md). What `trainsim evaluate` reports.
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace trainsim::evaluation {

/// Poses as read, in general affine form: an estimate's rotations are orthonormal only to the
/// digits it was printed with, so poses are inverted as matrices, as the devkit does.
using Pose = Eigen::Affine3d;
using Poses = std::vector<Pose>;

/// Reads a KITTI poses file (poses.txt, or an odometry pipeline's result): one pose per line,
/// the top three rows of its 4 × 4 matrix row by row, 12 numbers. Throws ConfigError naming the
/// file and line for anything else: a missing or unreadable file, a line without exactly 12
/// finite numbers, a rotation that is not one (|RᵀR − I| > 1e-3 or a reflection), an empty
/// line before the last, no pose at all, a file over 1 GiB.
Poses readKittiPoses(const std::filesystem::path& path);

/// A KITTI times.txt: one time in seconds per line, rising from line to line. ConfigError
/// naming the file and line for anything else (the same rules as readKittiPoses).
std::vector<double> readKittiTimes(const std::filesystem::path& path);

/// KITTI's `Tr` (velodyne → camera 0: p_cam = Tr · p_velo) from a calib.txt. ConfigError naming
/// the file when it has no `Tr:` line of 12 numbers with a rotation in it.
Pose readKittiTr(const std::filesystem::path& calib);

/// Camera-0 poses as poses.txt holds them (KITTI camera axes: x right, y down, z forward) as
/// poses in axes x forward, y left, z up relative to the first pose. With a calib.txt's Tr they
/// are the velodyne's poses, Tr⁻¹ · C_k · Tr, exactly as KITTI's LiDAR odometry pipelines turn
/// them; without one the camera's own motion with its axes renamed (the camera's offset and
/// tilt on the vehicle are then not taken out).
Poses vehicleAxes(const Poses& camera_poses, const Pose* tr = nullptr);

/// One segment of the devkit: from `first` to the first frame whose ground-truth path length
/// exceeds the first's by more than `length_m`; its errors per metre of segment length.
struct Segment {
  std::size_t first = 0;
  std::size_t last = 0;
  double length_m = 0.0;
  double translation = 0.0;   ///< |t(E)| / length, E = (Δestimate)⁻¹ · Δground truth
  double rotation_rad = 0.0;  ///< angle(E) / length, rad per metre
  double speed_m_s = 0.0;     ///< the ground truth's path over the time it took (with times)
};

/// The devkit's segments: starts every `step` frames, every length of `lengths_m` that the
/// sequence is long enough for. `gt` and `est` must have the same size, and `times` (seconds
/// per frame) too when given: then each segment has its speed.
std::vector<Segment> kittiSegments(const Poses& gt, const Poses& est,
                                   std::span<const double> lengths_m, std::size_t step = 10,
                                   std::span<const double> times = {});

/// Count, mean, standard deviation (population) and largest value.
struct Stats {
  std::size_t count = 0;
  double mean = 0.0;
  double stddev = 0.0;
  double max = 0.0;
};
Stats statsOf(std::span<const double> values);

/// The TrainSim paper's metrics, per frame, from poses in vehicle axes (vehicleAxes()):
/// TEX and TEY, the error of the translation between consecutive frames along x (forward) and
/// y (left) of the earlier frame, |Δt_est − Δt_gt| per axis in metres; EOD, the position error
/// in the x–y plane of the first frame over the ground truth's path length so far, in per cent,
/// for frames at least `eod_from_m` along the path (the ratio is meaningless near the start).
struct FrameErrors {
  std::vector<double> tex_m, tey_m, eod_percent;
};
FrameErrors frameErrors(const Poses& gt, const Poses& est, double eod_from_m = 10.0);

/// Everything `trainsim evaluate` reports.
struct Report {
  std::size_t frames = 0;
  double path_m = 0.0;  ///< the ground truth's path length
  std::size_t step = 10;
  struct Length {
    double length_m = 0.0;
    std::size_t segments = 0;
    double translation_percent = 0.0;
    double rotation_deg_per_m = 0.0;
  };
  std::vector<Length> lengths;  ///< per segment length
  Length all;                   ///< over every segment (length_m = 0): the devkit's summary
  /// With times: the segments of every length by their speed, in bins of `speed_bin_m_s` from
  /// 0 (only bins that hold a segment). The devkit plots errors against speed too, taking 10 Hz
  /// frames; a train's speeds and frame times are read from times.txt instead.
  struct Speed {
    double from_m_s = 0.0, to_m_s = 0.0;
    Length errors;  ///< length_m = 0
  };
  std::vector<Speed> speeds;
  double speed_bin_m_s = 0.0;  ///< 0: no times, no speed table
  Stats tex_m, tey_m, eod_percent;
  double eod_from_m = 10.0;
  bool velodyne_axes = false;  ///< TEX/TEY/EOD in the velodyne's axes (a calib.txt was given)
                               ///< or camera 0's renamed
};

struct EvaluateOptions {
  std::vector<double> lengths_m = {100, 200, 300, 400, 500, 600, 700, 800};  // the devkit's
  std::size_t step = 10;
  double eod_from_m = 10.0;
  const Pose* tr = nullptr;       ///< a calib.txt's Tr, or none
  std::span<const double> times;  ///< a times.txt (seconds per frame), or none
  double speed_bin_m_s = 5.0;     ///< the speed table's bins (18 km/h)
};

/// The report of `est` against `gt` (KITTI camera-0 poses, one per frame). ConfigError when
/// they (or the times) differ in length, hold fewer than two poses, or an option is out of its
/// range.
Report evaluate(const Poses& gt, const Poses& est, const EvaluateOptions& options = {});

/// The report as Markdown tables, and as one JSON object.
std::string markdown(const Report& report);
std::string json(const Report& report);

}  // namespace trainsim::evaluation
