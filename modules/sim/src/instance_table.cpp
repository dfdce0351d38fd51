#include "trainsim/sim/instance_table.hpp"

#include <fmt/format.h>

#include "trainsim/core/error.hpp"
#include "trainsim/core/log.hpp"

namespace trainsim::sim {

std::uint16_t InstanceTable::id(scene::InstanceId instance, scene::ClassId cls) {
  if (instance == 0)
    return 0;
  if (const auto it = ids_.find(instance); it != ids_.end())
    return it->second;
  if (order_.size() >= kOverflow) {
    if (!warned_)
      logWarn(fmt::format("more than {} objects in one sequence: the rest share instance id {}",
                          kOverflow - 1, kOverflow));
    warned_ = true;
    return kOverflow;
  }
  order_.push_back(instance);
  const auto id = static_cast<std::uint16_t>(order_.size());
  ids_.emplace(instance, id);
  if (csv_ != nullptr) {
    const Facts facts = facts_ ? facts_(instance) : Facts{};
    csv_->write(fmt::format(
        "{},{},{},{},{}\n", id, instance, scene::semanticClass(facts.cls.value_or(cls)).name,
        facts.track ? fmt::format("{}", *facts.track) : std::string(), facts.state));
  }
  return id;
}

void InstanceTable::begin(io::DatasetWriter& writer, const nlohmann::json& state) {
  csv_ = &writer.appendFile(writer.layout().inSequence(io::DatasetLayout::kInstances));
  ids_.clear();
  order_.clear();
  if (state.is_null()) {
    csv_->write("instance,scene_instance,class,track,state\n");
    return;
  }
  for (const nlohmann::json& v : state.at("instances")) {
    order_.push_back(v.get<scene::InstanceId>());
    if (order_.size() > kOverflow - 1 || !ids_.emplace(order_.back(), order_.size()).second)
      throw ConfigError(
          fmt::format("cannot resume from {}: its instance table is damaged; pass "
                      "--force to start over",
                      writer.checkpointFile().string()));
  }
}

nlohmann::json InstanceTable::state() const {
  return {{"instances", order_}};
}

namespace {

class InstanceTableSensor final : public Sensor {
 public:
  InstanceTableSensor(std::shared_ptr<InstanceTable> table, TimeNs period)
      : table_(std::move(table)), period_(period) {}
  std::string name() const override { return "instances"; }
  std::string kind() const override { return "instances"; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override { return {io::DatasetLayout::kInstances}; }
  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    table_->begin(writer, state);
  }
  Reading render(std::int64_t) const override { return {}; }
  void commit(std::int64_t, Reading&) override {}
  nlohmann::json state() const override { return table_->state(); }
  nlohmann::json summary() const override { return {{"instances", table_->size()}}; }

 private:
  std::shared_ptr<InstanceTable> table_;
  TimeNs period_;
};

}  // namespace

std::unique_ptr<Sensor> instanceTableSensor(std::shared_ptr<InstanceTable> table, TimeNs period) {
  return std::make_unique<InstanceTableSensor>(std::move(table), period);
}

}  // namespace trainsim::sim
