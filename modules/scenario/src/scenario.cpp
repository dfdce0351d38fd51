#include "trainsim/scenario/scenario.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "trainsim/core/hash.hpp"

namespace trainsim::scenario {
namespace {

std::string problemsText(const std::string& source, const std::vector<Problem>& problems) {
  std::string text = source + " is invalid:";
  for (const auto& p : problems)
    text += "\n  " + p.text();
  return text;
}

}  // namespace

InvalidScenario::InvalidScenario(std::string source, std::vector<Problem> problems)
    : ConfigError(problemsText(source, problems)),
      source_(std::move(source)),
      problems_(std::move(problems)) {}

std::string readScenarioText(const std::string& path) {
  std::ifstream file;
  if (path != "-") {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
      throw ConfigError("cannot read scenario " + path + ": it is a folder, not a file");
    file.open(path, std::ios::binary);
    if (!file)
      throw ConfigError(systemErrorMessage("cannot read scenario", path, errno));
  }
  std::istream& in = path == "-" ? std::cin : file;
  const std::string source = path == "-" ? "standard input" : path;
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxInputBytes)
      throw ConfigError(fmt::format("cannot read scenario {}: it is larger than {} MiB", source,
                                    kMaxInputBytes >> 20));
  }
  if (in.bad())
    throw ConfigError(systemErrorMessage("cannot read scenario", source, errno));
  return text;
}

Scenario Scenario::resolve(const Json& input, const Schema& schema, std::string source) {
  Schema::Resolution r = schema.resolve(input);
  if (!r.problems.empty()) {
    throw InvalidScenario(std::move(source), std::move(r.problems));
  }
  return Scenario(std::move(r.resolved), std::move(source));
}

std::string Scenario::text() const {
  return resolved_.dump(2) + "\n";
}

std::string Scenario::hash() const {
  return fmt::format("{:016x}", fnv1a64(resolved_.dump()));
}

const Json& Scenario::at(std::string_view path) const {
  try {
    return resolved_.at(pointerFromPath(path));
  } catch (const std::exception&) {
    throw RuntimeError(fmt::format("scenario has no parameter '{}'", path));
  }
}

Json::json_pointer pointerFromPath(std::string_view path) {
  std::string pointer;
  std::string token;
  auto flush = [&] {
    if (!token.empty()) {
      pointer += "/" + token;
      token.clear();
    }
  };
  for (char c : path) {
    if (c == '.' || c == '[') {
      flush();
    } else if (c == ']') {
      flush();
    } else if (c == '~') {
      token += "~0";
    } else if (c == '/') {
      token += "~1";
    } else {
      token += c;
    }
  }
  flush();
  return Json::json_pointer(pointer);
}

namespace {
constexpr const char* kSeed = "seed";
constexpr double kMaxSafeInteger = 9007199254740991.0;  // 2^53 - 1, exact in every JSON reader
}  // namespace

Param seedParam() {
  return integer(kSeed, 1, "",
                 "Master seed; every random stream is keyed by (seed, stream name, index)")
      .range(0, kMaxSafeInteger);
}

void overrideSeed(Json& input, std::uint64_t seed) {
  if (input.is_object())
    input[kSeed] = seed;
}

std::uint64_t Scenario::seed() const {
  return resolved_.at(kSeed).get<std::uint64_t>();
}

}  // namespace trainsim::scenario
