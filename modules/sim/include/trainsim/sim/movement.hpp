#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "trainsim/core/progress.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/sim/sensor.hpp"
#include "trainsim/sim/trajectory.hpp"

namespace trainsim::sim {

struct MovementOptions {
  /// Checkpoint after every sample whose index + 1 is a multiple of this (and at the end).
  /// It is also the unit of work of the run loop: the readings of these samples are rendered
  /// together and committed together.
  std::int64_t checkpoint_every_samples = 10;
  /// Worker threads that render readings (0: all cores). Never changes the output.
  int threads = 0;
  ProgressReporter* progress = nullptr;       ///< optional
  const std::atomic<bool>* cancel = nullptr;  ///< optional; set to stop at the next chunk
};

/// What the run loop did, beyond the readings: how many threads the work actually ran on.
struct MovementReport {
  std::vector<std::int64_t> readings;  ///< per sensor, over the whole run (resume included)
  int threads = 0;                     ///< size of the worker arena
  int render_threads = 0;              ///< distinct threads that ran render()
};

/// The movement system (paper, Movement System): walks the trajectory from the writer's resume
/// point and binds each sensor reading to the sample whose time is a multiple of that sensor's
/// period (t = k * T_S, integer nanoseconds, never accumulated).
///
/// The samples are cut into chunks of `checkpoint_every_samples`. A TBB pipeline in one arena
/// of `threads` workers renders the readings of several chunks at once (Sensor::render, for
/// every sensor and sample of a chunk in parallel) while one chunk at a time, in order, is
/// committed (Sensor::commit, in sample order and, within a sample, in sensor order) and
/// checkpointed; at most 2 * threads + 1 chunks are in flight, so memory stays bounded. The
/// output is therefore byte-identical for any thread count, and a killed run resumes
/// byte-identically. Throws Cancelled when `cancel` is set, and whatever a sensor throws.
MovementReport runMovement(const Trajectory& trajectory,
                           std::vector<std::unique_ptr<Sensor>>& sensors, io::DatasetWriter& writer,
                           const MovementOptions& options);

/// Number of readings a sensor of period `period` produces over samples [0, end) at T_S.
std::int64_t readingsBefore(std::int64_t end, TimeNs sample_period, TimeNs period);

}  // namespace trainsim::sim
