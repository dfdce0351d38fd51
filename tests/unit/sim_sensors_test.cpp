// GNSS, odometer and balise reader on a planned route, through the real run stage
// (sim::generate): no fix in tunnels, the odometer's scale error, one balise event per balise
// at the exact passage time.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "trainsim/core/geodesy.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

namespace fs = std::filesystem;

std::vector<std::vector<std::string>> readCsv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> row;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ','))
      row.push_back(f);
    if (!line.empty() && line.back() == ',')
      row.emplace_back();
    rows.push_back(row);
  }
  return rows;
}

struct PlannedRun {
  scenario::Scenario scenario;
  std::unique_ptr<Plan> plan;
  fs::path out;
};

PlannedRun runScenario(const std::string& name, const scenario::Json& input) {
  PlannedRun r{scenario::Scenario::resolve(input, scenarioSchema()), nullptr,
               fs::temp_directory_path() / ("trainsim-sensors-" + name)};
  fs::remove_all(r.out);
  r.plan = makePlan(r.scenario);
  GenerateOptions options;
  options.out = r.out;
  generate(r.scenario, options);
  return r;
}

const scenario::Json kTunnels = {
    {"seed", 5},
    {"route",
     {{"generator",
       {{"length_m", 12000},
        {"tunnel", {{"probability", 0.4}, {"length_min_m", 300}, {"length_max_m", 800}}}}}}}};

TEST(Gnss, NoFixInTunnelsAndReacquisitionDelayAfterThem) {
  scenario::Json input = kTunnels;
  input["sensors"] = {{"gnss_receivers", {{{"period_ns", 100'000'000}}}}};
  const PlannedRun r = runScenario("gnss", input);
  const auto rows = readCsv(r.out / "sequences/00/gnss.csv");
  const TrainTrajectory& traj = r.plan->trajectory();
  const track::Route& route = r.plan->route().route;
  const GeodeticAnchor anchor({43.7228, 10.3966, 50.0});
  int tunnels = 0, outside_fix = 0, delayed = 0;
  // The antenna is above the body reference point, midway between the pivots.
  const auto antenna = [&](TimeNs t) { return traj.at(t).chainage_m - 17.5 / 2; };
  const auto in_tunnel = [&](double c) {
    const track::Block& b = route.blockAt(c);
    return b.type == track::BlockType::kTunnel && c >= b.chainage_begin_m && c <= b.chainage_end_m;
  };
  // An independent exit time: the last instant (to 1 us) the antenna was in the tunnel.
  const auto exit_time = [&](TimeNs t) {
    TimeNs lo = 0, hi = t;  // in the tunnel at lo (if ever), out since hi
    if (!in_tunnel(antenna(lo))) {
      // Search back for a tunnel, in 0.1 s steps (tunnels take seconds to pass).
      TimeNs back = t;
      while (back > 0 && !in_tunnel(antenna(back)))
        back -= 100'000'000;
      if (!in_tunnel(antenna(back)))
        return TimeNs{-1};
      lo = back;
    }
    while (hi - lo > 1000) {
      const TimeNs mid = lo + (hi - lo) / 2;
      (in_tunnel(antenna(mid)) ? lo : hi) = mid;
    }
    return lo;
  };
  double sum2 = 0;
  int n = 0;
  TimeNs last_exit = -1;
  bool was_in = false;
  for (const auto& row : rows) {
    const TimeNs t = std::stoll(row[0]);
    const TrajectorySample s = traj.sample(t / traj.samplePeriod());
    const bool tunnel = in_tunnel(antenna(t));
    const bool fix = row[1] == "1";
    if (tunnel) {
      ++tunnels;
      was_in = true;
      ASSERT_FALSE(fix) << "fix inside a tunnel at t = " << t;
      continue;
    }
    if (was_in) {
      last_exit = exit_time(t);
      was_in = false;
    }
    if (last_exit >= 0 && t - last_exit < 5'000'000'000 - 1000) {
      ASSERT_FALSE(fix) << "fix before the reacquisition delay at t = " << t;
      ++delayed;
    } else if (last_exit >= 0 && t - last_exit < 5'000'000'000 + 1000) {
      continue;  // within the bisection's microsecond of the boundary
    } else {
      ASSERT_TRUE(fix) << "no fix in the open at t = " << t << ", " << toSeconds(t - last_exit)
                       << " s after the tunnel exit";
      ++outside_fix;
      // Horizontal error against the true antenna position.
      const Eigen::Vector3d p = s.p_world + s.q_world_body * Eigen::Vector3d(0, 0, 4.0);
      const Eigen::Vector3d m =
          anchor.toEnu(GeodeticPoint{std::stod(row[2]), std::stod(row[3]), std::stod(row[4])});
      sum2 += (m - p).head<2>().squaredNorm();
      ++n;
    }
  }
  EXPECT_GT(delayed, 40);
  EXPECT_GT(tunnels, 10);
  EXPECT_GT(outside_fix, 100);
  // 1.5 m Gauss–Markov + 0.3 m white per axis: about 2.2 m horizontal RMS (loose: the
  // correlation time is long compared with the run).
  const double rms = std::sqrt(sum2 / n);
  EXPECT_GT(rms, 0.5);
  EXPECT_LT(rms, 6.0);
}

