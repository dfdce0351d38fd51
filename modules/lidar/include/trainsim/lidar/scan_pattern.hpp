#pragma once
// Rotating multi-beam scan patterns: per-laser tables (elevation, azimuth offset, firing time)
// from public datasheets and driver calibration files (resources/lidars.json), or uniform.
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace trainsim::lidar {

/// One laser of a rotating LiDAR, in the sensor frame (x forward, y left, z up).
struct Laser {
  double elevation_deg = 0.0;       ///< up from the xy plane
  double azimuth_offset_deg = 0.0;  ///< counter-clockwise seen from above, added to the column's
  double time_offset_s = 0.0;       ///< firing time after its column's start
  int ring = 0;                     ///< rank by elevation, 0 = the highest (KITTI, A-LOAM)
  /// Where the beam leaves the head, as a Velodyne calibration gives it (vert_offset_correction
  /// and horiz_offset_correction): `vertical_offset_m` up across the beam, at right angles to
  /// it, and `horizontal_offset_m` to its left, level. A return at range r along the beam's
  /// direction d (elevation ω, azimuth α) lies at
  ///   r d + vertical_offset_m (−sin ω cos α, −sin ω sin α, cos ω) + horizontal_offset_m (−sin α,
  ///   cos α, 0),
  /// as the velodyne driver writes it (rawdata.cc).
  double vertical_offset_m = 0.0;
  double horizontal_offset_m = 0.0;
};

/// A rotating LiDAR's firing pattern. The head spins clockwise seen from above (as Velodyne and
/// Ouster heads do) at `rotation_hz`; a revolution has N = revolutionColumns() columns, column k
/// of the revolution starting at k / (N · rotation_hz) after the frame time, its azimuth
/// 180° − 360° · k / N (the frame starts and ends looking backwards, the rear being the seam).
/// The scan fires `columns` of them, from k = first_column on: all N, or those within an azimuth
/// window (windowed()). Laser l of scan column c (revolution column k = first_column + c) fires
/// time_offset_s later, while the head has turned on, so its ray's azimuth is
///   α = 180° − 360° · (k / N + rotation_hz · time_offset_s) + azimuth_offset_deg.
struct ScanPattern {
  std::string name;
  std::vector<Laser> lasers;  ///< in firing order (laser id)
  int columns = 0;            ///< columns a scan fires
  /// Columns a revolution holds (0: `columns`, a scan of the whole revolution) and the first a
  /// scan fires.
  int revolution_columns = 0, first_column = 0;
  double rotation_hz = 10.0;
  double range_min_m = 0.9, range_max_m = 120.0;
  double range_sigma_m = 0.02;  ///< the datasheet's range accuracy, 1 σ
  /// A preset's column period in its default mode (a Velodyne's whole firing sequence), which
  /// gives its columns at a spin rate when none are asked for; 0 for uniform, whose lasers of a
  /// column fire together.
  double firing_period_s = 0.0;
  /// The shortest column the device can fire (a Velodyne's firing sequence; an Ouster's fastest
  /// mode, 2048 columns at 10 Hz); 0 for uniform (no limit).
  double shortest_column_s = 0.0;
  /// The spin rates the device runs at: a Velodyne's range (0 ... 0: any), or an Ouster's modes,
  /// the (columns, Hz) pairs its firmware offers (empty: any columns the firing allows).
  double rotation_hz_min = 0.0, rotation_hz_max = 0.0;
  std::vector<std::pair<int, double>> modes;
  /// Where an Ouster's beams leave the head: `beam_origin_radius_m` out from the spin axis
  /// towards the column's azimuth (lidar_origin_to_beam_origin_mm) and `beam_origin_height_m`
  /// above the sensor frame's origin (lidar_to_sensor_transform's z), every beam alike.
  double beam_origin_radius_m = 0.0, beam_origin_height_m = 0.0;

  /// Whether any beam leaves the head off the sensor frame's origin.
  bool offsetBeams() const;

  int revolutionColumns() const { return revolution_columns > 0 ? revolution_columns : columns; }
  /// Whether the scan fires the whole revolution (no azimuth window).
  bool wholeRevolution() const { return columns == revolutionColumns(); }
  double columnPeriod() const { return 1.0 / (revolutionColumns() * rotation_hz); }
  double revolution() const { return 1.0 / rotation_hz; }
  /// The azimuth of laser l's ray in scan column c, degrees (not wrapped).
  double azimuthDeg(int column, int laser) const;
  /// Where the head points when laser l fires in scan column c: azimuthDeg() without the
  /// laser's own azimuth offset, degrees.
  double headAzimuthDeg(int column, int laser) const {
    return azimuthDeg(column, laser) - lasers[static_cast<std::size_t>(laser)].azimuth_offset_deg;
  }
  /// The firing time of scan column c after the frame time, seconds.
  double columnTime(int column) const { return (first_column + column) * columnPeriod(); }
  /// The firing time of laser l in scan column c after the frame time, seconds.
  double firingTime(int column, int laser) const {
    return columnTime(column) + lasers[static_cast<std::size_t>(laser)].time_offset_s;
  }
  /// Lasers by ring: ringLasers()[r] is the laser with ring r.
  std::vector<int> ringLasers() const;
  /// Sets every laser's ring from the elevations (0 = highest; ties by laser id).
  void assignRings();
};

/// The preset names, in table order ("vlp16", "hdl32", "hdl64", "os1_64", "vlp32c",
/// "os1_128").
std::vector<std::string> presetNames();
/// A preset's pattern; `columns` 0 takes the device's own count at `rotation_hz` (0: the
/// preset's rate): as many whole firing sequences as a revolution holds. Throws ConfigError for
/// an unknown name.
ScanPattern preset(std::string_view name, double rotation_hz = 0.0, int columns = 0);
/// `pattern` (a whole revolution) firing only within `fov_deg` of azimuth centred on the
/// sensor's x axis, as a Velodyne's FOV setting or an Ouster's azimuth window does: the columns
/// whose azimuth 180° − 360° · k / N lies within ±fov_deg / 2 (the lasers' own offsets turn their
/// rays a few degrees beyond). `fov_deg` 360 (or more) leaves the pattern as it is; a window too
/// narrow to hold a column leaves none (columns 0).
ScanPattern windowed(ScanPattern pattern, double fov_deg);
/// A uniform pattern: `channels` lasers evenly from fov_up_deg down to fov_down_deg, all of a
/// column firing together, `columns` columns per revolution.
ScanPattern uniformPattern(int channels, double fov_up_deg, double fov_down_deg, int columns,
                           double rotation_hz);

}  // namespace trainsim::lidar
