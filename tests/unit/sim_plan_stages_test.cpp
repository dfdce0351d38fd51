// The staged plan: each stage is rebuilt only when the scenario sections it reads change.
#include <gtest/gtest.h>

#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

scenario::Scenario resolve(const scenario::Json& input) {
  return scenario::Scenario::resolve(input, scenarioSchema());
}

struct Builds {
  std::int64_t route, layout, motion;
  bool operator==(const Builds&) const = default;
};
Builds builds(const Planner& p) {
  return {p.builds("route"), p.builds("layout"), p.builds("motion")};
}

TEST(Planner, RebuildsOnlyTheStagesWhoseSectionsChanged) {
  scenario::Json input = {{"route", {{"generator", {{"length_m", 2500}}}}}};
  Planner planner;
  const Plan first = planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{1, 1, 1}));

  input["train"] = {{"max_accel_m_s2", 0.5}};
  const Plan train_edit = planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{1, 1, 2}));
  EXPECT_EQ(&train_edit.route(), &first.route());  // the very same stage, shared
  EXPECT_EQ(&train_edit.layout(), &first.layout());
  EXPECT_NE(train_edit.motion().duration(), first.motion().duration());

  input["sensors"] = {{"imus", {{{"preset", "tactical"}}}}};
  input["description"] = "sensors and text do not touch the plan";
  planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{1, 1, 2}));

  // An obstacle in the train's way ends its run short of it (train.stop_for_obstacles).
  input["objects"] = {{"obstacles", {{{"kind", "person"}, {"chainage_m", 2000.0}}}}};
  const Plan obstacle_edit = planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{1, 1, 3}));
  EXPECT_LT(obstacle_edit.motion().duration(), train_edit.motion().duration());

  // The motion reads the layout too (an obstacle given on the double track may stand in the
  // train's way).
  input["layout"] = {{"track_centre_distance_m", 4.5}};
  planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{1, 2, 4}));

  input["design"] = {{"max_cant_mm", 150}};
  planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{2, 3, 5}));

  input["seed"] = 9;  // the seed draws the route and the layout
  planner.plan(resolve(input));
  EXPECT_EQ(builds(planner), (Builds{3, 4, 6}));
}

TEST(Planner, ReusedStagesGiveTheSamePlanAsAFreshOne) {
  const scenario::Json a = {{"route", {{"generator", {{"length_m", 2000}}}}}};
  scenario::Json b = a;
  b["train"] = {{"max_jerk_m_s3", 0.4}};
  Planner planner;
  planner.plan(resolve(a));
  const Plan reused = planner.plan(resolve(b));
  const std::unique_ptr<Plan> fresh = makePlan(resolve(b));
  EXPECT_EQ(trajectoryCsv(reused), trajectoryCsv(*fresh));
  EXPECT_EQ(railroadJson(reused), railroadJson(*fresh));
}

TEST(PipelineStages, StagesNotRunComeFromTheTable) {
  std::vector<std::string> expected;
  for (const PipelineStage& s : pipelineStages())
    if (!s.implemented)
      expected.emplace_back(s.description);
  EXPECT_EQ(stagesNotRun(), expected);
  // Every stage of the paper's pipeline is built now (the cameras were the last).
  EXPECT_TRUE(expected.empty());
  EXPECT_EQ(pipelineStages()[0].name, "route");
}

}  // namespace
}  // namespace trainsim::sim
