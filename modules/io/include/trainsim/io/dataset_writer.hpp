#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/io/file_io.hpp"

namespace trainsim::io {

/// What the caller asked to do with the output folder.
struct OutputPolicy {
  bool force = false;   ///< start over in a folder that already holds something
  bool resume = false;  ///< continue an interrupted run of the same scenario and seed
};

/// Identifies a run, so that --resume only continues the run it interrupted.
struct RunIdentity {
  std::string scenario_hash;
  std::uint64_t seed = 0;
};

/// Owns the dataset folder (its paths: DatasetLayout; behaviour: docs/ARCHITECTURE.md,
/// "The dataset folder"): creates its layout, writes every file atomically, records checkpoints
/// so that a killed run can be resumed byte-identically, and writes manifest.json last, as the
/// mark of a complete dataset.
///
/// Folder rules: a missing or empty folder is used; a folder holding a dataset or an
/// interrupted run is only reused with --force (start over) or --resume (continue, same
/// scenario and seed); any other non-empty folder is refused unless --force, and then only
/// TrainSim's own entries are removed from it. Refusals throw ConfigError (exit 2); file
/// system failures throw IoError (exit 1) naming the file.
///
/// While a run is in progress the folder holds `.trainsim/checkpoint.json`; it is removed when
/// the dataset is complete.
class DatasetWriter {
 public:
  enum class Start { kFresh, kResume, kAlreadyComplete };

  DatasetWriter(std::filesystem::path root, const DatasetLayout& layout,
                const RunIdentity& identity, const OutputPolicy& policy);
  ~DatasetWriter();
  DatasetWriter(const DatasetWriter&) = delete;
  DatasetWriter& operator=(const DatasetWriter&) = delete;

  Start start() const { return start_; }
  const std::filesystem::path& root() const { return root_; }
  const DatasetLayout& layout() const { return layout_; }
  /// The sequence folder, e.g. OUT/sequences/00.
  const std::filesystem::path& sequenceDir() const { return sequence_dir_; }

  /// Where the interrupted run stopped (first trajectory sample still to simulate) and the
  /// state it saved; 0 and null for a fresh run.
  std::int64_t resumeSample() const { return resume_sample_; }
  const nlohmann::json& resumeState() const { return resume_state_; }

  /// Writes `relative` (a path inside the dataset) atomically, creating its folder.
  void writeFile(const std::filesystem::path& relative, std::string_view bytes);

  /// An append-only file inside the dataset; on resume it is cut back to its checkpointed
  /// length, otherwise created empty. The writer owns it; the reference stays valid.
  AppendFile& appendFile(const std::filesystem::path& relative);

  /// Records that every sample before `next_sample` is complete: flushes the append files and
  /// atomically writes their lengths and `state` (what the sensors need to continue).
  void checkpoint(std::int64_t next_sample, const nlohmann::json& state);

  /// Marks the dataset complete: writes manifest.json and removes the checkpoint.
  void finish(const nlohmann::json& manifest);

 private:
  void prepare(const RunIdentity& identity, const OutputPolicy& policy);
  void startOver();
  void loadCheckpoint(const RunIdentity& identity);
  void rollBack() noexcept;

  std::filesystem::path root_;
  DatasetLayout layout_;
  std::filesystem::path sequence_dir_;
  std::string identity_hash_;
  std::uint64_t identity_seed_ = 0;
  Start start_ = Start::kFresh;
  std::int64_t resume_sample_ = 0;
  nlohmann::json resume_state_;
  std::map<std::string, std::int64_t> resume_lengths_;
  std::map<std::string, std::int64_t> committed_lengths_;
  std::map<std::string, std::unique_ptr<AppendFile>> append_files_;
  bool finished_ = false;
};

}  // namespace trainsim::io
