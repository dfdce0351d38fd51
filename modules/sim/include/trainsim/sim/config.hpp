#pragma once

// The scenario's sections as the code runs on them: one typed struct per section, bound to
// its JSON declaration in one place (scenario/binding.hpp). The declarations live beside
// their bindings in modules/sim/src/sections/; the schema (schema.cpp) lists the sections in
// one table. Code reads a section with e.g. routeSection().read(scenario.json()) and names a
// field's JSON path with routeSection().path(&RouteConfig::source) — never by a string.

#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "trainsim/core/enum_names.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/core/time.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/scenario/binding.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/motion.hpp"
#include "trainsim/track/route_design.hpp"
#include "trainsim/track/vehicle.hpp"

namespace trainsim::sim {

/// Where the main track comes from.
enum class RouteSource { kGenerated, kWaypoints, kBlocks };
inline constexpr EnumName<RouteSource> kRouteSourceNames[] = {
    {RouteSource::kGenerated, "generated"},
    {RouteSource::kWaypoints, "waypoints"},
    {RouteSource::kBlocks, "blocks"}};
constexpr std::span<const EnumName<RouteSource>> enumNames(RouteSource) {
  return kRouteSourceNames;
}

/// `route`: where the main track comes from and how it is laid out.
struct RouteConfig {
  RouteSource source = RouteSource::kGenerated;
  std::string waypoints_file;  ///< absolute, or relative to the working directory once resolved
  track::WaypointParams waypoints;
  track::RouteOptions options;  ///< all but `rules`, which is the design section
  track::RouteGeneratorParams generator;
  std::vector<track::BlockSpec> blocks;
};

/// `train.body`: the lead vehicle's body as a box in body axes (origin midway between the bogie
/// pivots at top of rail), for what it hides from the LiDARs on it.
struct BodyConfig {
  bool enabled = true;
  double front_x_m = 10.0;  ///< the roof's front edge
  double length_m = 24.0;
  double width_m = 2.9;
  double roof_m = 3.8;  ///< above top of rail

  /// The box, in body axes.
  Eigen::AlignedBox3d box() const {
    return {Eigen::Vector3d(front_x_m - length_m, -0.5 * width_m, 0.0),
            Eigen::Vector3d(front_x_m, 0.5 * width_m, roof_m)};
  }
};

/// `train`: longitudinal limits, the body on its bogies, the reported point, dynamics.
struct TrainConfig {
  track::MotionLimits limits;
  track::VehicleGeometry vehicle;
  /// Body point whose pose the trajectory reports (body axes, m).
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();
  track::TrainDynamics dynamics;
  BodyConfig body;
  /// Brake to a stop obstacle_margin_m short of the first obstacle in the train's way (and end
  /// the run there) rather than run through it.
  bool stop_for_obstacles = true;
  double obstacle_margin_m = 20.0;
  /// The front of the train forward of the body origin: the body's front edge, or the front
  /// wheelset where that lies further forward.
  double frontX() const {
    return std::max(body.front_x_m, 0.5 * vehicle.bogie_spacing_m + 0.5 * vehicle.wheelbase_m);
  }
};

/// `trajectory`: the movement system's clock.
struct TrajectoryConfig {
  TimeNs sample_period_ns = 10'000'000;  ///< T_S
  double standstill_start_s = 0.0;       ///< at rest before departure
  double standstill_end_s = 0.0;         ///< at rest after arrival
  bool static_only = false;              ///< no run: at rest for the two standstills only
};

/// `dataset`: the KITTI sequence and the frame clock of the visual sensors.
struct DatasetConfig {
  int sequence = 0;
  TimeNs frame_period_ns = 100'000'000;
};

const scenario::Section<GeodeticPoint>& geodeticOriginSection();
/// "trajectory.sample_period_ns": the period every other period is a multiple of.
std::string samplePeriodPath();
const scenario::Section<TrajectoryConfig>& trajectorySection();
const scenario::Section<DatasetConfig>& datasetSection();
const scenario::Section<RouteConfig>& routeSection();
const scenario::Section<track::DesignRules>& designSection();
/// One item of route.blocks as JSON (the block binding's writer).
scenario::Json routeBlockJson(const track::BlockSpec& block);
const scenario::Section<track::LayoutParams>& layoutSection();
const scenario::Section<TrainConfig>& trainSection();
const scenario::Section<terrain::TerrainParams>& terrainSection();
const scenario::Section<environment::AssetParams>& assetsSection();
const scenario::Section<environment::ObjectParams>& objectsSection();

/// x_m, y_m, z_m of a body-axes position (train.reference_point, sensor mounts): within
/// 100 m forward or back and 10 m sideways and up or down.
template <typename T, typename Ref>
void bindBodyPosition(scenario::Binding<T>& b, Ref position) {
  constexpr double x_limit_m = 100.0, yz_limit_m = 10.0;
  const auto axis = [position](int i) {
    return [position, i](T& t) -> double& { return std::invoke(position, t)[i]; };
  };
  const scenario::Unit m = scenario::units::si("m");
  b.number("x_m", axis(0), m, "Forward").range(-x_limit_m, x_limit_m);
  b.number("y_m", axis(1), m, "Left").range(-yz_limit_m, yz_limit_m);
  b.number("z_m", axis(2), m, "Up").range(-yz_limit_m, yz_limit_m);
}

}  // namespace trainsim::sim
