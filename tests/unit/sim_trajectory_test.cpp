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
  const TrainTrajectory& traj = *plan->trajectory;
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
    // Position rounding: |p| ~ 1e4 m → 2e-12 m, over 2T.
    ASSERT_LE(ev, T * T / 2 * jerk + 1e-9) << "sample " << k;
    ASSERT_LE(ea, T * T * snap + 1e-8) << "sample " << k;
    worst_v = std::max(worst_v, ev);
    worst_a = std::max(worst_a, ea);
  }
  EXPECT_GT(worst_v, 0.0);
  EXPECT_GT(worst_a, 0.0);
  // And the speed is the along-track speed of the front pivot, bounded by the limit in force.
  for (std::int64_t k = 0; k < n; ++k)
    ASSERT_LE(at(k).speed_m_s, plan->motion.limit().at(traj.motion(k).u_m) + 1e-9);
}

TEST(TrainTrajectory, EndsAtRestAndTimesAreExact) {
  const std::unique_ptr<Plan> plan = planFor(scenario::Json::object());
  const TrainTrajectory& traj = *plan->trajectory;
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
  input["route"]["blocks"] = blockListJson(generated->route.route);
  const auto rebuilt = makePlan(scenario::Scenario::resolve(input, scenarioSchema()));
  const track::Route& a = generated->route.route;
  const track::Route& b = rebuilt->route.route;
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  EXPECT_NEAR(a.track.length(), b.track.length(), 1e-5);
  const auto ea = a.track.horizontal().at(a.track.length()).position_m;
  const auto eb = b.track.horizontal().at(b.track.length()).position_m;
  EXPECT_LT((ea - eb).norm(), 1e-3);  // lengths were rounded to 1 µm
  EXPECT_EQ(generated->layout.tracks.size(), rebuilt->layout.tracks.size());
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

}  // namespace
}  // namespace trainsim::sim
