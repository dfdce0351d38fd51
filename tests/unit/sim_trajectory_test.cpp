// The sampled trajectory of a planned scenario (sim::TrainTrajectory): finite differences of
// the sampled position of an off-centre body point match its sampled velocity, and those of the
// velocity its acceleration, within bounds derived from the samples themselves:
//  - where x is smooth, the central difference errs by T²/6·|x'''|;
//  - where x'' steps by Δ (ends of vertical curves; ends of Bloss cant ramps, where the roll
//    acceleration steps and a lever arm turns it into a linear one), it errs by T·Δ/4.
// With x''' estimated as the central difference of the sampled x'' (which reads Δ/(2T) at a
// step), T²/2·max|est x'''| covers both. The same one level up bounds the acceleration check,
// with T²·max|est x''''| (a step Δ in a gives an error Δ/2 and an estimate Δ/T²).
#include <gtest/gtest.h>

#include <array>
#include <sstream>

#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/geodesy.hpp"

#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

std::unique_ptr<Plan> planFor(const scenario::Json& input) {
  return makePlan(scenario::Scenario::resolve(input, scenarioSchema()));
}

TEST(TrainTrajectory, SampledReferencePointIsConsistentToSecondOrder) {
  const scenario::Json input = {
      {"route", {{"transition_shape", "bloss"}, {"generator", {{"length_m", 5000}}}}},
      {"train", {{"reference_point", {{"x_m", 6.0}, {"y_m", 0.7}, {"z_m", 3.2}}}}}};
  const std::unique_ptr<Plan> plan = planFor(input);
  const TrainTrajectory& traj = plan->trajectory();
  const double T = toSeconds(traj.samplePeriod());
  const std::int64_t n = traj.sampleCount();
  ASSERT_GT(n, 1000);
  std::vector<TrajectorySample> s(static_cast<std::size_t>(n));
  for (std::int64_t k = 0; k < n; ++k)
    s[static_cast<std::size_t>(k)] = traj.sample(k);
  auto at = [&](std::int64_t k) -> const TrajectorySample& {
    return s[static_cast<std::size_t>(k)];
  };
  double worst_v = 0, worst_a = 0;
  for (std::int64_t k = 3; k + 3 < n; ++k) {
    // |ȧ| and |ä| around k from the sampled accelerations.
    double jerk = 0, snap = 0;
    for (std::int64_t j = k - 2; j <= k + 2; ++j) {
      jerk = std::max(jerk, (at(j + 1).a_world - at(j - 1).a_world).norm() / (2 * T));
      snap = std::max(snap,
                      (at(j + 1).a_world - 2 * at(j).a_world + at(j - 1).a_world).norm() / (T * T));
    }
    const Eigen::Vector3d fd_v = (at(k + 1).p_world - at(k - 1).p_world) / (2 * T);
    const Eigen::Vector3d fd_a = (at(k + 1).v_world - at(k - 1).v_world) / (2 * T);
    const double ev = (fd_v - at(k).v_world).norm();
    const double ea = (fd_a - at(k).a_world).norm();
    // Position rounding: world positions are differences of Earth-centred coordinates
    // (6.4e6 m), good to a few 1e-9 m, over 2T.
    ASSERT_LE(ev, T * T / 2 * jerk + 5e-9 / (2 * T)) << "sample " << k;
    ASSERT_LE(ea, T * T * snap + 1e-8) << "sample " << k;
    worst_v = std::max(worst_v, ev);
    worst_a = std::max(worst_a, ea);
  }
  EXPECT_GT(worst_v, 0.0);
  EXPECT_GT(worst_a, 0.0);
  // And the speed is the along-track speed of the front pivot, bounded by the limit in force.
  for (std::int64_t k = 0; k < n; ++k)
    ASSERT_LE(at(k).speed_m_s, plan->motion().limit().at(traj.motion(k).u_m) + 1e-9);
}

TEST(TrainTrajectory, EndsAtRestAndTimesAreExact) {
  const std::unique_ptr<Plan> plan = planFor(scenario::Json::object());
  const TrainTrajectory& traj = plan->trajectory();
  const std::int64_t n = traj.sampleCount();
  EXPECT_EQ(traj.sample(n - 1).t_ns, (n - 1) * traj.samplePeriod());
  EXPECT_EQ(traj.sample(0).speed_m_s, 0.0);
  EXPECT_EQ(traj.sample(n - 1).speed_m_s, 0.0);
  EXPECT_GT(traj.sample(n / 2).speed_m_s, 0.0);
}

