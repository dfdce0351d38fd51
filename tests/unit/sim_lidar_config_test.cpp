// The LiDAR section's problems, each named at its field: a mount whose beams leave the head
// inside the train's body, range limits that leave no range, more columns than the device
// fires, spin rates and modes the device does not run. And the settings of LiDARs and cameras
// that are valid but may not be meant, said by validate and at a run's start.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>

#include "trainsim/sim/schema.hpp"
#include "trainsim/sim/sensor_registry.hpp"

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

TEST(SensorWarnings, EachSettingThatMayNotBeMeantIsOneLineNamingItsSensorAndTheDefaultHasNone) {
  EXPECT_TRUE(sensorWarnings(loadScenario("").json()).empty());
  scenario::Json input = lidarScenario();
  scenario::Json& lidars = input["sensors"]["lidars"];
  lidars[0]["returns"] = "dual";   // with one ray a pulse
  lidars[0]["range_max_m"] = 150;  // beyond the VLP-16's 100 m
  lidars.push_back({{"name", "wide"},
                    {"model", "vlp16"},
                    {"period_ns", 2'000'000'000},
                    {"columns", 900},
                    {"sub_rays", 4},
                    {"beam_divergence_mrad", 0},
                    {"mount", {{"x_m", 9.0}}}});
  const auto camera = [](scenario::Json mount) {
    return scenario::Json{
        {"width", 64}, {"height", 48}, {"period_ns", 2'000'000'000}, {"mount", std::move(mount)}};
  };
  input["sensors"]["cameras"] = {camera(scenario::Json::object()),  // camera 0: nothing to say
                                 camera({{"yaw_deg", 90}}),         // turned against camera 0
                                 camera({{"x_m", 10.5}, {"z_m", 0.4}, {"pitch_deg", -70}})};
  input["sensors"]["cameras"][2]["draw_distance_m"] = 1000;  // past the 400 m of terrain
  const scenario::Schema::Resolution r = scenarioSchema().resolve(input);
  ASSERT_TRUE(r.problems.empty()) << r.problems[0].text();
  const std::vector<std::string> lines = sensorWarnings(r.resolved);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"sensors.lidars[0]", "returns is dual but sub_rays is 1"},
      {"sensors.lidars[0]", "range_max_m 150 m is beyond the vlp16's 100 m"},
      {"sensors.lidars[1]", "sub_rays is 4 but beam_divergence_mrad is 0"},
      {"sensors.cameras[1]", "the camera is turned against camera 0, so calib.txt's P3"},
      {"sensors.cameras[2]", "the camera is turned against camera 0, so calib.txt's P4"},
      {"sensors.cameras[2]", "at draw_distance_m 1000 m the picture reaches"},
      {"sensors.cameras[2]", "the camera sees the rail-top plane from 0.35 m along its axis"}};
  ASSERT_EQ(lines.size(), expected.size());
  for (std::size_t i = 0; i < lines.size(); ++i)  // in table order: the LiDARs, then the cameras
    EXPECT_EQ(lines[i].rfind(expected[i].first + ": " + expected[i].second, 0), 0u) << lines[i];
  // Every LiDAR and camera in the same fog: nothing more to say. One camera in a thinner layer
  // and one in clear air: each is said to differ from the first LiDAR, after the rest.
  // (`lidars` no longer refers to the list: adding the cameras moved the ordered JSON's items.)
  for (const char* kind : {"lidars", "cameras"})
    for (scenario::Json& item : input["sensors"][kind]) {
      item["fog_visibility_m"] = 200;
      if (kind == std::string("lidars"))
        item["range_10_percent_m"] = 40;
    }
  const scenario::Schema::Resolution same = scenarioSchema().resolve(input);
  ASSERT_TRUE(same.problems.empty()) << same.problems[0].text();
  EXPECT_EQ(sensorWarnings(same.resolved), lines);
  input["sensors"]["cameras"][1]["fog_height_m"] = 50;
  input["sensors"]["cameras"][2]["fog_visibility_m"] = 0;
  const std::vector<std::string> foggy = sensorWarnings(scenarioSchema().resolve(input).resolved);
  ASSERT_EQ(foggy.size(), lines.size() + 2);
  EXPECT_EQ(foggy[lines.size()].rfind("sensors.cameras[1]: fog_visibility_m 200 m and "
                                      "fog_height_m 50 m, but sensors.lidars[0] has "
                                      "fog_visibility_m 200 m and fog_height_m 100 m",
                                      0),
            0u)
      << foggy[lines.size()];
  EXPECT_EQ(foggy[lines.size() + 1].rfind("sensors.cameras[2]: no fog (fog_visibility_m 0), but "
                                          "sensors.lidars[0] has fog_visibility_m 200 m",
                                          0),
            0u)
      << foggy[lines.size() + 1];
}

}  // namespace
}  // namespace trainsim::sim
