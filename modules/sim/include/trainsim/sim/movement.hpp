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
  std::int64_t checkpoint_every_samples = 10;
  ProgressReporter* progress = nullptr;       ///< optional
  const std::atomic<bool>* cancel = nullptr;  ///< optional; set to stop after the current sample
};

/// The movement system (paper, Movement System): walks the trajectory sample by sample from
/// the writer's resume point, binds each sensor reading to the sample whose time is a multiple
/// of that sensor's period (t = k * T_S, integer nanoseconds, never accumulated), and
/// checkpoints so that a killed run resumes byte-identically. Sensors run in the given order
/// at each sample. Returns the number of readings each sensor produced over the whole run
/// (including those before a resume point). Throws Cancelled when `cancel` is set.
std::vector<std::int64_t> runMovement(const Trajectory& trajectory,
                                      std::vector<std::unique_ptr<Sensor>>& sensors,
                                      io::DatasetWriter& writer, const MovementOptions& options);

/// Number of readings a sensor of period `period` produces over samples [0, end) at T_S.
std::int64_t readingsBefore(std::int64_t end, TimeNs sample_period, TimeNs period);

}  // namespace trainsim::sim
