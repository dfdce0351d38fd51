#include "lidar_config.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "trainsim/core/error.hpp"

namespace trainsim::sim {
namespace {

namespace units = scenario::units;
constexpr scenario::Unit kM = units::si("m");

}  // namespace

std::string_view presetName(LidarModel m) {
  switch (m) {
    case LidarModel::kVlp16:
      return "vlp16";
    case LidarModel::kHdl32:
      return "hdl32";
    case LidarModel::kVlp32c:
      return "vlp32c";
    case LidarModel::kOs1_64:
      return "os1_64";
    case LidarModel::kOs1_128:
      return "os1_128";
    case LidarModel::kHdl64:
    case LidarModel::kUniform:
      break;
  }
  return "hdl64";
}

lidar::ScanPattern devicePattern(const LidarConfig& c) {
  constexpr int kUniformColumns = 2048;
  return lidar::windowed(
      c.model == LidarModel::kUniform
          ? lidar::uniformPattern(c.uniform.channels, c.uniform.fov_up_rad / kRadPerDeg,
                                  c.uniform.fov_down_rad / kRadPerDeg,
                                  c.columns > 0 ? c.columns : kUniformColumns, c.rotation_hz)
          : lidar::preset(presetName(c.model), c.rotation_hz, c.columns),
      c.horizontal_fov_rad / kRadPerDeg);
}

const scenario::Binding<LidarConfig>& lidarBinding() {
  static const scenario::Binding<UniformConfig> uniform = [] {
    scenario::Binding<UniformConfig> b;
    b.integer("channels", &UniformConfig::channels, "", "Lasers, evenly spaced in elevation")
        .range(1, 512);
    b.number("fov_up_deg", &UniformConfig::fov_up_rad, units::kDegree, "Highest laser's elevation")
        .range(-90, 90);
    b.number("fov_down_deg", &UniformConfig::fov_down_rad, units::kDegree,
             "Lowest laser's elevation")
        .range(-90, 90);
    b.check([](const UniformConfig& u, const scenario::FieldPaths<UniformConfig>& at,
               std::vector<scenario::Problem>& out) {
      if (u.fov_down_rad >= u.fov_up_rad)
        out.push_back({at(u.fov_down_rad), "must be below " + at.key(u.fov_up_rad)});
    });
    return b;
  }();
  static const scenario::Binding<LidarConfig> binding = [] {
    using C = LidarConfig;
    scenario::Binding<C> b;
    b.embed(&C::basics,
            sensorBasics({"<name>.csv (one row per scan) and the velodyne/labels/point_info "
                          "folders of its position in the list (velodyne, velodyne_1, …)",
                          10'000'000, 10'000'000'000,
                          "Scan period: one revolution is recorded every period_ns; it must equal "
                          "dataset.frame_period_ns (KITTI pairs every scan with a line of "
                          "times.txt and poses.txt)",
                          "Pose of the sensor's axes (x forward, y left, z up: KITTI's velodyne "
                          "frame); the default is the cab roof"}));
    b.choice("model", &C::model,
             "Scan pattern: Velodyne HDL-64E S3, VLP-16, HDL-32E, VLP-32C, Ouster OS1-64 or "
             "OS1-128 from their calibration tables (resources/lidars.json: each laser's angles, "
             "firing time and where its beam leaves the head, in the frame the device's driver "
             "writes points in: an HDL-64E's beams start 0.14-0.22 m above its origin, an OS1's "
             "36 mm above and 16 mm out, and ranges are measured from there), or uniform (the "
             "fields under uniform; every beam from the origin)");
    b.number("rotation_hz", &C::rotation_hz, units::si("Hz"),
             "Spin rate; one revolution must fit in period_ns. A Velodyne spins at 5 ... 20 Hz, "
             "an Ouster at 10 or 20 Hz (its modes)")
        .range(1, 40);
    b.integer("columns", &C::columns, "",
              "Firings per revolution; 0: the device's own at this spin rate (2083 for the "
              "HDL-64E and 1024 for an OS1 at 10 Hz, 512 at 20 Hz), 2048 for uniform. At most as "
              "many as the device fires: a Velodyne's whole firing sequence a column (1808 for "
              "the VLP-16 at 10 Hz); an OS1 one of its modes (512, 1024 or 2048 columns at "
              "10 Hz, 512 or 1024 at 20 Hz)")
        .range(0, 65535);
    b.number("horizontal_fov_deg", &C::horizontal_fov_rad, units::kDegree,
             "Azimuth window centred forward: the head spins the whole revolution and fires only "
             "the columns within it (a Velodyne's FOV setting, an Ouster's azimuth_window), "
             "at their times in the revolution; 360: all")
        .range(1, 360);
    b.object("uniform", &C::uniform, uniform, "The uniform pattern (model \"uniform\")");
    b.number("range_min_m", &C::range_min_m, kM,
             "Shortest range (a surface nearer still blocks the beam, and returns nothing); 0: "
             "the device's (0.9 m for uniform)")
        .range(0, 100);
    b.number("range_max_m", &C::range_max_m, kM,
             "Longest range; 0: the device's (120 m for uniform)")
        .range(0, 2000);
    b.number("range_sigma_m", &C::range_sigma_m, kM,
             "Gaussian range noise, 1 sigma; -1: the device's datasheet value (VLP-16 and VLP-32C "
             "0.03 m, HDL-32E and HDL-64E 0.02 m, OS1-64 and OS1-128 0.015 m; 0.02 m for uniform)",
             scenario::Sentinel{-1.0, -1.0})
        .range(-1, 1);
    b.number("range_sigma_per_m", &C::range_sigma_per_m, units::si("m/m"),
             "Range noise growing with range: sigma = range_sigma_m + this * range")
        .range(0, 0.1);
    b.number("dropout", &C::dropout, units::kNone, "Probability that a return is lost").range(0, 1);
    b.number("intensity_threshold", &C::intensity_threshold, units::kNone,
             "Returns whose reflectivity is below this are lost")
        .range(0, 10);
    b.number("range_10_percent_m", &C::range_10_percent_m, kM,
             "How far a 10 % Lambertian target at normal incidence is detected (the OS1 "
             "datasheet: 40 m, and 120 m at 80 %): received power falls as reflectivity / R^2, so "
             "a return of reflectivity rho (the Lambertian-Beckmann backscatter at its incidence, "
             "times the share of the beam's footprint it covers) is lost beyond "
             "range_10_percent_m * sqrt(rho / 0.1): dark ground at a grazing angle fades first; "
             "0: every return within range_max_m")
        .range(0, 2000);
    b.choice("intensity", &C::intensity,
             "reflectivity: Lambertian-Beckmann backscatter of the material at its incidence "
             "(calibrated, as Velodyne reports it); raw: the same falling as 1/R^2, equal at 10 m");
    b.choice("intensity_scale", &C::scale,
             "unit: float 0..1 (KITTI); vlp16: Velodyne's 0..100 diffuse, 101..255 "
             "retro-reflectors");
    b.boolean("motion_distortion", &C::motion_distortion,
              "Cast each column of firings from the pose at its firing time (a spinning sensor "
              "on a moving train; its lasers' offsets within the column, under 40 µs, are not "
              "moved for: 1.8 mm at 160 km/h); false: the whole scan from the pose at the "
              "scan's start");
    b.boolean("motion_compensated", &C::motion_compensated,
              "velodyne/*.bin in the sensor frame at the scan's start (deskewed: KITTI odometry "
              "and ground truth); false: each point in the sensor frame at its firing (as the "
              "sensor measures, for pipelines that deskew)");
    b.integer("sub_rays", &C::sub_rays, "",
              "Rays per pulse spread over the beam's footprint (beam divergence): thin wires and "
              "edges give partial, fainter echoes, and a pulse can return two; 1: one ray along "
              "the beam's axis. More sub-rays sample the footprint's rim better (a 12 mm wire at "
              "30 m: 94 % of the predicted hit rate with 64, 99 % with 256) and cost as many "
              "rays")
        .range(1, 1024);
    b.number("beam_divergence_mrad", &C::divergence_rad, units::kMilliradian,
             "Full angle of the beam's footprint (VLP-16 2.25 mrad, OS1 2.3 mrad FWHM; "
             "sensors-reference.md 1)")
        .range(0, 50);
    b.number("echo_separation_m", &C::echo_separation_m, kM,
             "Sub-ray hits further apart in range than this are separate echoes, unless they "
             "lie on one surface (the plane through one hit with its normal meets the other's "
             "ray within this): ground or a wall at a grazing angle is one stretched echo")
        .range(0.01, 100);
    b.choice("returns", &C::returns,
             "Echoes a pulse reports: strongest (received power), last, or dual (both; one "
             "point when they are the same echo). point_info's return index is 0 for the strongest "
             "(or the only) return, 1 for the last of a dual pair");
    b.number("fog_visibility_m", &C::fog_visibility_m, kM,
             "Meteorological visibility of fog at the train (2 % contrast, Koschmieder: "
             "extinction 3.912 / visibility), in the cameras' layer (fog_height_m): every echo "
             "is dimmed by its two-way transmission, so far and dark surfaces fade first, and "
             "the fog's own backscatter returns an echo a few metres out, class fog (after "
             "Rasshofer et al. 2011 and Hahner et al. 2021: a 20 ns pulse, 0.046 / MOR "
             "backscatter). With returns strongest, thick fog hides all but near, bright "
             "surfaces behind its echo; last and dual still report the surfaces the fog lets be "
             "detected (range_10_percent_m sets how faint that is). Every pulse then takes the "
             "path that weighs several echoes, one ray at a time: about twice a clear frame's "
             "time; 0: clear")
        .range(0, 100000);
    b.number("fog_height_m", &C::fog_height_m, kM,
             "The fog's scale height: its extinction falls by e for every this many metres "
             "above the sensor (and stays the visibility's below it), as the cameras' "
             "fog_height_m")
        .range(1, 100000);
    b.number("fog_overlap_m", &C::fog_overlap_m, kM,
             "Range from which the receiver sees the whole beam (its overlap with the beam "
             "rises linearly from 0.9 m to here): the fog's echo comes mostly from its first "
             "metres, so this sets how strong it is. Default [unverified per device]: Hahner "
             "et al. note most sensors reach full overlap within 10 m and use 1 m, with which "
             "an HDL-64E's sky returns fog even in 1 km of visibility")
        .range(1, 100);
    b.boolean("point_info", &C::point_info,
              "Write point_info/*.bin: per point firing time, range, ring, return index, "
              "material");
    b.boolean("pcd", &C::pcd,
              "Also write each scan as pcd/NNNNNN.pcd through PCL (binary PCD v0.7; fields x y "
              "z intensity ring time label, the label as in labels/*.label), for PCL, Open3D, "
              "CloudCompare and ROS tools");
    b.check([](const C& c, const scenario::FieldPaths<C>& at, std::vector<scenario::Problem>& out) {
      if (c.basics.period_ns * c.rotation_hz < 1e9 * (1.0 - 1e-12))
        out.push_back({at(c.rotation_hz), "is too slow: one revolution must fit in period_ns"});
      if (c.range_sigma_m < 0.0 && c.range_sigma_m != -1.0)
        out.push_back({at(c.range_sigma_m), "must be -1 (the device's) or 0 ... 1"});
      // The limits as the sensor will have them: a 0 stands for the device's own value, and a
      // limit set against the device's other one can leave no range at all.
      const lidar::ScanPattern device = devicePattern(c);
      const double near = c.range_min_m > 0.0 ? c.range_min_m : device.range_min_m;
      const double far = c.range_max_m > 0.0 ? c.range_max_m : device.range_max_m;
      if (c.range_min_m > 0.0 && c.range_max_m > 0.0 && near >= far)
        out.push_back({at(c.range_min_m), "must be below " + at.key(c.range_max_m)});
      else if (near >= far)
        out.push_back({at(c.range_max_m > 0.0 ? c.range_max_m : c.range_min_m),
                       fmt::format("leaves no range: shortest {} m, longest {} m (0 takes the "
                                   "device's own: {} ... {} m)",
                                   near, far, device.range_min_m, device.range_max_m)});
      // The spin rates the device runs at, and an Ouster's (columns, rate) modes.
      if (device.rotation_hz_max > 0.0 &&
          !(c.rotation_hz >= device.rotation_hz_min && c.rotation_hz <= device.rotation_hz_max))
        out.push_back(
            {at(c.rotation_hz),
             fmt::format("{:g} Hz is outside the {}'s {:g} ... {:g} Hz ({:g} ... {:g} "
                         "rpm)",
                         c.rotation_hz, device.name, device.rotation_hz_min, device.rotation_hz_max,
                         60.0 * device.rotation_hz_min, 60.0 * device.rotation_hz_max)});
      const std::string modes =
          fmt::format("{}", fmt::join(device.modes | std::views::transform([](const auto& m) {
                                        return fmt::format("{} x {:g} Hz", m.first, m.second);
                                      }),
                                      ", "));
      const auto runs = [&](int columns) {
        return std::ranges::any_of(device.modes, [&](const auto& m) {
          return m.second == c.rotation_hz && (columns == 0 || m.first == columns);
        });
      };
      if (!device.modes.empty() && !runs(0))
        out.push_back({at(c.rotation_hz), fmt::format("{:g} Hz is not a rate the {} spins at (its "
                                                      "modes: {})",
                                                      c.rotation_hz, device.name, modes)});
      else if (!device.modes.empty() && !runs(c.columns))
        out.push_back(
            {at(c.columns), fmt::format("{} columns at {:g} Hz is not one of the {}'s modes ({})",
                                        c.columns, c.rotation_hz, device.name, modes)});
      // A column can be no shorter than the device fires one (a Velodyne's firing sequence).
      if (device.modes.empty() && c.columns > 0 && device.shortest_column_s > 0.0 &&
          1.0 / (c.columns * c.rotation_hz) < device.shortest_column_s * (1.0 - 1e-9))
        out.push_back(
            {at(c.columns),
             fmt::format("is more than the {} can fire at {} Hz: {} columns leave {:.2f} us a "
                         "column, shorter than the {:.3f} us it needs for one (at most {})",
                         device.name, c.rotation_hz, c.columns, 1e6 / (c.columns * c.rotation_hz),
                         device.shortest_column_s * 1e6,
                         static_cast<int>(std::floor(
                             1.0 / (device.shortest_column_s * c.rotation_hz) * (1.0 + 1e-9))))});
      if (device.columns < 1)
        out.push_back(
            {at(c.horizontal_fov_rad),
             fmt::format("holds no column: the {} columns a revolution are {:.3g} deg "
                         "apart",
                         device.revolutionColumns(), 360.0 / device.revolutionColumns())});
      // Each field has its range; their product is bounded too, so that a scan fits in memory
      // (32 bytes a return slot) and in a run: 2^22 pulses is 8 × an OS1-64 at 2048 columns,
      // 2^28 rays every preset with 1024 sub-rays a pulse (about two minutes a scan here).
      constexpr double kMaxPulses = 1 << 22, kMaxRays = 1 << 28;
      const double pulses = static_cast<double>(device.columns) * device.lasers.size();
      if (pulses > kMaxPulses)
        out.push_back({at(c.columns),
                       fmt::format("gives {:.0f} pulses a scan ({} columns × {} lasers): at most "
                                   "{:.0f}",
                                   pulses, device.columns, device.lasers.size(), kMaxPulses)});
      else if (pulses * c.sub_rays > kMaxRays)
        out.push_back(
            {at(c.sub_rays), fmt::format("gives {:.0f} rays a scan ({} columns × {} lasers × {} "
                                         "sub-rays): at most {:.0f}",
                                         pulses * c.sub_rays, device.columns, device.lasers.size(),
                                         c.sub_rays, kMaxRays)});
    });
    return b;
  }();
  return binding;
}

Eigen::Isometry3d bodyFromSensor(const Mount& mount) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = mount.r_body_sensor * rotationBodyFromKittiVelodyne();
  T.translation() = mount.position_m;
  return T;
}

