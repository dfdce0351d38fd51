#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trainsim/core/error.hpp"
#include "trainsim/scenario/schema.hpp"

namespace trainsim::scenario {

/// A scenario that failed validation; what() holds one "path: message" line per problem.
class InvalidScenario : public ConfigError {
 public:
  InvalidScenario(std::string source, std::vector<Problem> problems);
  const std::vector<Problem>& problems() const { return problems_; }
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  std::vector<Problem> problems_;
};

/// Bounds on every JSON document TrainSim reads from a user: its size and its nesting depth (a
/// scenario nests five levels deep; nothing recurses on input without a bound).
inline constexpr std::size_t kMaxInputBytes = std::size_t{16} << 20;
inline constexpr std::size_t kMaxJsonDepth = 64;

/// Reads a scenario file, or standard input when `path` is "-". Throws ConfigError naming the
/// file when it cannot be read, is a folder or is larger than kMaxInputBytes.
std::string readScenarioText(const std::string& path);

/// Parses JSON text, bounded: throws ConfigError "<source>:<line>:<column>: <reason>" for
/// malformed JSON, a number out of double's range, nesting deeper than kMaxJsonDepth, and a
/// key that appears twice in one object (naming both lines); "<source>: ..." for text larger
/// than kMaxInputBytes.
Json parseJson(std::string_view text, std::string_view source);

/// A fully resolved scenario: validated, every default filled in. This is what runs and what
/// is saved as OUT/scenario.json.
class Scenario {
 public:
  /// Validates `input` against `schema`; throws InvalidScenario listing every problem.
  static Scenario resolve(const Json& input, const Schema& schema, std::string source = "scenario");

  const Json& json() const { return resolved_; }
  /// Pretty-printed JSON (2-space indent, trailing newline): the bytes of OUT/scenario.json.
  std::string text() const;
  /// 16 hex digits identifying the resolved scenario (FNV-1a 64 of its compact JSON): a
  /// fingerprint to tell runs apart, not a cryptographic digest.
  std::string hash() const;

  /// The value at a dotted path such as "dataset.frame_period_ns" or "sensors.imus[0].rate_hz".
  /// Throws RuntimeError if the path is absent (a schema/code mismatch, not a user error).
  const Json& at(std::string_view path) const;
  template <typename T>
  T get(std::string_view path) const {
    return at(path).get<T>();
  }

  /// The master seed (seedParam()).
  std::uint64_t seed() const;

  /// Where it was read from (a file's path, "<stdin>", ...): what messages about it are
  /// prefixed with, as InvalidScenario's are.
  const std::string& source() const { return source_; }

 private:
  Scenario(Json resolved, std::string source)
      : resolved_(std::move(resolved)), source_(std::move(source)) {}
  Json resolved_;
  std::string source_;
};

/// Runs `stage`, a step that reads `scenario` (its plan, its sensors), and rethrows a
/// ConfigError it throws prefixed with the scenario's source, as InvalidScenario's lines are:
/// "FILE: route.blocks[1]: ...". InvalidScenario, which names its source already, passes.
template <typename Stage>
decltype(auto) namingItsSource(const Scenario& scenario, Stage&& stage) {
  try {
    return std::forward<Stage>(stage)();
  } catch (const InvalidScenario&) {
    throw;
  } catch (const ConfigError& e) {
    throw ConfigError(scenario.source() + ": " + e.what());
  }
}

/// The top-level `seed` every scenario has: every random stream is keyed by (seed, stream
/// name, index). Declared here, beside Scenario::seed() that reads it.
Param seedParam();
/// Sets the seed of an unresolved scenario document (trainsim --seed).
void overrideSeed(Json& input, std::uint64_t seed);

/// Converts "a.b[2].c" to the JSON pointer "/a/b/2/c".
Json::json_pointer pointerFromPath(std::string_view path);

}  // namespace trainsim::scenario
