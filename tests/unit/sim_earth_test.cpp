// The route on the Earth, end to end through the plan: a level 100 km straight keeps its
// ellipsoidal height and an IMU on it at constant speed feels no along-track force; a route
// given in latitude/longitude/height at constant height is run at that height.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "trainsim/core/geodesy.hpp"
#include "trainsim/inertial/earth.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

std::unique_ptr<Plan> planFor(const scenario::Json& input) {
  return makePlan(scenario::Scenario::resolve(input, scenarioSchema()));
}

TEST(RouteOnEarth, LevelStraightKeepsItsHeightAndAnImuFeelsNoAlongTrackForce) {
  const scenario::Json none = {{"probability", 0.0}};
  const std::unique_ptr<Plan> plan =
      planFor({{"route",
                {{"station_stops", false},
                 {"generator",
                  {{"length_m", 100'000},
                   {"curve_share", 0.0},
                   {"grade_max_permille", 0.0},
                   {"station", none},
                   {"tunnel", none},
                   {"bridge", none}}}}},
               {"layout", {{"double_track", false}, {"auxiliary", {{"probability", 0.0}}}}}});
  const GeodeticPoint origin{43.7228, 10.3966, 50.0};
  const GeodeticAnchor anchor(origin);
  const inertial::Earth earth(origin, true);
  const TrainTrajectory& traj = plan->trajectory();
  int cruising = 0;
  double worst_f = 0.0, worst_h = 0.0;
  for (TimeNs t = 0; t <= traj.endTime(); t += 5'000'000'000) {
    const TrajectorySample s = traj.at(t);
    worst_h = std::max(worst_h, std::abs(anchor.fromEnu(s.p_world).height_m - 50.0));
    if (std::abs(s.accel_m_s2) > 0.0 || s.speed_m_s < 10.0)
      continue;
    ++cruising;
    inertial::MountKinematics m;
    m.p_world = s.p_world;
    m.v_world = s.v_world;
    m.a_world = s.a_world;
    m.r_world_sensor = s.q_world_body.toRotationMatrix();
    m.w_sensor = s.w_body;
    const inertial::ImuTruth f = inertial::imuTruth(earth, m);
    worst_f = std::max(worst_f, std::abs(f.specific_force.x()));
  }
  EXPECT_GT(cruising, 300);
  EXPECT_LT(worst_h, 1e-3);
  // Only the Coriolis force's along-track part remains: 2 Ω v sin(...) is across the track
  // for a train running east or west, and below 1e-5 along it here.
  EXPECT_LT(worst_f, 1e-5);
  const double length = plan->route().route.track.length();
  EXPECT_NEAR(length, 100'000.0, 1e-6 * 100'000.0);
}

TEST(RouteOnEarth, LatitudeLongitudeRouteRunsAtItsGivenHeight) {
  const GeodeticPoint origin{43.7228, 10.3966, 50.0};
  const GeodeticAnchor anchor(origin);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "trainsim-earth-waypoints.csv";
  {
    std::ofstream out(file);
    out << "latitude_deg,longitude_deg,height_m\n";
    for (const Eigen::Vector2d& en :
         {Eigen::Vector2d(0, 0), Eigen::Vector2d(20'000, 3'000), Eigen::Vector2d(45'000, -4'000)}) {
      const GeodeticPoint p = anchor.fromAzimuthalEquidistant(en, 50.0);
      out << fmt::format("{:.12f},{:.12f},50\n", p.latitude_deg, p.longitude_deg);
    }
  }
  const std::unique_ptr<Plan> plan =
      planFor({{"route", {{"source", "waypoints"}, {"waypoints_file", file.string()}}},
               {"layout", {{"double_track", false}, {"auxiliary", {{"probability", 0.0}}}}}});
  const TrainTrajectory& traj = plan->trajectory();
  double worst = 0.0;
  int n = 0;
  for (TimeNs t = 0; t <= traj.endTime(); t += 2'000'000'000, ++n) {
    const track::BodyState b = traj.body(traj.motionAt(t));
    worst = std::max(worst, std::abs(anchor.fromEnu(b.front).height_m - 50.0));
  }
  std::filesystem::remove(file);
  EXPECT_GT(n, 100);
  EXPECT_LT(worst, 1e-3);
}

}  // namespace
}  // namespace trainsim::sim
