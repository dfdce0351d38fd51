#include "trainsim/sim/movement.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <exception>
#include <mutex>

#include "trainsim/core/error.hpp"

namespace trainsim::sim {
namespace {

// The readings of samples [begin, end): rendered in parallel, committed in order.
struct Chunk {
  struct Job {
    std::int64_t k;
    std::size_t sensor;
    Reading reading;
  };
  std::int64_t begin = 0;
  std::int64_t end = 0;
  std::vector<Job> jobs;  // sample order, then sensor order
};

}  // namespace

std::int64_t readingsBefore(std::int64_t end, TimeNs sample_period, TimeNs period) {
  if (end <= 0)
    return 0;
  const std::int64_t stride = period / sample_period;
  return (end - 1) / stride + 1;  // samples 0, stride, 2*stride, ... below end
}

MovementReport runMovement(const Trajectory& trajectory,
                           std::vector<std::unique_ptr<Sensor>>& sensors, io::DatasetWriter& writer,
                           const MovementOptions& options) {
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

  const std::int64_t every = std::max<std::int64_t>(1, options.checkpoint_every_samples);
  const std::int64_t first = writer.resumeSample();
  const nlohmann::json& saved = writer.resumeState();
  // A checkpoint is the user's file: it is checked against this run before it is used.
  const auto refuse = [&](const std::string& why) {
    throw ConfigError(fmt::format("cannot resume from {}: {}; pass --force to start over",
                                  writer.checkpointFile().string(), why));
  };
  if (first > count || (first % every != 0 && first != count))
    refuse(
        fmt::format("next_sample {} is not a frame boundary of this run ({} samples, a frame "
                    "every {})",
                    first, count, every));
  if (first > 0 && !saved.is_object())
    refuse("its state is not an object");
  for (auto& s : sensors) {
    const std::string name = s->name();
    const bool has = first > 0 && saved.contains(name);
    try {
      s->begin(writer, has ? saved.at(name) : nlohmann::json());
    } catch (const nlohmann::json::exception& e) {
      refuse(
          fmt::format("the state of sensor {} is damaged ({})", name, messageValue(e.what(), 120)));
    }
    if (first > 0 && !has && !s->state().is_null())
      refuse(fmt::format("it holds no state for sensor {}", name));
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

  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  // TBB caps its workers at the core count unless told otherwise; --threads N must mean N.
  const tbb::global_control allow(
      tbb::global_control::max_allowed_parallelism,
      static_cast<std::size_t>(std::max(threads, tbb::info::default_concurrency())));
  tbb::task_arena arena(threads);
  std::atomic<std::uint64_t> render_slots{0};  // bit i: arena slot i ran render()

  if (options.progress)
    options.progress->begin("simulate", count, "samples", first);
  // The first failure (a sensor's exception, or Cancelled) stops the source, lets the chunks in
  // flight drain without work, and is rethrown after the pipeline: no exception crosses TBB, so
  // no chunk in flight is left undestroyed.
  std::mutex failure_mutex;
  std::exception_ptr failure;
  std::atomic<bool> failed{false};
  auto fail = [&](std::exception_ptr e) {
    const std::lock_guard lock(failure_mutex);
    if (!failure)
      failure = std::move(e);
    failed = true;
  };
  auto cancelled = [&](std::int64_t k) {
    if (options.cancel && options.cancel->load(std::memory_order_relaxed))
      fail(std::make_exception_ptr(Cancelled("run cancelled at sample " + std::to_string(k))));
    return failed.load();
  };

  std::int64_t next = first;
  auto source = [&](tbb::flow_control& fc) -> std::shared_ptr<Chunk> {
    if (next >= count || cancelled(next)) {
      fc.stop();
      return nullptr;
    }
    auto chunk = std::make_shared<Chunk>();
    chunk->begin = next;
    chunk->end = std::min(count, (next / every + 1) * every);
    for (std::int64_t k = chunk->begin; k < chunk->end; ++k)
      for (std::size_t i = 0; i < sensors.size(); ++i)
        if (k % strides[i] == 0)
          chunk->jobs.push_back({k, i, {}});
    next = chunk->end;
    return chunk;
  };
  // Chunks render in parallel (up to in_flight at once); within a chunk the readings render one
  // after the other, since a heavy sensor parallelises its own frame (columns, tiles) in the
  // same arena and light sensors are cheaper than a task each.
  auto render = [&](std::shared_ptr<Chunk> chunk) {
    if (failed)
      return chunk;
    const int slot = tbb::this_task_arena::current_thread_index();
    if (slot >= 0 && slot < 64)
      render_slots.fetch_or(std::uint64_t{1} << slot, std::memory_order_relaxed);
    try {
      for (Chunk::Job& job : chunk->jobs)
        job.reading = sensors[job.sensor]->render(job.k);
    } catch (...) {
      fail(std::current_exception());
    }
    return chunk;
  };
  auto commit = [&](std::shared_ptr<Chunk> chunk) {
    if (cancelled(chunk->begin))
      return;
    try {
      for (Chunk::Job& job : chunk->jobs)
        sensors[job.sensor]->commit(job.k, job.reading);
      if (options.progress && !chunk->jobs.empty())
        options.progress->update(chunk->end);
      if (chunk->end < count)
        writer.checkpoint(chunk->end, state());
    } catch (...) {
      fail(std::current_exception());
    }
  };
  const auto in_flight = static_cast<std::size_t>(2 * threads + 1);
  arena.execute([&] {
    tbb::parallel_pipeline(
        in_flight,
        tbb::make_filter<void, std::shared_ptr<Chunk>>(tbb::filter_mode::serial_in_order, source) &
            tbb::make_filter<std::shared_ptr<Chunk>, std::shared_ptr<Chunk>>(
                tbb::filter_mode::parallel, render) &
            tbb::make_filter<std::shared_ptr<Chunk>, void>(tbb::filter_mode::serial_in_order,
                                                           commit));
  });
  if (failure)
    std::rethrow_exception(failure);
  for (auto& s : sensors)
    s->end();
  writer.checkpoint(count, state());
  if (options.progress)
    options.progress->end();

  MovementReport report;
  for (const auto& s : sensors)
    report.readings.push_back(readingsBefore(count, ts, s->period()));
  report.threads = arena.max_concurrency();
  report.render_threads = std::popcount(render_slots.load());
  return report;
}

}  // namespace trainsim::sim
