#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace trainsim::scenario {

/// Scenario documents keep their keys in declaration order, so `trainsim defaults`, saved
/// scenarios and hashes are stable and read in the order the schema explains them.
using Json = nlohmann::ordered_json;

enum class ParamType { kBool, kInteger, kNumber, kString, kEnum, kObject, kArray };

/// One declared scenario parameter: a leaf value, an object of parameters, or an array of
/// items that share one declaration. Every parameter is declared once, with its unit, default,
/// range and description; validation, `trainsim defaults`, `trainsim schema`, docs/SCENARIO.md
/// and the studio's property panels are all derived from these declarations.
///
/// Build them with the free functions below and the chainable setters, e.g.
///   integer("sample_period_ns", 10'000'000, "ns", "Trajectory sample period T_S")
///       .range(100'000, 1'000'000'000)
struct Param {
  std::string key;
  ParamType type = ParamType::kObject;
  std::string unit;  ///< SI unit also spelled in the key's suffix ("m", "ns", "deg"); "" if none
  Json default_value;
  std::optional<double> minimum;     ///< inclusive
  std::optional<double> maximum;     ///< inclusive
  std::vector<std::string> choices;  ///< kEnum
  std::string description;
  std::vector<Param> fields;          ///< kObject
  std::shared_ptr<const Param> item;  ///< kArray: the declaration every item follows
  std::optional<std::size_t> max_items;
  /// For integer time periods: the path of the integer parameter this one must be a positive
  /// whole multiple of (sensor periods are multiples of the trajectory period T_S).
  std::string multiple_of;
  /// For strings inside array items: when omitted, item i > 0 defaults to
  /// "<default>_<i>" (sensor names: imu, imu_1, imu_2, ...), so defaults stay unique.
  bool numbered_per_item = false;

  Param& range(std::optional<double> lo, std::optional<double> hi) {
    minimum = lo;
    maximum = hi;
    return *this;
  }
  Param& multipleOf(std::string path) {
    multiple_of = std::move(path);
    return *this;
  }
  Param& numberedPerItem() {
    numbered_per_item = true;
    return *this;
  }
  Param& maxItems(std::size_t n) {
    max_items = n;
    return *this;
  }
  /// The field declared under `key`, or nullptr.
  const Param* field(std::string_view field_key) const;
};

Param boolean(std::string key, bool default_value, std::string description);
Param integer(std::string key, std::int64_t default_value, std::string unit,
              std::string description);
Param number(std::string key, double default_value, std::string unit, std::string description);
Param string(std::string key, std::string default_value, std::string description);
Param choice(std::string key, std::string default_value, std::vector<std::string> choices,
             std::string description);
Param object(std::string key, std::string description, std::vector<Param> fields);
/// An array whose items follow `item` (its key is ignored); defaults to `default_items`.
Param array(std::string key, std::string description, Param item,
            Json default_items = Json::array());

const char* typeName(ParamType type);

}  // namespace trainsim::scenario
