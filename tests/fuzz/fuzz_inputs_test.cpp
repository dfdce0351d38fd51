// A seeded mutation fuzzer of everything a user hands TrainSim: scenario JSON and waypoint CSV.
// Each input goes the way `trainsim validate` takes it (parse, resolve, build the whole plan)
// and, when that accepts it, the way `trainsim plan` takes it (write the plan folder). Checked
// for every input:
//   - no crash and no exception outside TrainSim's own (an "internal error", exit 1);
//   - bounded time: a watchdog cancels an input after its budget (as Ctrl-C would), and the
//     input must stop soon after;
//   - a rejection is ConfigError (exit 2) or RuntimeError (exit 1) with one-line messages that
//     name a JSON path or the file;
//   - validate accepting an input implies plan writing it (the input was not cancelled).
// The counts: TRAINSIM_FUZZ_SCENARIOS and TRAINSIM_FUZZ_WAYPOINTS (defaults 1500 and 500, the CI
// budget under the sanitizers); TRAINSIM_FUZZ_SEED picks another sequence.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim {
namespace {
namespace fs = std::filesystem;
using scenario::Json;
using Clock = std::chrono::steady_clock;

std::int64_t envCount(const char* name, std::int64_t fallback) {
  const char* v = std::getenv(name);
  return v != nullptr ? std::atoll(v) : fallback;
}

// Sets the cancel flag of the input that runs past its budget, as Ctrl-C would.
class Watchdog {
 public:
  Watchdog() : thread_([this] { loop(); }) {}
  ~Watchdog() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  void arm(std::chrono::milliseconds budget) {
    flag_ = false;
    const std::lock_guard lock(mutex_);
    deadline_ = Clock::now() + budget;
    armed_ = true;
    wake_.notify_all();
  }
  void disarm() {
    const std::lock_guard lock(mutex_);
    armed_ = false;
  }
  const std::atomic<bool>* flag() const { return &flag_; }
  bool fired() const { return flag_.load(); }

 private:
  void loop() {
    std::unique_lock lock(mutex_);
    while (!stop_) {
      if (armed_ && Clock::now() >= deadline_) {
        flag_ = true;
        armed_ = false;
      }
      wake_.wait_for(lock, std::chrono::milliseconds(5));
    }
  }
  std::atomic<bool> flag_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  Clock::time_point deadline_{};
  bool armed_ = false;
  bool stop_ = false;
  std::thread thread_;
};

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed, std::string_view stream)
      : rnd_(RandomStream(seed, stream)) {}
  std::size_t below(std::size_t n) {
    return n == 0 ? 0 : std::min(n - 1, static_cast<std::size_t>(rnd_.uniform() * n));
  }
  bool chance(double p) { return rnd_.uniform() <= p; }
  template <typename T>
  const T& pick(const std::vector<T>& v) {
    return v[below(v.size())];
  }

  // Byte-level damage: what an editor, a truncated download or a bad merge does.
  std::string damage(std::string text) {
    if (text.empty())
      return "x";
    const std::size_t at = below(text.size());
    switch (below(6)) {
      case 0:
        text[at] = static_cast<char>(below(256));
        break;
      case 1:
        text.erase(at, 1 + below(16));
        break;
      case 2:
        text.insert(at, text.substr(below(text.size()), 1 + below(32)));
        break;
      case 3:
        text.resize(at);
        break;
      case 4:
        text.insert(at, pick(std::vector<std::string>{",", "\"", "{", "[", "]", "}", ":", "\n",
                                                      "\\", "0", "-", ".", "e", "\xff"}));
        break;
      default:
        std::swap(text[at], text[below(text.size())]);
        break;
    }
    return text;
  }

  Json value(const Json& old) {
    static const std::vector<Json> kValues = {0,
                                              -1,
                                              1,
                                              2,
                                              1e308,
                                              -1e308,
                                              1e-308,
                                              4.9e-324,
                                              9223372036854775807LL,
                                              1e19,
                                              -1e19,
                                              0.5,
                                              1e6,
                                              1e9,
                                              -0.0,
                                              "",
                                              "x",
                                              "clothoid",
                                              true,
                                              false,
                                              nullptr,
                                              Json::array(),
                                              Json::object(),
                                              Json::array({1, 2}),
                                              std::string(300, 'a')};
    if (old.is_number() && chance(0.5)) {
      const double x = old.get<double>();
      return pick(std::vector<double>{x * 10, x / 10, x + 1, x - 1, -x, x * 1e6, x * 1e-6,
                                      std::nextafter(x, 1e300)});
    }
    return pick(kValues);
  }

 private:
  RandomCursor rnd_;
};

