// The run's general sections: `geodetic_origin`, `trajectory` and `dataset`.

#include "trainsim/sim/config.hpp"

namespace trainsim::sim {

const scenario::Section<GeodeticPoint>& geodeticOriginSection() {
  static const scenario::Section<GeodeticPoint> section = [] {
    scenario::Section<GeodeticPoint> s{
        "geodetic_origin",
        "Where the scenario's local frame sits on Earth. The world frame is ENU (x east, y "
        "north, z up) tangent to the WGS-84 ellipsoid at this point.",
        scenario::Binding<GeodeticPoint>(GeodeticPoint{43.7228, 10.3966, 50.0}),
        {}};
    auto& b = s.binding;
    const scenario::Unit deg = scenario::units::si("deg");  // stored in degrees, as given
    b.number("latitude_deg", &GeodeticPoint::latitude_deg, deg, "Geodetic latitude of the origin")
        .range(-90, 90);
    b.number("longitude_deg", &GeodeticPoint::longitude_deg, deg,
             "Geodetic longitude of the origin")
        .range(-180, 180);
    b.number("height_m", &GeodeticPoint::height_m, scenario::units::si("m"),
             "Ellipsoidal height of the origin")
        .range(-500, 9000);
    return s;
  }();
  return section;
}

const scenario::Section<TrajectoryConfig>& trajectorySection() {
  static const scenario::Section<TrajectoryConfig> section = [] {
    scenario::Section<TrajectoryConfig> s{
        "trajectory", "Ground-truth trajectory sampling (the movement system's clock).", {}, {}};
    s.binding
        .integer("sample_period_ns", &TrajectoryConfig::sample_period_ns, "ns",
                 "Trajectory sample period T_S; every sensor period is a multiple of it")
        .range(100'000, 1'000'000'000);
    using T = TrajectoryConfig;
    const scenario::Unit sec = scenario::units::si("s");
    constexpr double kWeek = 7 * 86400.0;
    s.binding
        .number("standstill_start_s", &T::standstill_start_s, sec,
                "The train stands at the start of the route this long before it departs (IMU "
                "alignment; hours for calibration and Allan-variance data)")
        .range(0, kWeek);
    s.binding
        .number("standstill_end_s", &T::standstill_end_s, sec,
                "The train stands this long where it stops at the end of the run")
        .range(0, kWeek);
    s.binding.boolean("static_only", &T::static_only,
                      "No run at all: the train stands at the start of the route for "
                      "standstill_start_s + standstill_end_s (static calibration data)");
    s.binding.check([](const T& t, const scenario::FieldPaths<T>& at,
                       std::vector<scenario::Problem>& out) {
      if (t.static_only && !(t.standstill_start_s + t.standstill_end_s > 0.0))
        out.push_back({at(t.standstill_start_s), "must be above 0 when " + at.key(t.static_only) +
                                                     " is true (the standstill is the run)"});
    });
    return s;
  }();
  return section;
}

std::string samplePeriodPath() {
  return trajectorySection().path(&TrajectoryConfig::sample_period_ns);
}

const scenario::Section<DatasetConfig>& datasetSection() {
  static const scenario::Section<DatasetConfig> section = [] {
    scenario::Section<DatasetConfig> s{
        "dataset", "Dataset layout and the frame clock of the visual sensors.", {}, {}};
    s.binding
        .integer("sequence", &DatasetConfig::sequence, "",
                 "KITTI sequence number: output goes to sequences/NN")
        .range(0, 99);
    s.binding
        .integer("frame_period_ns", &DatasetConfig::frame_period_ns, "ns",
                 "Period of dataset frames (times.txt, poses.txt, LiDAR scans, images)")
        .range(1'000'000, 60'000'000'000)
        .multipleOf(samplePeriodPath());
    return s;
  }();
  return section;
}

}  // namespace trainsim::sim
