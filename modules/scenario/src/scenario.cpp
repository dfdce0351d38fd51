#include "trainsim/scenario/scenario.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

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
  if (path == "-") {
    return std::string(std::istreambuf_iterator<char>(std::cin), {});
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ConfigError(systemErrorMessage("cannot read scenario", path, errno));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw ConfigError(systemErrorMessage("cannot read scenario", path, errno));
  }
  return text.str();
}

Json parseJson(std::string_view text, std::string_view source) {
  try {
    return Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& e) {
    // nlohmann reports the byte offset just past the offending character; turn it into the
    // 1-based line and column an editor shows.
    const std::size_t offset = std::min<std::size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
    std::size_t line = 1;
    std::size_t column = 1;
    for (std::size_t i = 0; i < offset; ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    std::string reason = e.what();
    if (const auto pos = reason.find(": "); pos != std::string::npos) {
      reason = reason.substr(pos + 2);  // drop "[json.exception.parse_error.101] ... column N"
    }
    throw ConfigError(fmt::format("{}:{}:{}: malformed JSON: {}", source, line, column, reason));
  }
}

Scenario Scenario::resolve(const Json& input, const Schema& schema, std::string source) {
  Schema::Resolution r = schema.resolve(input);
  if (!r.problems.empty()) {
    throw InvalidScenario(std::move(source), std::move(r.problems));
  }
  return Scenario(std::move(r.resolved));
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