TEST(BlockScenario, AGeneratedRouteEditedAsBlocksPlansTheSameMainTrack) {
  scenario::Json input = scenario::Json::parse(R"({"route": {"generator": {"length_m": 8000}}})");
  const auto generated = makePlan(scenario::Scenario::resolve(input, scenarioSchema()));
  input["route"]["source"] = "blocks";
  input["route"]["blocks"] = blockListJson(generated->route().route);
  const auto rebuilt = makePlan(scenario::Scenario::resolve(input, scenarioSchema()));
  const track::Route& a = generated->route().route;
  const track::Route& b = rebuilt->route().route;
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  EXPECT_NEAR(a.track.length(), b.track.length(), 1e-5);
  const auto ea = a.track.horizontal().at(a.track.length()).position_m;
  const auto eb = b.track.horizontal().at(b.track.length()).position_m;
  EXPECT_LT((ea - eb).norm(), 1e-3);  // lengths were rounded to 1 µm
  EXPECT_EQ(generated->layout().tracks.size(), rebuilt->layout().tracks.size());
}

TEST(BlockScenario, ProblemsNameTheBlock) {
  scenario::Json input = scenario::Json::parse(R"({"route": {"source": "blocks", "blocks": []}})");
  auto problems = scenarioSchema().resolve(input).problems;
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "route.blocks");
  input["route"]["blocks"] = scenario::Json::parse(
      R"([{"type": "straight", "length_m": 300}, {"type": "tunnel", "length_m": 0},
          {"type": "curve", "length_m": 0, "transition_m": 0}])");
  problems = scenarioSchema().resolve(input).problems;
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].path, "route.blocks[1].length_m");
  EXPECT_EQ(problems[1].path, "route.blocks[2].length_m");
  // Range checks name the field (consistency checks wait until the fields are valid).
  input["route"]["blocks"][2] = {{"type", "curve"}, {"radius_m", 5.0}};
  problems = scenarioSchema().resolve(input).problems;
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "route.blocks[2].radius_m");
}

// The pose at any time (Trajectory::at) against the sampled trajectory and its own derivatives.
std::vector<double> csvRow(const std::string& text, std::size_t row) {
  std::size_t begin = 0;
  for (std::size_t i = 0; i <= row; ++i)
    begin = text.find('\n', begin) + 1;  // skip the header and `row` rows
  std::vector<double> out;
  std::stringstream line(text.substr(begin, text.find('\n', begin) - begin));
  std::string field;
  while (std::getline(line, field, ','))
    out.push_back(std::stod(field));
  return out;
}

TEST(PoseAtAnyTime, AgreesWithTheSampledTrajectoryFileAtSampleTimes) {
  const std::unique_ptr<Plan> plan = planFor({{"route", {{"generator", {{"length_m", 3000}}}}}});
  const TrainTrajectory& traj = plan->trajectory();
  const std::string csv = trajectoryCsv(*plan);
  for (std::int64_t k = 0; k < traj.sampleCount(); k += 97) {
    const TrajectorySample s = traj.at(k * traj.samplePeriod());
    const std::vector<double> row = csvRow(csv, static_cast<std::size_t>(k));
    ASSERT_EQ(static_cast<TimeNs>(row[0]), s.t_ns);
    // x_m y_m z_m (columns 13–15) are written to 1 µm, yaw pitch roll to 12 digits.
    EXPECT_NEAR(row[13], s.p_world.x(), 5e-7);
    EXPECT_NEAR(row[14], s.p_world.y(), 5e-7);
    EXPECT_NEAR(row[15], s.p_world.z(), 5e-7);
    // Against the local level at the body: R_world_body = R_world_local · attitude(ψ, θ, φ).
    const GeodeticAnchor anchor({43.7228, 10.3966, 50.0});
    const Eigen::Matrix3d r =
        anchor.rotationAnchorFromLocalEnu(s.p_world) * attitude(row[16], row[17], row[18]);
    EXPECT_LT((r - s.q_world_body.toRotationMatrix()).norm(), 1e-11);
    // sample(k) is at(k T_S) bit for bit.
    const TrajectorySample again = traj.sample(k);
    EXPECT_EQ(again.p_world, s.p_world);
    EXPECT_EQ(again.v_world, s.v_world);
  }
}