// Every leaf and object of a document, as JSON pointers.
void collectPointers(const Json& j, const Json::json_pointer& at,
                     std::vector<Json::json_pointer>& out) {
  out.push_back(at);
  if (j.is_object())
    for (const auto& [k, v] : j.items())
      collectPointers(v, at / k, out);
  else if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i)
      collectPointers(j[i], at / i, out);
}

std::string mutateScenario(Mutator& m, const Json& base,
                           const std::vector<Json::json_pointer>& pointers) {
  Json doc = base;
  const int edits = 1 + static_cast<int>(m.below(3));
  for (int e = 0; e < edits; ++e) {
    const Json::json_pointer& p = m.pick(pointers);
    if (!doc.contains(p))
      continue;
    switch (m.below(6)) {
      case 0:
      case 1:
      case 2:
        doc[p] = m.value(doc[p]);
        break;
      case 3:
        if (!p.empty()) {
          Json& parent = doc.at(p.parent_pointer());
          if (parent.is_array())
            parent.erase(std::stoul(p.back()));
          else
            parent.erase(p.back());
        }
        break;
      case 4:
        if (doc[p].is_object())
          doc[p][m.pick(std::vector<std::string>{"extra", "length", "name", "seed"})] = 1;
        else if (doc[p].is_array())
          doc[p].push_back(doc[p].empty() ? Json::object() : doc[p][0]);
        break;
      default:
        doc[p] = Json::array({doc[p]});
        break;
    }
  }
  std::string text = doc.dump(m.chance(0.5) ? 2 : -1);
  if (m.chance(0.25))
    text = m.damage(text);
  if (!text.empty() && m.chance(0.05))  // a key twice in one object
    text.insert(1, "\"seed\": 3, \"seed\": 4, ");
  return text;
}

std::string mutateWaypoints(Mutator& m, const std::string& base) {
  std::vector<std::string> rows;
  for (std::size_t b = 0, e; b < base.size(); b = e + 1) {
    e = base.find('\n', b);
    if (e == std::string::npos)
      e = base.size();
    rows.push_back(base.substr(b, e - b));
  }
  const int edits = 1 + static_cast<int>(m.below(3));
  for (int k = 0; k < edits && !rows.empty(); ++k) {
    const std::size_t r = 1 + m.below(rows.size() - 1);
    switch (m.below(8)) {
      case 0:
        rows.erase(rows.begin() + static_cast<std::ptrdiff_t>(r));
        break;
      case 1:
        rows.insert(rows.begin() + static_cast<std::ptrdiff_t>(r), rows[r]);
        break;
      case 2:
        std::swap(rows[r], rows[1 + m.below(rows.size() - 1)]);
        break;
      case 3: {  // one field becomes an interesting value
        std::vector<std::string> fields;
        std::string f;
        for (char c : rows[r] + ",") {
          if (c == ',') {
            fields.push_back(f);
            f.clear();
          } else {
            f += c;
          }
        }
        fields.pop_back();
        if (fields.empty())
          break;
        fields[m.below(fields.size())] = m.pick(
            std::vector<std::string>{"0", "-1", "1e308", "nan", "inf", "1e-300", "", "x", "STATION",
                                     "tunnel", "5", "1,5", "100000", "-100000", "1e400", "0x10"});
        std::string joined;
        for (std::size_t i = 0; i < fields.size(); ++i)
          joined += (i ? "," : "") + fields[i];
        rows[r] = joined;
        break;
      }
      case 4:
        rows[r] += ",-5";  // the decimal-comma row
        break;
      case 5:
        rows[0] = m.damage(rows[0]);
        break;
      case 6:
        rows[r] = m.damage(rows[r]);
        break;
      default:
        rows.push_back(rows[r]);
        break;
    }
  }
  std::string out;
  for (const std::string& row : rows)
    out += row + "\n";
  return out;
}

