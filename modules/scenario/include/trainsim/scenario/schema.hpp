#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "trainsim/scenario/param.hpp"

namespace trainsim::scenario {

/// One problem found in a scenario: the JSON path of the offending value ("" for the whole
/// document) and what is wrong with it.
struct Problem {
  std::string path;
  std::string message;
  /// "path: message", the one-line form printed by `trainsim validate`.
  std::string text() const;
};

/// A check across several parameters of a fully resolved scenario; appends problems.
using ConsistencyCheck = std::function<void(const Json& resolved, std::vector<Problem>& problems)>;

/// The complete scenario schema: a root object of declared sections plus the consistency
/// checks that no single declaration can express.
class Schema {
 public:
  Schema() = default;

  /// Adds a top-level section (or top-level parameter). Keys must be unique.
  void add(Param section);
  void addCheck(ConsistencyCheck check);

  const Param& root() const { return root_; }

  struct Resolution {
    Json resolved;                  ///< the input with every missing parameter filled in
    std::vector<Problem> problems;  ///< empty when the input is valid
  };
  /// Validates `input` and fills in defaults. Collects every problem instead of stopping at
  /// the first: unknown keys (with a "did you mean" suggestion), wrong types, values out of
  /// range or not in an enum, periods that are not multiples, failed consistency checks.
  Resolution resolve(const Json& input) const;

  /// The scenario every default gives: resolve({}).
  Json defaults() const;

  /// The parameter table as Markdown: one row per leaf parameter with its JSON path, type,
  /// unit, default, allowed range and description (the content of docs/SCENARIO.md). With
  /// `built_in`, the text of the scenario that runs when none is given, it is shown too, as what
  /// sets some keys otherwise than their defaults.
  std::string markdown(std::string_view built_in = {}) const;

 private:
  Param root_ = object("", "TrainSim scenario", {});
  std::vector<ConsistencyCheck> checks_;
};

}  // namespace trainsim::scenario
