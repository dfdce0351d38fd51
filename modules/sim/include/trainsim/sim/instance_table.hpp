#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/scene/semantics.hpp"
#include "trainsim/sim/sensor.hpp"

namespace trainsim::sim {

/// The sequence's 16-bit instance ids: SemanticKITTI keeps an object's instance in the upper
/// 16 bits of its label, unique within a sequence, 0 for "stuff". The scene's instance ids are
/// 64-bit (a pure function of what the object is), so the table numbers them 1, 2, … in the
/// order the sensors first commit them (sample order, then sensor order: the same for any
/// thread count), and every perception sensor of the run shares it, so an object has one id in
/// every LiDAR's labels and every camera's instance image. Each new id is appended to
/// instances.csv (id, the scene's instance id as objects.csv lists it, its class: a signal's is
/// signal whether its head or its post is seen first, other objects the class they were first
/// seen as (a tree's crown and trunk share one id); the layout track a track asset belongs to,
/// so the rails of the train's own track 0 can be told from the others; and its state, what the
/// object shows if it shows anything: a signal's aspect), and the table is checkpointed, so a
/// resumed run numbers on exactly as the killed one would have.
///
/// Past 65535 objects in one sequence the ids run out: further objects share 65535, and the
/// run says so once.
class InstanceTable {
 public:
  static constexpr std::uint16_t kOverflow = 0xFFFF;
  /// What instances.csv says of an object beyond its ids: its class where the object has one
  /// whatever part of it is seen first (a signal's head and post: signal), the layout track it
  /// belongs to (a rail, a catenary mast or wire, a signal) and what it shows (a signal's
  /// "proceed", "caution" or "stop"); nothing and empty for most.
  struct Facts {
    std::optional<int> track;
    std::string_view state;
    std::optional<scene::ClassId> cls;
  };
  using FactsOf = std::function<Facts(scene::InstanceId)>;

  explicit InstanceTable(FactsOf facts = {}) : facts_(std::move(facts)) {}

  /// The id of `instance` (a thing of class `cls`); 0 for 0. Call from commit() only.
  std::uint16_t id(scene::InstanceId instance, scene::ClassId cls);
  std::size_t size() const { return order_.size(); }

  /// Opens instances.csv; `state` is null for a fresh run.
  void begin(io::DatasetWriter& writer, const nlohmann::json& state);
  nlohmann::json state() const;

 private:
  std::map<scene::InstanceId, std::uint16_t> ids_;
  std::vector<scene::InstanceId> order_;  // order_[i] has id i + 1
  FactsOf facts_;
  io::AppendFile* csv_ = nullptr;
  bool warned_ = false;
};

/// The run-loop face of the table (like the frame clock, not a registered kind): opens and
/// checkpoints it with the sensors; `period` is the frame period.
std::unique_ptr<Sensor> instanceTableSensor(std::shared_ptr<InstanceTable> table, TimeNs period);

}  // namespace trainsim::sim