struct Outcome {
  int exit_code = 0;
  bool cancelled = false;
  std::string message;
};

class FuzzInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / fmt::format("trainsim-fuzz-{}", ::getpid());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `trainsim validate` then, if it accepts, `trainsim plan`: in process, under the watchdog.
  // `shown` is what a failure prints (the waypoint file, for the waypoint fuzzer), else `text`.
  Outcome run(const std::string& text, const std::string& source, std::string shown = {}) {
    if (shown.empty())
      shown = text;
    Outcome o;
    const fs::path out = dir_ / "plan";
    fs::remove_all(out);
    watchdog_.arm(budget_);
    const auto t0 = Clock::now();
    const CancelScope cancel(watchdog_.flag());
    bool valid = false;
    try {
      const scenario::Json input = scenario::parseJson(text, source);
      const scenario::Scenario sc = sim::resolveScenario(input, dir_.string(), source);
      const std::unique_ptr<sim::Plan> plan = sim::makePlan(sc);
      valid = true;  // validate's exit 0
      sim::writePlanFolder(*plan, sc, out, false);
    } catch (const scenario::InvalidScenario& e) {
      o.exit_code = 2;
      for (const scenario::Problem& p : e.problems()) {
        checkLine(p.text(), text);
        // Only the document itself (not an object) and the count of problems left out have
        // no path; validate prints the file before every line.
        EXPECT_TRUE(!p.path.empty() || p.message.rfind("... and", 0) == 0 ||
                    p.message.rfind("expected an object", 0) == 0)
            << "a problem names no JSON path: " << p.text();
      }
      o.message = e.problems().front().text();
    } catch (const Cancelled& e) {
      o.exit_code = 1;
      o.cancelled = true;
      o.message = e.what();
      if (slow_.size() < 3)
        slow_.push_back(shown);
    } catch (const Error& e) {
      o.exit_code = exitCodeFor(e);
      o.message = e.what();
      checkLine(o.message, text);
      EXPECT_TRUE(namesAPathOrFile(o.message, source))
          << "names neither a JSON path nor a file: " << o.message;
      EXPECT_FALSE(valid) << "validate accepted the input but plan failed: " << o.message << "\n"
                          << shown;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "internal error (" << e.what() << ") on\n" << shown;
      o.exit_code = 1;
    }
    watchdog_.disarm();
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0);
    EXPECT_LT(took, budget_ + slack_) << "input ran " << took.count() << " ms, not stopped by "
                                      << "its cancel flag:\n"
                                      << shown;
    ++codes_[o.cancelled ? -1 : o.exit_code];
    return o;
  }

  static void checkLine(const std::string& message, const std::string& text) {
    EXPECT_EQ(message.find('\n'), std::string::npos)
        << "message spans lines: " << messageValue(message, 400) << "\n on "
        << messageValue(text, 400);
    EXPECT_LE(message.size(), 400u) << "message too long: " << messageValue(message, 400);
  }

  // A file name (the scenario's or the waypoint file's) or a dotted JSON path such as
  // route.blocks[1] or sensors.imus[0].name.
  static bool namesAPathOrFile(const std::string& message, const std::string& source) {
    static const std::regex kJsonPath(R"((^|[ (])[a-z_]+(\[\d+\])?(\.[a-z_0-9]+(\[\d+\])?)+)");
    return message.find(source) != std::string::npos ||
           message.find("waypoints.csv") != std::string::npos ||
           std::regex_search(message, kJsonPath);
  }

  void report(const char* what) const {
    std::string line;
    for (const auto& [code, n] : codes_)
      line += fmt::format(" {}: {}", code < 0 ? "cancelled" : fmt::format("exit {}", code), n);
    std::cout << what << ":" << line << "\n";
    for (const std::string& text : slow_)  // valid but large, or slow: worth a look
      std::cout << "cancelled after " << budget_.count() << " ms:\n" << text << "\n";
  }

  fs::path dir_;
  Watchdog watchdog_;