TEST(Odometer, DistanceErrorEqualsTheScaleError) {
  scenario::Json input = kTunnels;
  input["sensors"] = {{"odometers", {{{"scale_error", 0.012}, {"slip", {{"enabled", false}}}}}}};
  const PlannedRun r = runScenario("odometer", input);
  const auto rows = readCsv(r.out / "sequences/00/odometer.csv");
  const TrainTrajectory& traj = r.plan->trajectory();
  const double pulse = 3.141592653589793 * 0.92 / 200;
  const double u0 = traj.sample(0).distance_m;
  for (const auto& row : rows) {
    const TimeNs t = std::stoll(row[0]);
    const double truth = traj.sample(t / traj.samplePeriod()).distance_m - u0;
    const double measured = std::stod(row[2]);
    // Whole pulses of the encoder's (1 + ε)·s: the error is ε·s less under one pulse.
    ASSERT_LE(measured, 1.012 * truth + 1e-6);
    ASSERT_GT(measured, 1.012 * truth - pulse - 1e-6);
    ASSERT_EQ(row[4], "0");
  }
  EXPECT_GT(std::stod(rows.back()[2]), 10000.0);
}

TEST(Odometer, SlipAndSlideStartOnlyUnderHighAcceleration) {
  scenario::Json input = kTunnels;
  input["sensors"] = {{"odometers", {{{"slip", {{"rate_per_s", 2.0}}}}}}};
  const PlannedRun r = runScenario("slip", input);
  const auto rows = readCsv(r.out / "sequences/00/odometer.csv");
  const TrainTrajectory& traj = r.plan->trajectory();
  int starts = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i][4] != "0" && rows[i - 1][4] == "0") {
      ++starts;
      const double a = traj.sample(std::stoll(rows[i][0]) / traj.samplePeriod()).accel_m_s2;
      if (rows[i][4] == "1")
        EXPECT_GT(a, 0.5);
      else
        EXPECT_LT(a, -0.4);
    }
  }
  EXPECT_GT(starts, 0);
}

TEST(BaliseReader, OneEventPerBaliseAtTheExactPassageTime) {
  scenario::Json input = kTunnels;
  input["sensors"] = {{"balise_readers", {{{"detection_sigma_m", 0.0}}}}};
  const PlannedRun r = runScenario("balises", input);
  const auto rows = readCsv(r.out / "sequences/00/balises.csv");
  const TrainTrajectory& traj = r.plan->trajectory();
  const track::MotionProfile& motion = r.plan->motion();
  // Expected balises, re-derived from the placement rule: groups of two 3 m apart every
  // 1000 m from 200 m, plus a group 50 m before each station, ahead of the antenna at the start.
  const track::Route& route = r.plan->route().route;
  std::vector<double> groups;
  for (double u = 200; u + 6 < route.track.distanceLength(); u += 1000)
    groups.push_back(u);
  for (const track::Block& b : route.blocks)
    if (b.type == track::BlockType::kStation)
      groups.push_back(route.track.vertical().at(b.chainage_begin_m).distance_m - 50);
  std::vector<double> expected;
  const double start = traj.sample(0).distance_m + 2.0;
  const double end = traj.sample(traj.sampleCount() - 1).distance_m + 2.0;
  for (double g : groups)
    for (double u : {g, g + 3.0})
      if (u > start && u <= end)
        expected.push_back(u);
  std::sort(expected.begin(), expected.end());
  ASSERT_EQ(rows.size(), expected.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_NEAR(std::stod(rows[i][3]), expected[i], 1e-3);
    // The exact time the antenna (2 m ahead of the front pivot) reaches the balise.
    double lo = 0, hi = motion.duration();
    for (int k = 0; k < 100; ++k) {
      const double mid = 0.5 * (lo + hi);
      (motion.at(mid).u_m + 2.0 < expected[i] ? lo : hi) = mid;
    }
    EXPECT_NEAR(std::stoll(rows[i][0]) * 1e-9, hi, 1e-6) << "balise at " << expected[i];
  }
}

}  // namespace
}  // namespace trainsim::sim
