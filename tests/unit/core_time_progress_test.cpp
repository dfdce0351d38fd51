// Integer-nanosecond time, error-to-exit-code policy and the progress reporter's formats.

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainsim/core/error.hpp"
#include "trainsim/core/progress.hpp"
#include "trainsim/core/time.hpp"

namespace trainsim {
namespace {

TEST(Time, ConvertsSecondsToNearestNanosecond) {
  EXPECT_EQ(fromSeconds(0.01), 10'000'000);
  EXPECT_EQ(fromSeconds(1e-9), 1);
  EXPECT_EQ(fromSeconds(-2.5), -2'500'000'000);
  EXPECT_DOUBLE_EQ(toSeconds(1'500'000'000), 1.5);
  EXPECT_THROW(fromSeconds(1e19), ConfigError);
  EXPECT_THROW(fromSeconds(std::nan("")), ConfigError);
}

TEST(Time, IntegerSampleTimesDoNotDrift) {
  // One day at 100 Hz: k * T_S is exact, unlike a float sum of 0.01 s steps.
  constexpr TimeNs ts = 10'000'000;
  constexpr std::int64_t k = 8'640'000;
  EXPECT_EQ(k * ts, 86'400 * kNsPerSecond);
  double drifting = 0.0;
  for (std::int64_t i = 0; i < k; ++i)
    drifting += 0.01;
  EXPECT_NE(drifting, 86400.0);  // why time is never accumulated in float seconds
}

TEST(Time, MultipleOfChecksPositiveWholeMultiples) {
  EXPECT_TRUE(isMultipleOf(100'000'000, 10'000'000));
  EXPECT_FALSE(isMultipleOf(15'000'000, 10'000'000));
  EXPECT_FALSE(isMultipleOf(0, 10'000'000));
  EXPECT_FALSE(isMultipleOf(10, 0));
}

TEST(Errors, MapToExitCodes) {
  EXPECT_EQ(exitCodeFor(ConfigError("x")), 2);
  EXPECT_EQ(exitCodeFor(IoError("x")), 1);
  EXPECT_EQ(exitCodeFor(RuntimeError("x")), 1);
  EXPECT_EQ(exitCodeFor(std::runtime_error("x")), 1);
  EXPECT_EQ(systemErrorMessage("cannot write", "/x/y", ENOSPC),
            "cannot write /x/y: No space left on device");
}

std::string readAll(std::FILE* f) {
  std::rewind(f);
  std::string s;
  for (int c; (c = std::fgetc(f)) != EOF;)
    s.push_back(static_cast<char>(c));
  return s;
}

TEST(Progress, JsonModeWritesOneParsableObjectPerLine) {
  std::FILE* bar = std::tmpfile();
  std::FILE* json = std::tmpfile();
  {
    ProgressReporter p(ProgressMode::kJson, bar, json);
    p.begin("simulate", 200, "samples", 50);
    p.update(120);
    p.end();
  }
  const std::string text = readAll(json);
  EXPECT_TRUE(readAll(bar).empty());
  std::size_t lines = 0, start = 0;
  nlohmann::json last;
  for (std::size_t nl; (nl = text.find('\n', start)) != std::string::npos; start = nl + 1) {
    last = nlohmann::json::parse(text.substr(start, nl - start));
    EXPECT_EQ(last.at("stage"), "simulate");
    EXPECT_EQ(last.at("total"), 200);
    ++lines;
  }
  EXPECT_GE(lines, 2u);  // the first and the last update are always shown
  EXPECT_EQ(last.at("done"), 200);
  EXPECT_DOUBLE_EQ(last.at("fraction").get<double>(), 1.0);
  std::fclose(bar);
  std::fclose(json);
}

TEST(Progress, BarModeDrawsRateAndEtaOnTheBarStream) {
  std::FILE* bar = std::tmpfile();
  std::FILE* json = std::tmpfile();
  {
    ProgressReporter p(ProgressMode::kBar, bar, json);
    p.begin("simulate", 10, "frames");
    p.end();
  }
  const std::string text = readAll(bar);
  EXPECT_NE(text.find("100%"), std::string::npos);
  EXPECT_NE(text.find("frames/s"), std::string::npos);
  EXPECT_NE(text.find("ETA"), std::string::npos);
  EXPECT_TRUE(readAll(json).empty());
  std::fclose(bar);
  std::fclose(json);
}

TEST(Progress, NoneAndAutoWithoutTerminalAreSilent) {
  std::FILE* bar = std::tmpfile();  // a file is not a terminal
  std::FILE* json = std::tmpfile();
  for (ProgressMode mode : {ProgressMode::kNone, ProgressMode::kAuto}) {
    ProgressReporter p(mode, bar, json);
    p.begin("x", 3, "frames");
    p.update(2);
    p.end();
  }
  EXPECT_TRUE(readAll(bar).empty());
  EXPECT_TRUE(readAll(json).empty());
  EXPECT_THROW(parseProgressMode("loud"), ConfigError);
  std::fclose(bar);
  std::fclose(json);
}

TEST(Progress, ListenerSeesFirstAndLastUpdateOfEachStageEvenWhenSilent) {
  std::FILE* bar = std::tmpfile();
  std::FILE* json = std::tmpfile();
  std::vector<std::pair<std::string, std::int64_t>> seen;
  {
    ProgressReporter p(ProgressMode::kNone, bar, json);
    p.setListener([&](const ProgressUpdate& u) {
      seen.emplace_back(std::string(u.stage), u.done);
      EXPECT_EQ(u.total, 40);
      EXPECT_EQ(u.unit, "samples");
    });
    p.begin("run", 40, "samples", 10);
    for (int i = 11; i <= 40; ++i)
      p.update(i);  // rate-limited: only the completed stage is forced through
    p.end();
  }
  ASSERT_GE(seen.size(), 3u);
  EXPECT_EQ(seen.front(), std::make_pair(std::string("run"), std::int64_t{10}));
  EXPECT_EQ(seen.back(), std::make_pair(std::string("run"), std::int64_t{40}));
  EXPECT_LT(seen.size(), 10u);
  EXPECT_TRUE(readAll(bar).empty());
  EXPECT_TRUE(readAll(json).empty());
  std::fclose(bar);
  std::fclose(json);
}

}  // namespace
}  // namespace trainsim
