// The LiDAR section's problems, each named at its field: a mount whose beams leave the head
// inside the train's body, range limits that leave no range, more columns than the device
// fires, spin rates and modes the device does not run.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

// A VLP-16 on the cab roof, 900 columns a scan, one scan every 2 s.
scenario::Json lidarScenario() {
  return {{"dataset", {{"frame_period_ns", 2'000'000'000}}},
          {"sensors",
           {{"lidars", {{{"model", "vlp16"}, {"period_ns", 2'000'000'000}, {"columns", 900}}}}}}};
}

TEST(LidarConfig, ALidarInsideTheTrainsBodyIsAProblemNamingItsMount) {
  scenario::Json input = lidarScenario();
  input["sensors"]["lidars"][0]["mount"]["z_m"] = 3.0;  // under the 3.8 m roof, on the body
  auto problems = scenarioSchema().resolve(input).problems;
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "sensors.lidars[0].mount");
  EXPECT_NE(problems[0].message.find("train.body"), std::string::npos);
  input["train"]["body"]["enabled"] = false;  // or with no body to be inside
  EXPECT_TRUE(scenarioSchema().resolve(input).problems.empty());
  // Its housing standing on the roof: the HDL-64E's origin is on it and its beams leave the
  // head 0.14 m and more above it; a VLP-16's +15° laser leaves it 11 mm below its origin, and
  // the uniform pattern's all at it, on the roof, which the body's box holds.
  input["train"]["body"]["enabled"] = true;
  input["sensors"]["lidars"][0]["mount"]["z_m"] = 3.8;
  for (const auto& [model, inside] :
       {std::pair{"hdl64", false}, std::pair{"vlp16", true}, std::pair{"uniform", true}}) {
    input["sensors"]["lidars"][0]["model"] = model;
    input["sensors"]["lidars"][0]["columns"] = model == std::string("hdl64") ? 1000 : 900;
    EXPECT_EQ(scenarioSchema().resolve(input).problems.size(), inside ? 1u : 0u) << model;
  }
}

TEST(LidarConfig, LimitsThatLeaveNoRangeOrOverlapFiringsAreProblemsNamingTheField) {
  const auto problemsOf = [](const scenario::Json& lidar) {
    scenario::Json input = lidarScenario();
    for (const auto& [k, v] : lidar.items())
      input["sensors"]["lidars"][0][k] = v;
    return scenarioSchema().resolve(input).problems;
  };
  // 0 stands for the device's limit (VLP-16: 0.9 ... 100 m): set against it, no range is left.
  for (const auto& [lidar, field] :
       {std::pair{scenario::Json{{"range_max_m", 0.5}}, "range_max_m"},
        std::pair{scenario::Json{{"range_min_m", 100.0}}, "range_min_m"},
        std::pair{scenario::Json{{"range_min_m", 50.0}, {"range_max_m", 40.0}}, "range_min_m"},
        // 4000 columns at the default 10 Hz are 25 us each; the VLP-16 fires for 55.296 us (1808
        // fit).
        std::pair{scenario::Json{{"columns", 4000}}, "columns"},
        std::pair{scenario::Json{{"range_sigma_m", -0.5}}, "range_sigma_m"}}) {
    const auto problems = problemsOf(lidar);
    ASSERT_EQ(problems.size(), 1u) << lidar.dump();
    EXPECT_EQ(problems[0].path, std::string("sensors.lidars[0].") + field) << lidar.dump();
  }
  EXPECT_NE(problemsOf({{"columns", 4000}})[0].message.find("1808"), std::string::npos);
  // An Ouster runs its modes: 2048 columns at 10 Hz and 1024 at 20 Hz among them (a 97.7 us
  // firing sequence would allow half); 4096 at 10 Hz, 777 at 10 Hz, or any columns at 13 Hz are
  // none of them. A Velodyne spins at 5 ... 20 Hz.
  for (const char* model : {"os1_64", "os1_128"}) {
    SCOPED_TRACE(model);
    for (const auto& [columns, hz] : {std::pair{2048, 10.0}, std::pair{1024, 20.0}})
      EXPECT_TRUE(problemsOf({{"model", model}, {"columns", columns}, {"rotation_hz", hz}}).empty())
          << columns;
    for (const int columns : {4096, 777}) {
      const auto os1 = problemsOf({{"model", model}, {"columns", columns}});
      ASSERT_EQ(os1.size(), 1u);
      EXPECT_EQ(os1[0].path, "sensors.lidars[0].columns");
      EXPECT_NE(os1[0].message.find("is not one of the " + std::string(model) +
                                    "'s modes (512 x 10 Hz, 1024 x 10 Hz, 2048 x 10 Hz, 512 x "
                                    "20 Hz, 1024 x 20 Hz)"),
                std::string::npos)
          << os1[0].message;
    }
    const auto rate = problemsOf({{"model", model}, {"rotation_hz", 13.0}});
    ASSERT_EQ(rate.size(), 1u);
    EXPECT_EQ(rate[0].path, "sensors.lidars[0].rotation_hz");
  }
  for (const char* model : {"vlp16", "hdl32", "hdl64", "vlp32c"}) {
    SCOPED_TRACE(model);
    for (const double hz : {5.0, 20.0})
      EXPECT_TRUE(problemsOf({{"model", model}, {"rotation_hz", hz}, {"columns", 0}}).empty());
    for (const double hz : {1.0, 4.9, 20.5}) {
      const auto slow = problemsOf({{"model", model}, {"rotation_hz", hz}, {"columns", 0}});
      ASSERT_EQ(slow.size(), 1u) << hz;
      EXPECT_EQ(slow[0].path, "sensors.lidars[0].rotation_hz");
      EXPECT_NE(slow[0].message.find("is outside the " + std::string(model) +
                                     "'s 5 ... 20 Hz (300 ... 1200 rpm)"),
                std::string::npos)
          << slow[0].message;
    }
  }
  for (const scenario::Json& fine :
       {scenario::Json{{"range_min_m", 0.5}}, scenario::Json{{"range_max_m", 1.0}},
        scenario::Json{{"columns", 1808}}, scenario::Json{{"range_sigma_m", -1}}})
    EXPECT_TRUE(problemsOf(fine).empty()) << fine.dump();
}

}  // namespace
}  // namespace trainsim::sim
