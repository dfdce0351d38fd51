#include "trainsim/sim/movement.hpp"

#include <fmt/format.h>

#include "trainsim/core/error.hpp"

namespace trainsim::sim {

std::int64_t readingsBefore(std::int64_t end, TimeNs sample_period, TimeNs period) {
  if (end <= 0)
    return 0;
  const std::int64_t stride = period / sample_period;
  return (end - 1) / stride + 1;  // samples 0, stride, 2*stride, ... below end
}

std::vector<std::int64_t> runMovement(const Trajectory& trajectory,
                                      std::vector<std::unique_ptr<Sensor>>& sensors,
                                      io::DatasetWriter& writer, const MovementOptions& options) {
  const TimeNs ts = trajectory.samplePeriod();
  const std::int64_t count = trajectory.sampleCount();
  std::vector<std::int64_t> strides;
  for (const auto& s : sensors) {
    if (!isMultipleOf(s->period(), ts)) {
      throw RuntimeError(fmt::format("sensor {}: period {} ns is not a multiple of T_S {} ns",
                                     s->name(), s->period(), ts));
    }
    strides.push_back(s->period() / ts);
  }

  const std::int64_t first = writer.resumeSample();
  const nlohmann::json& saved = writer.resumeState();
  for (auto& s : sensors) {
    const std::string name = s->name();
    s->begin(writer, saved.is_object() && saved.contains(name) ? saved.at(name) : nlohmann::json());
  }

  auto state = [&] {
    nlohmann::json all = nlohmann::json::object();
    for (const auto& s : sensors) {
      nlohmann::json st = s->state();
      if (!st.is_null())
        all[s->name()] = std::move(st);
    }
    return all;
  };

  if (options.progress)
    options.progress->begin("simulate", count, "samples", first);
  const std::int64_t every = std::max<std::int64_t>(1, options.checkpoint_every_samples);
  for (std::int64_t k = first; k < count; ++k) {
    if (options.cancel && options.cancel->load(std::memory_order_relaxed)) {
      throw Cancelled("run cancelled at sample " + std::to_string(k));
    }
    bool fired = false;
    for (std::size_t i = 0; i < sensors.size() && !fired; ++i)
      fired = k % strides[i] == 0;
    if (fired) {
      const TrajectorySample sample = trajectory.sample(k);
      for (std::size_t i = 0; i < sensors.size(); ++i) {
        if (k % strides[i] == 0)
          sensors[i]->capture(k, sample);
      }
      if (options.progress)
        options.progress->update(k + 1);
    }
    if ((k + 1) % every == 0 && k + 1 < count) {
      writer.checkpoint(k + 1, state());
    }
  }
  for (auto& s : sensors)
    s->end();
  writer.checkpoint(count, state());
  if (options.progress)
    options.progress->end();

  std::vector<std::int64_t> readings;
  for (const auto& s : sensors)
    readings.push_back(readingsBefore(count, ts, s->period()));
  return readings;
}

}  // namespace trainsim::sim
