// The scenario schema machinery on a small schema of its own: defaults, every kind of
// problem, arrays, multiples, paths and the Markdown table.

#include <gtest/gtest.h>

#include "trainsim/scenario/scenario.hpp"
#include "trainsim/scenario/schema.hpp"

namespace trainsim::scenario {
namespace {

Schema testSchema() {
  Schema s;
  s.add(integer("seed", 1, "", "seed").range(0, 1e15));
  s.add(object("clock", "clock",
               {integer("period_ns", 10, "ns", "base period").range(1, 1000),
                integer("frame_ns", 100, "ns", "frame period").multipleOf("clock.period_ns")}));
  s.add(object(
      "lidar", "lidar",
      {number("range_m", 120.0, "m", "max range").range(1, 2000), boolean("enabled", true, "on"),
       choice("model", "vlp16", {"vlp16", "hdl64", "os1_128"}, "preset"),
       string("name", "front", "name")}));
  s.add(array("imus", "imus",
              object("", "imu",
                     {integer("period_ns", 10, "ns", "imu period").multipleOf("clock.period_ns"),
                      number("noise", 0.1, "", "noise").range(0, std::nullopt)}))
            .maxItems(2));
  return s;
}

std::vector<std::string> problems(const Json& input) {
  std::vector<std::string> out;
  for (const auto& p : testSchema().resolve(input).problems)
    out.push_back(p.text());
  return out;
}

TEST(Schema, FillsEveryDefaultInDeclarationOrder) {
  const Json d = testSchema().defaults();
  EXPECT_EQ(d.dump(),
            R"({"seed":1,"clock":{"period_ns":10,"frame_ns":100},"lidar":{"range_m":120.0,)"
            R"("enabled":true,"model":"vlp16","name":"front"},"imus":[]})");
}

TEST(Schema, KeepsGivenValuesAndFillsArrayItems) {
  const auto r = testSchema().resolve(Json::parse(R"({"lidar":{"range_m":200},"imus":[{}]})"));
  ASSERT_TRUE(r.problems.empty());
  EXPECT_EQ(r.resolved["lidar"]["range_m"], 200.0);
  EXPECT_TRUE(r.resolved["lidar"]["range_m"].is_number_float());  // numbers are canonical
  EXPECT_EQ(r.resolved["imus"][0].dump(), R"({"period_ns":10,"noise":0.1})");
}

TEST(Schema, AcceptsIntegralFloatsForIntegers) {
  const auto r = testSchema().resolve(Json::parse(R"({"seed": 1e3})"));
  ASSERT_TRUE(r.problems.empty());
  EXPECT_TRUE(r.resolved["seed"].is_number_integer());
  EXPECT_EQ(r.resolved["seed"], 1000);
}

TEST(Schema, UnknownKeysSuggestTheNearestName) {
  EXPECT_EQ(problems(Json::parse(R"({"lidar":{"rnage_m":5}})")),
            std::vector<std::string>{"lidar.rnage_m: unknown key; did you mean 'range_m'?"});
  EXPECT_EQ(problems(Json::parse(R"({"weather":{}})")),
            std::vector<std::string>{"weather: unknown key"});
}

TEST(Schema, ReportsWrongTypesWithPathAndUnit) {
  EXPECT_EQ(problems(Json::parse(R"({"lidar":{"range_m":"far","enabled":1}})")),
            (std::vector<std::string>{"lidar.range_m: expected a number (m), got \"far\"",
                                      "lidar.enabled: expected true or false, got 1"}));
  EXPECT_EQ(problems(Json::parse(R"({"clock":{"period_ns":2.5}})")),
            std::vector<std::string>{"clock.period_ns: expected an integer (ns), got 2.5"});
  EXPECT_EQ(problems(Json::parse(R"({"clock":[]})")),
            std::vector<std::string>{"clock: expected an object, got []"});
}

TEST(Schema, ReportsValuesOutOfRangeAndNotInEnum) {
  EXPECT_EQ(problems(Json::parse(R"({"lidar":{"range_m":5000}})")),
            std::vector<std::string>{"lidar.range_m: 5000 m is above the maximum 2000 m"});
  EXPECT_EQ(problems(Json::parse(R"({"imus":[{"noise":-1}]})")),
            std::vector<std::string>{"imus[0].noise: -1 is below the minimum 0"});
  EXPECT_EQ(problems(Json::parse(R"({"lidar":{"model":"hdl46"}})")),
            std::vector<std::string>{
                "lidar.model: 'hdl46' is not one of vlp16, hdl64, os1_128; did you mean 'hdl64'?"});
  EXPECT_EQ(
      problems(Json::parse(R"({"seed":18446744073709551615})")),
      std::vector<std::string>{"seed: 18446744073709551615 does not fit in a 64-bit integer"});
}

TEST(Schema, ChecksPeriodsAreMultiplesIncludingArrayItemsAndDefaults) {
  EXPECT_EQ(problems(Json::parse(R"({"clock":{"frame_ns":25}})")),
            std::vector<std::string>{
                "clock.frame_ns: 25 ns is not a positive multiple of clock.period_ns (10 ns)"});
  // Changing the base makes the default frame period (100) invalid too.
  EXPECT_EQ(problems(Json::parse(R"({"clock":{"period_ns":30},"imus":[{"period_ns":60}]})")),
            std::vector<std::string>{
                "clock.frame_ns: 100 ns is not a positive multiple of clock.period_ns (30 ns)"});
  EXPECT_EQ(problems(Json::parse(R"({"imus":[{},{"period_ns":15}]})")),
            std::vector<std::string>{
                "imus[1].period_ns: 15 ns is not a positive multiple of clock.period_ns (10 ns)"});
}

TEST(Schema, LimitsArrayLengthAndCollectsEveryProblem) {
  EXPECT_EQ(problems(Json::parse(R"({"imus":[{},{},{}]})")),
            std::vector<std::string>{"imus: has 3 items; at most 2 are allowed"});
  EXPECT_EQ(problems(Json::parse(R"({"sed":1,"lidar":{"range_m":0},"imus":{}})")).size(), 3u);
}

TEST(Schema, RunsConsistencyChecksOnValidDocuments) {
  Schema s = testSchema();
  s.addCheck([](const Json& r, std::vector<Problem>& out) {
    if (r["lidar"]["range_m"].get<double>() > 1000 && r["lidar"]["model"] == "vlp16") {
      out.push_back({"lidar.range_m", "a VLP-16 reaches at most 1000 m"});
    }
  });
  const auto r = s.resolve(Json::parse(R"({"lidar":{"range_m":1500}})"));
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems[0].text(), "lidar.range_m: a VLP-16 reaches at most 1000 m");
}

TEST(Schema, MarkdownListsEveryLeafWithTypeUnitDefaultAndRange) {
  const std::string md = testSchema().markdown();
  EXPECT_NE(md.find("| `lidar.range_m` | number | m | `120.0` | 1 … 2000 | max range |"),
            std::string::npos);
  EXPECT_NE(md.find("| `clock.frame_ns` | integer | ns | `100` | multiple of `clock.period_ns` |"),
            std::string::npos);
  EXPECT_NE(md.find("| `imus[].noise` | number | – | `0.1` | ≥ 0 | noise |"), std::string::npos);
  EXPECT_NE(md.find("`vlp16`, `hdl64`, `os1_128`"), std::string::npos);
  EXPECT_NE(md.find("| `seed` | integer |"), std::string::npos);
}

TEST(Scenario, MalformedJsonNamesLineAndColumn) {
  try {
    parseJson("{\n  \"a\": 1,\n  \"b\": tru\n}", "bad.json");
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.json:3:", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("malformed JSON"), std::string::npos);
  }
}

TEST(Scenario, ResolvesOrThrowsEveryProblem) {
  const Scenario s = Scenario::resolve(Json::parse(R"({"seed":5})"), testSchema());
  EXPECT_EQ(s.seed(), 5u);
  EXPECT_EQ(s.get<double>("lidar.range_m"), 120.0);
  EXPECT_EQ(s.hash().size(), 16u);
  EXPECT_NE(s.hash(), Scenario::resolve(Json::object(), testSchema()).hash());
  EXPECT_EQ(s.text().back(), '\n');
  try {
    Scenario::resolve(Json::parse(R"({"sed":5,"lidar":{"range_m":0}})"), testSchema(), "x.json");
    FAIL() << "no exception";
  } catch (const InvalidScenario& e) {
    EXPECT_EQ(e.problems().size(), 2u);
    EXPECT_EQ(e.source(), "x.json");
  }
}

TEST(Scenario, DottedPathsBecomeJsonPointers) {
  EXPECT_EQ(pointerFromPath("sensors.imus[0].rate_hz").to_string(), "/sensors/imus/0/rate_hz");
  EXPECT_EQ(pointerFromPath("seed").to_string(), "/seed");
  EXPECT_THROW(Scenario::resolve(Json::object(), testSchema()).at("nope.x"), RuntimeError);
}

TEST(Scenario, MissingFileIsAnInputErrorNamingTheFile) {
  try {
    readScenarioText("/nonexistent/scenario.json");
    FAIL() << "no exception";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scenario.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace trainsim::scenario