#if defined(__SANITIZE_ADDRESS__)  // everything runs several times slower
  std::chrono::milliseconds budget_{8000};
  std::chrono::milliseconds slack_{15000};
#else
  std::chrono::milliseconds budget_{4000};
  std::chrono::milliseconds slack_{6000};  // the longest stretch between cancellation checks
#endif
  std::map<int, int> codes_;
  std::vector<std::string> slow_;
};

// Inputs per run. Under the sanitizers every input takes about five times as long, and half as
// many still meet every kind of mutation many times over; the Release suite runs them all.
#if defined(__SANITIZE_ADDRESS__)
constexpr std::int64_t kScenarios = 750, kWaypointFiles = 250;
#else
constexpr std::int64_t kScenarios = 1500, kWaypointFiles = 500;
#endif

Json baseScenario() {
  Json doc = scenario::parseJson(sim::defaultScenarioText(), "default");
  // A short route keeps each valid input's plan to a fraction of a second.
  doc["route"]["generator"]["length_m"] = 2500;
  return doc;
}

TEST_F(FuzzInputs, MutatedScenariosAreAcceptedOrRefusedCleanlyInBoundedTime) {
  const std::int64_t count = envCount("TRAINSIM_FUZZ_SCENARIOS", kScenarios);
  Mutator m(static_cast<std::uint64_t>(envCount("TRAINSIM_FUZZ_SEED", 1)), "fuzz.scenario");
  const Json base = baseScenario();
  std::vector<Json::json_pointer> pointers;
  collectPointers(base, Json::json_pointer(), pointers);
  for (std::int64_t i = 0; i < count && !HasFailure(); ++i)
    run(mutateScenario(m, base, pointers), "fuzz.json");
  report("scenarios");
  EXPECT_GT(codes_[0], count / 20) << "too few mutated scenarios were valid to test plan";
  EXPECT_GT(codes_[2], count / 4);
}

TEST_F(FuzzInputs, MutatedWaypointFilesAreAcceptedOrRefusedCleanlyInBoundedTime) {
  const std::int64_t count = envCount("TRAINSIM_FUZZ_WAYPOINTS", kWaypointFiles);
  Mutator m(static_cast<std::uint64_t>(envCount("TRAINSIM_FUZZ_SEED", 1)), "fuzz.waypoints");
  const std::string base =
      "n_m,e_m,d_m,radius_m,block\n0,0,0,,\n0,800,0,,station\n300,1600,-2,1500,\n"
      "300,2600,-4,,tunnel\n900,3400,0,2000,\n900,4200,0,,\n";
  const std::string scenario_text = R"({"route": {"source": "waypoints",
      "waypoints_file": "waypoints.csv"}, "layout": {"auxiliary": {"probability": 0.5}}})";
  for (std::int64_t i = 0; i < count && !HasFailure(); ++i) {
    const std::string csv = i == 0 ? base : mutateWaypoints(m, base);
    io::writeFileAtomic(dir_ / "waypoints.csv", csv);
    run(scenario_text, "fuzz.json", "waypoints.csv:\n" + csv);
  }
  report("waypoint files");
  EXPECT_GT(codes_[0], count / 20) << "too few mutated waypoint files were valid";
  EXPECT_GT(codes_[2], count / 4);
}

}  // namespace
}  // namespace trainsim
