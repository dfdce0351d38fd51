#pragma once
// Rotating multi-beam scan patterns: per-laser tables (elevation, azimuth offset, firing time)
// from public datasheets and driver calibration files (resources/lidars.json), or uniform.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace trainsim::lidar {

/// One laser of a rotating LiDAR, in the sensor frame (x forward, y left, z up).
struct Laser {
  double elevation_deg = 0.0;       ///< up from the xy plane
  double azimuth_offset_deg = 0.0;  ///< counter-clockwise seen from above, added to the column's
  double time_offset_s = 0.0;       ///< firing time after its column's start
  int ring = 0;                     ///< rank by elevation, 0 = the highest (KITTI, A-LOAM)
};

/// A rotating LiDAR's firing pattern. The head spins clockwise seen from above (as Velodyne and
/// Ouster heads do) at `rotation_hz`; a revolution has `columns` columns, column c starting at
/// c / (columns · rotation_hz) after the frame time, its azimuth 180° − 360° · c / columns (the
/// frame starts and ends looking backwards, the rear being the seam). Laser l of column c fires
/// time_offset_s later, while the head has turned on, so its ray's azimuth is
///   α = 180° − 360° · (c / columns + rotation_hz · time_offset_s) + azimuth_offset_deg.
struct ScanPattern {
  std::string name;
  std::vector<Laser> lasers;  ///< in firing order (laser id)
  int columns = 0;
  double rotation_hz = 10.0;
  double range_min_m = 0.9, range_max_m = 120.0;
  double range_sigma_m = 0.02;  ///< the datasheet's range accuracy, 1 σ
  /// A preset's whole firing sequence (the shortest column it can fire); 0 for uniform, whose
  /// lasers of a column fire together.
  double firing_period_s = 0.0;

  double columnPeriod() const { return 1.0 / (columns * rotation_hz); }
  double revolution() const { return 1.0 / rotation_hz; }
  /// The azimuth of laser l's ray in column c, degrees (not wrapped).
  double azimuthDeg(int column, int laser) const;
  /// The firing time of laser l in column c after the frame time, seconds.
  double firingTime(int column, int laser) const {
    return column * columnPeriod() + lasers[static_cast<std::size_t>(laser)].time_offset_s;
  }
  /// Lasers by ring: ringLasers()[r] is the laser with ring r.
  std::vector<int> ringLasers() const;
  /// Sets every laser's ring from the elevations (0 = highest; ties by laser id).
  void assignRings();
};

/// The preset names, in table order ("vlp16", "hdl32", "hdl64", "os1_64", "vlp32c").
std::vector<std::string> presetNames();
/// A preset's pattern; `columns` 0 takes the device's own count at `rotation_hz` (0: the
/// preset's rate): as many whole firing sequences as a revolution holds. Throws ConfigError for
/// an unknown name.
ScanPattern preset(std::string_view name, double rotation_hz = 0.0, int columns = 0);
/// A uniform pattern: `channels` lasers evenly from fov_up_deg down to fov_down_deg, all of a
/// column firing together, `columns` columns per revolution.
ScanPattern uniformPattern(int channels, double fov_up_deg, double fov_down_deg, int columns,
                           double rotation_hz);

}  // namespace trainsim::lidar
