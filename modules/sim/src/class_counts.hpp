#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainsim/scene/semantics.hpp"

namespace trainsim::sim {

/// What a labelling sensor counts per class over a run (a LiDAR's points, a camera's semantic
/// pixels): kept in its checkpoint state under `key`, reported in its manifest summary by class
/// name (only the classes it saw) with their total under `total_key`.
class ClassCounts {
 public:
  ClassCounts(const char* key, const char* total_key) : key_(key), total_key_(total_key) {
    reset();
  }

  void reset() { counts_.assign(scene::classes().size(), 0); }
  /// Adds one of class `cls` (ids past the table count as its last class).
  void add(std::size_t cls) { ++counts_[std::min(cls, counts_.size() - 1)]; }
  const std::vector<std::int64_t>& counts() const { return counts_; }

  /// The counts of a checkpoint's state (zeros if it has none); a table of another length is a
  /// checkpoint of another build: json's type_error, which the checkpoint's reader reports.
  void restore(const nlohmann::json& state) {
    reset();
    if (!state.is_object() || !state.contains(key_))
      return;
    counts_ = state.at(key_).get<std::vector<std::int64_t>>();
    if (counts_.size() != scene::classes().size())
      throw nlohmann::json::type_error::create(302, std::string(key_) + " has the wrong length",
                                               nullptr);
  }
  nlohmann::json state() const { return {{key_, counts_}}; }

  nlohmann::json summary() const {
    nlohmann::json classes = nlohmann::json::object();
    std::int64_t total = 0;
    for (std::size_t c = 0; c < counts_.size(); ++c) {
      total += counts_[c];
      if (counts_[c] > 0)
        classes[scene::classes()[c].name] = counts_[c];
    }
    return {{total_key_, total}, {key_, classes}};
  }

 private:
  const char* key_;
  const char* total_key_;
  std::vector<std::int64_t> counts_;
};

}  // namespace trainsim::sim