TEST(PoseAtAnyTime, DerivativesMatchFiniteDifferencesBetweenSamples) {
  const scenario::Json input = {
      {"route", {{"transition_shape", "bloss"}, {"generator", {{"length_m", 4000}}}}},
      {"train", {{"reference_point", {{"x_m", 6.0}, {"y_m", 0.7}, {"z_m", 3.2}}}}}};
  const std::unique_ptr<Plan> plan = planFor(input);
  const TrainTrajectory& traj = plan->trajectory();
  constexpr TimeNs h_ns = 1'000'000;  // 1 ms
  const double h = toSeconds(h_ns);
  int checked = 0;
  for (std::int64_t k = 2; k + 2 < traj.sampleCount(); k += 7) {
    // Half-way between two samples, where nothing was ever sampled.
    const TimeNs t = k * traj.samplePeriod() + traj.samplePeriod() / 2;
    std::array<TrajectorySample, 5> s;
    for (int j = -2; j <= 2; ++j)
      s[static_cast<std::size_t>(j + 2)] = traj.at(t + j * h_ns);
    const TrajectorySample& c = s[2];
    // Bounds from the stencil itself (see the top of this file): h²/2 max|x'''| estimated.
    const double jerk =
        std::max((s[3].a_world - s[1].a_world).norm(), (s[4].a_world - s[0].a_world).norm() / 2) /
        (2 * h);
    const Eigen::Vector3d fd_v = (s[3].p_world - s[1].p_world) / (2 * h);
    const Eigen::Vector3d fd_a = (s[3].v_world - s[1].v_world) / (2 * h);
    // Positions round to a few 1e-9 m (Earth-centred differences), over 2h; the attitude,
    // built on the chord between the pivots, to that over 17.5 m.
    ASSERT_LE((fd_v - c.v_world).norm(), h * h / 2 * jerk + 5e-9 / (2 * h)) << "t " << t;
    ASSERT_LE((fd_a - c.a_world).norm(), h * jerk + 1e-6) << "t " << t;
    // Angular velocity from the rotation increment: log(R(t-h)ᵀ R(t+h)) / 2h, in body axes.
    const Eigen::AngleAxisd inc(s[1].q_world_body.conjugate() * s[3].q_world_body);
    const Eigen::Vector3d fd_w = inc.axis() * inc.angle() / (2 * h);
    const double spin = std::max((s[3].alpha_body - s[1].alpha_body).norm() / (2 * h), 1e-6);
    ASSERT_LE((fd_w - c.w_body).norm(),
              h * h * spin + c.w_body.norm() * c.w_body.norm() * h + 5e-9 / 17.5 / (2 * h))
        << "t " << t;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(PoseAtAnyTime, ClampsToTheRunAndKeepsIntegerTime) {
  const std::unique_ptr<Plan> plan = planFor({{"route", {{"generator", {{"length_m", 2000}}}}}});
  const TrainTrajectory& traj = plan->trajectory();
  EXPECT_EQ(traj.at(-5).p_world, traj.sample(0).p_world);
  EXPECT_EQ(traj.at(traj.endTime() + 1'000'000'000).p_world,
            traj.sample(traj.sampleCount() - 1).p_world);
  EXPECT_EQ(traj.at(123'456'789).t_ns, 123'456'789);
}

// trajectory.standstill_start_s / _end_s put the train at rest before departure and after
// arrival; the run between them is the run without standstills, shifted in time.
TEST(Standstill, AtRestBeforeAndAfterTheRunWhichIsOnlyShifted) {
  const scenario::Json route = {{"generator", {{"length_m", 2000}}}};
  const std::unique_ptr<Plan> plain = planFor({{"route", route}});
  const std::unique_ptr<Plan> held = planFor(
      {{"route", route}, {"trajectory", {{"standstill_start_s", 12}, {"standstill_end_s", 7.5}}}});
  const TrainTrajectory& a = plain->trajectory();
  const TrainTrajectory& b = held->trajectory();
  const TimeNs before = 12'000'000'000;
  EXPECT_EQ(b.sampleCount(), a.sampleCount() + 1950);  // (12 + 7.5) s at 10 ms
  for (TimeNs t = 0; t <= before; t += 250'000'000) {
    const TrajectorySample s = b.at(t);
    ASSERT_EQ(s.p_world, a.at(0).p_world) << t;
    ASSERT_EQ(s.speed_m_s, 0.0);
    ASSERT_EQ(s.w_body.norm(), 0.0);
  }
  for (TimeNs t = 0; t <= a.endTime(); t += 1'000'000'000)
    ASSERT_LE((b.at(t + before).p_world - a.at(t).p_world).norm(), 1e-9) << t;
  for (TimeNs t = a.endTime(); t <= a.endTime() + 7'500'000'000; t += 500'000'000) {
    const TrajectorySample s = b.at(t + before);
    ASSERT_LE((s.p_world - a.at(a.endTime()).p_world).norm(), 1e-9) << t;
    ASSERT_EQ(s.speed_m_s, 0.0);
  }
}

TEST(Standstill, AStaticOnlyRunNeverMovesAndNeedsADuration) {
  const std::unique_ptr<Plan> plan =
      planFor({{"route", {{"generator", {{"length_m", 2000}}}}},
               {"trajectory", {{"static_only", true}, {"standstill_start_s", 60}}}});
  const TrainTrajectory& traj = plan->trajectory();
  EXPECT_EQ(traj.sampleCount(), 6001);
  const Eigen::Vector3d p0 = traj.sample(0).p_world;
  for (std::int64_t k = 0; k < traj.sampleCount(); k += 97) {
    ASSERT_EQ(traj.sample(k).p_world, p0);
    ASSERT_EQ(traj.sample(k).v_world.norm(), 0.0);
  }
  try {
    planFor({{"trajectory", {{"static_only", true}}}});
    FAIL() << "a static run without a standstill was accepted";
  } catch (const scenario::InvalidScenario& e) {
    ASSERT_EQ(e.problems().size(), 1u);
    EXPECT_NE(e.problems()[0].text().find("trajectory.standstill_start_s"), std::string::npos)
        << e.problems()[0].text();
    EXPECT_NE(e.problems()[0].text().find("static_only"), std::string::npos);
  }
}

TEST(ObstacleStop, TheTrainStopsItsMarginShortOfTheFirstObstacleInItsWay) {
  // On a 2 km route: a cow beside the main track (its footprint 2.2 m from the centre, beyond
  // the body's 1.45 m), a car along it with its side 1.1 m from the centre (in the way: its
  // rear, 2.2 m behind its chainage, is what the train meets) and a person on the track further
  // on. The train's front (the body's front edge, 1.25 m ahead of the front pivot) stops
  // obstacle_margin_m short of the car's rear and stands there: the run never goes beyond.
  scenario::Json input = {{"route", {{"generator", {{"length_m", 2000}}}}}};
  input["objects"]["obstacles"] = scenario::Json::array(
      {{{"kind", "cow"}, {"chainage_m", 900.0}, {"offset_m", 3.0}, {"heading_deg", 90.0}},
       {{"kind", "car"}, {"chainage_m", 1500.0}, {"offset_m", -2.0}, {"heading_deg", 0.0}},
       {{"kind", "person"}, {"chainage_m", 1700.0}, {"offset_m", 0.0}}});
  const auto end = [](const Plan& p) {
    return p.trajectory().sample(p.trajectory().sampleCount() - 1);
  };
  const auto check = [&](double margin) {
    SCOPED_TRACE(margin);
    scenario::Json in = input;
    in["train"]["obstacle_margin_m"] = margin;
    const std::unique_ptr<Plan> plan = planFor(in);
    const double car_rear = plan->route().route.track.vertical().at(1500.0).distance_m - 2.2;
    const TrajectorySample last = end(*plan);
    EXPECT_NEAR(last.distance_m, car_rear - margin - 1.25, 1e-6);
    EXPECT_EQ(last.speed_m_s, 0.0);
    double furthest = 0.0;
    for (std::int64_t k = 0; k < plan->trajectory().sampleCount(); k += 10)
      furthest = std::max(furthest, plan->trajectory().sample(k).distance_m);
    EXPECT_LE(furthest, last.distance_m + 1e-9);
    return last.t_ns;
  };
  const TimeNs at_20 = check(20.0);
  EXPECT_GT(at_20, check(60.0));  // stopping 40 m earlier: a shorter run
  // Running through them (or with none in the way) the train drives to the route's end.
  scenario::Json through = input;
  through["train"]["stop_for_obstacles"] = false;
  scenario::Json none = input;
  none["objects"]["obstacles"].erase(1);
  none["objects"]["obstacles"].erase(1);
  const std::unique_ptr<Plan> a = planFor(through), b = planFor(none);
  EXPECT_GT(end(*a).distance_m, 1990.0);
  EXPECT_EQ(end(*a).distance_m, end(*b).distance_m);
  EXPECT_EQ(a->trajectory().sampleCount(), b->trajectory().sampleCount());
  // Turned across the track the car is in the way from 0.9 m further on (its half width).
  input["objects"]["obstacles"][1]["heading_deg"] = 90.0;
  input["objects"]["obstacles"][1]["offset_m"] = 0.0;
  const std::unique_ptr<Plan> across = planFor(input);
  EXPECT_NEAR(end(*across).distance_m,
              across->route().route.track.vertical().at(1500.0).distance_m - 0.9 - 21.25, 1e-6);
}

TEST(ObstacleStop, AnObstacleUnderTheTrainOrTooNearItsStartIsAProblemNamingIt) {
  // The train's front starts at 20 m (the rear wheelset at 0): a cow at 12 m stands under it; a
  // person 10 m ahead of the front is nearer than the 20 m margin. The problem names the
  // scenario's source ("scenario" when resolved without one), as the schema's problems do.
  const auto problem = [](const scenario::Json& obstacle, double margin) -> std::string {
    scenario::Json input = {{"route", {{"generator", {{"length_m", 1500}}}}}};
    input["objects"]["obstacles"] = scenario::Json::array({obstacle});
    input["train"]["obstacle_margin_m"] = margin;
    try {
      planFor(input);
    } catch (const ConfigError& e) {
      return e.what();
    }
    return "";
  };
  const scenario::Json cow = {{"kind", "cow"}, {"chainage_m", 12.0}, {"offset_m", 0.5}};
  const scenario::Json person = {{"kind", "person"}, {"chainage_m", 30.0}, {"offset_m", -0.8}};
  EXPECT_EQ(problem(cow, 20.0).rfind(
                "scenario: objects.obstacles[0]: a cow under the train where it starts", 0),
            0u)
      << problem(cow, 20.0);
  EXPECT_EQ(
      problem(person, 20.0).rfind("scenario: objects.obstacles[0]: a person in the train's way", 0),
      0u)
      << problem(person, 20.0);
  EXPECT_EQ(problem(person, 5.0), "");
  scenario::Json through = {{"route", {{"generator", {{"length_m", 1500}}}}}};
  through["objects"]["obstacles"] = scenario::Json::array({cow, person});
  through["train"]["stop_for_obstacles"] = false;
  EXPECT_NO_THROW(planFor(through));
}

TEST(ObstacleStop, AnObstacleGivenOnTheDoubleTrackButAcrossTheMainTrackStopsTheTrain) {
  // The double track runs 4 m to the right of the main track: a person 4 m to the left of its
  // centre stands on the main track, and a car across the double track at 3 m to its left
  // reaches over the main track's centre; the train stops short of each as of one given on
  // track 0 at the same place.
  const auto stopAt = [](const scenario::Json& obstacle) {
    scenario::Json input = {{"route", {{"generator", {{"length_m", 2000}}}}},
                            {"layout", {{"auxiliary", {{"probability", 0.0}}}}}};
    input["objects"]["obstacles"] = scenario::Json::array({obstacle});
    const std::unique_ptr<Plan> plan = planFor(input);
    return plan->trajectory().sample(plan->trajectory().sampleCount() - 1).distance_m;
  };
  const double person = stopAt({{"track", 1}, {"chainage_m", 1500.0}, {"offset_m", 4.0}});
  EXPECT_NEAR(person, stopAt({{"track", 0}, {"chainage_m", 1500.0}, {"offset_m", 0.0}}), 1e-3);
  EXPECT_LT(person, 1500.0);
  const double car = stopAt({{"kind", "car"},
                             {"track", 1},
                             {"chainage_m", 1500.0},
                             {"offset_m", 3.0},
                             {"heading_deg", 90.0}});
  EXPECT_NEAR(car,
              stopAt({{"kind", "car"},
                      {"track", 0},
                      {"chainage_m", 1500.0},
                      {"offset_m", -1.0},
                      {"heading_deg", 90.0}}),
              1e-3);
  EXPECT_LT(car, 1500.0);
}

}  // namespace
}  // namespace trainsim::sim
