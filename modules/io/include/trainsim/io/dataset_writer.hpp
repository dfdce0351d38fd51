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

/// What a run will do with its output folder.
enum class OutputFolder {
  kNew,        ///< missing or empty: created or used as it is
  kStartOver,  ///< --force: TrainSim's own entries are removed first
  kResume,     ///< --resume of an interrupted run of the same scenario and seed
  kComplete,   ///< --resume of a complete dataset of the same scenario and seed: nothing to do
};

/// Checks `root` against the folder rules (below) without touching it, so that `plan` and
/// `generate` refuse a bad --out before they plan: ConfigError (exit 2) for an empty name, a
/// path naming a file or lying below one, a non-empty folder that is not TrainSim's without
/// --force, a dataset or interrupted run without --force or --resume, or --resume of another
/// scenario or seed; IoError (exit 1) if the folder, or the one it would be made in, cannot be
/// written. `identity` is compared on --resume only.
OutputFolder checkOutputFolder(const std::filesystem::path& root, const OutputPolicy& policy,
                               const RunIdentity& identity = {});

/// Removes TrainSim's own entries (DatasetLayout::ownEntries) from `root`, nothing else (--force).
void removeOwnEntries(const std::filesystem::path& root);

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
/// the dataset is complete. A run that fails or is cancelled before its first frame is complete
/// removes what it created (the folder itself if it made it); after that the folder keeps the
/// complete frames, can be continued with --resume, and the writer says so. A checkpoint is
/// trusted only after it is checked against the files it lists: every refusal names it.
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

  /// The checkpoint file, for messages.
  std::filesystem::path checkpointFile() const;

  /// Writes `relative` (a path inside the dataset) atomically, creating its folder. Every path
  /// must stay inside the dataset (DatasetLayout::isInside), else RuntimeError.
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
  void startOver();
  void loadCheckpoint();
  void rollBack() noexcept;
  void removeCreated() noexcept;
  std::filesystem::path inside(const std::filesystem::path& relative) const;

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
  bool created_root_ = false;          ///< the folder did not exist before this run
  std::int64_t committed_sample_ = 0;  ///< next_sample of the last checkpoint
};

}  // namespace trainsim::io