Eigen::Isometry3d poseOnBody(const Mount& mount, const TrainConfig& train) {
  Eigen::Isometry3d T = bodyFromSensor(mount);
  T.translation() += train.reference_point;
  return T;
}
std::string insideTheBody(const Eigen::Isometry3d& pose, const lidar::ScanPattern& pattern,
                          const TrainConfig& train) {
  if (!train.body.enabled || lidar::beamsLeaveOutside(pattern, pose, train.body.box()))
    return {};
  return "the LiDAR's beams leave its head inside the train's body (train.body): mount it above "
         "train.body.roof_m or ahead of train.body.front_x_m, or set train.body.enabled false";
}

lidar::LidarParams scannerParams(const LidarConfig& c, const TrainConfig& train,
                                 const std::string& path) {
  lidar::LidarParams p;
  p.pattern = devicePattern(c);
  if (train.body.enabled) {
    const Eigen::Isometry3d pose = poseOnBody(c.basics.mount.mount(), train);
    if (const std::string why = insideTheBody(pose, p.pattern, train); !why.empty())
      throw ConfigError(fmt::format("{}: {}", mountPath(path), why));
    p.vehicle = lidar::LidarParams::Vehicle{train.body.box(), pose};
  }
  if (c.range_min_m > 0.0)
    p.pattern.range_min_m = c.range_min_m;
  if (c.range_max_m > 0.0)
    p.pattern.range_max_m = c.range_max_m;
  p.range_sigma_m = c.range_sigma_m < 0.0 ? p.pattern.range_sigma_m : c.range_sigma_m;
  p.range_sigma_slope = c.range_sigma_per_m;
  p.dropout = c.dropout;
  p.intensity_threshold = c.intensity_threshold;
  p.range_10_percent_m = c.range_10_percent_m;
  p.scale = c.scale == IntensityScaleName::kVlp16 ? lidar::IntensityScale::kVlp16
                                                  : lidar::IntensityScale::kUnit;
  p.range_falloff = c.intensity == IntensityQuantity::kRaw;
  p.motion_distortion = c.motion_distortion;
  p.motion_compensated = c.motion_compensated;
  p.sub_rays = c.sub_rays;
  p.divergence_rad = c.divergence_rad;
  p.echo_separation_m = c.echo_separation_m;
  p.fog.visibility_m = c.fog_visibility_m;
  p.fog.height_m = c.fog_height_m;
  p.fog.overlap_full_m = c.fog_overlap_m;
  p.returns = c.returns == ReturnMode::kDual   ? lidar::LidarParams::Returns::kDual
              : c.returns == ReturnMode::kLast ? lidar::LidarParams::Returns::kLast
                                               : lidar::LidarParams::Returns::kStrongest;
  return p;
}

std::vector<std::string> lidarWarnings(const LidarConfig& c, const std::string& path) {
  std::vector<std::string> out;
  // One ray a pulse has one echo: dual returns need the beam's footprint sampled. Valid (the
  // files are those of strongest), but not what was asked for.
  if (c.returns == ReturnMode::kDual && c.sub_rays == 1)
    out.push_back(
        fmt::format("{}: returns is dual but sub_rays is 1: one ray a pulse has one echo, "
                    "so every pulse gives one point, as strongest would; set sub_rays (16 "
                    "or more) and beam_divergence_mrad for second echoes",
                    path));
  if (c.sub_rays > 1 && c.divergence_rad == 0.0)
    out.push_back(
        fmt::format("{}: sub_rays is {} but beam_divergence_mrad is 0: every sub-ray is the "
                    "beam's axis, {} times the rays for the points one ray gives",
                    path, c.sub_rays, c.sub_rays));
  if (c.model == LidarModel::kUniform && c.uniform.channels == 1)
    out.push_back(
        fmt::format("{}: uniform.channels is 1: its one laser is at fov_up_deg ({} deg) and "
                    "fov_down_deg is not used",
                    path, c.uniform.fov_up_rad / kRadPerDeg));
  if (c.fog_visibility_m > 0.0 && c.range_10_percent_m == 0.0)
    out.push_back(
        fmt::format("{}: fog_visibility_m is set but range_10_percent_m is 0: a sensor that "
                    "detects every echo however faint returns the fog's own echo on every pulse "
                    "that meets nothing nearer; set range_10_percent_m (the OS1 datasheet: 40 m)",
                    path));
  if (const double device = devicePattern(c).range_max_m;
      c.model != LidarModel::kUniform && c.range_max_m > device)
    out.push_back(
        fmt::format("{}: range_max_m {} m is beyond the {}'s {} m (its datasheet's range): "
                    "returns that far are more than the device gives",
                    path, c.range_max_m, presetName(c.model), device));
  if (const double device = devicePattern(c).range_min_m;
      c.model != LidarModel::kUniform && c.range_min_m > 0.0 && c.range_min_m < device)
    out.push_back(
        fmt::format("{}: range_min_m {} m is below the {}'s {} m (its datasheet's shortest "
                    "range): returns that near are more than the device gives",
                    path, c.range_min_m, presetName(c.model), device));
  return out;
}

}  // namespace trainsim::sim
