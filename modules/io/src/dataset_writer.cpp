#include "trainsim/io/dataset_writer.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

#include "trainsim/core/error.hpp"
#include "trainsim/core/log.hpp"

namespace trainsim::io {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kStateDir = DatasetLayout::kStateDir;
constexpr const char* kCheckpoint = DatasetLayout::kCheckpoint;
constexpr const char* kManifest = DatasetLayout::kManifest;

void makeDirectories(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    throw IoError("cannot create folder " + dir.string() + ": " + ec.message());
  }
}

bool isEmptyDirectory(const fs::path& dir) {
  std::error_code ec;
  return fs::directory_iterator(dir, ec) == fs::directory_iterator();
}

void removeAll(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
  if (ec) {
    throw IoError("cannot remove " + p.string() + ": " + ec.message());
  }
}

// A run record (checkpoint or manifest) is the user's folder state, not ours to trust: a
// damaged one is refused as bad input, naming the file.
json readRecord(const fs::path& path) {
  try {
    return json::parse(readFile(path));
  } catch (const json::exception& e) {
    throw ConfigError(fmt::format("{} is damaged ({}); pass --force to start over", path.string(),
                                  messageValue(e.what(), 120)));
  } catch (const IoError& e) {
    throw ConfigError(std::string(e.what()) + "; pass --force to start over");
  }
}

// The nearest part of `path` that exists (the path itself or a folder above it); "" if none.
fs::path nearestExisting(const fs::path& path) {
  std::error_code ec;
  for (fs::path p = path; !p.empty(); p = p.parent_path()) {
    if (fs::exists(fs::symlink_status(p, ec)))
      return p;
    if (p == p.parent_path())
      break;
  }
  return {};
}

}  // namespace

OutputFolder checkOutputFolder(const fs::path& root, const OutputPolicy& policy,
                               const RunIdentity& identity) {
  if (policy.force && policy.resume)
    throw ConfigError("--force and --resume exclude each other");
  if (root.empty())
    throw ConfigError("the output folder name is empty");
  const std::string where = root.string();
  const fs::path anchored = root.is_relative() ? fs::path(".") / root : root;
  const fs::path existing = nearestExisting(anchored);
  std::error_code ec;
  if (!existing.empty() && !fs::is_directory(existing, ec)) {
    throw ConfigError(existing == anchored
                          ? "output " + where + " exists and is not a folder"
                          : "output " + where + ": " + existing.string() + " is not a folder");
  }
  const fs::path writable = existing.empty() ? fs::path(".") : existing;
  if (::access(writable.c_str(), W_OK | X_OK) != 0) {
    throw IoError(existing == anchored
                      ? systemErrorMessage("cannot write output folder", where, errno)
                      : systemErrorMessage("cannot create output folder", where, errno));
  }
  if (!fs::exists(root, ec) || isEmptyDirectory(root))
    return OutputFolder::kNew;

  const bool interrupted = fs::exists(root / kCheckpoint, ec);
  const bool complete = !interrupted && fs::exists(root / kManifest, ec);
  if (policy.force)
    return OutputFolder::kStartOver;
  if (!interrupted && !complete) {
    if (fs::exists(root / DatasetLayout::kRailroad, ec) &&
        fs::exists(root / DatasetLayout::kDesignReport, ec))
      throw ConfigError("output " + where + " holds a plan: pass --force to overwrite it");
    throw ConfigError("output " + where +
                      " is not empty and was not written by trainsim: choose an empty folder or "
                      "pass --force (which removes only TrainSim's own entries from it)");
  }
  if (!policy.resume) {
    throw ConfigError(interrupted ? "output " + where +
                                        " holds an interrupted run: pass --resume to continue it "
                                        "or --force to start over"
                                  : "output " + where +
                                        " already holds a dataset: pass --force to overwrite it");
  }
  const fs::path record = root / (complete ? kManifest : kCheckpoint);
  const json doc = readRecord(record);
  std::string hash = "?";
  std::uint64_t seed = 0;
  if (doc.is_object() && doc.contains("scenario_hash") && doc["scenario_hash"].is_string())
    hash = doc["scenario_hash"].get<std::string>();
  if (doc.is_object() && doc.contains("seed") && doc["seed"].is_number_unsigned())
    seed = doc["seed"].get<std::uint64_t>();
  if (hash != identity.scenario_hash || seed != identity.seed) {
    throw ConfigError(fmt::format(
        "output {} holds {} of another scenario or seed ({} records hash {}, seed {}); pass "
        "--force to start over",
        where, complete ? "a dataset" : "an interrupted run", record.string(), messageValue(hash),
        seed));
  }
  return complete ? OutputFolder::kComplete : OutputFolder::kResume;
}

DatasetWriter::DatasetWriter(fs::path root, const DatasetLayout& layout,
                             const RunIdentity& identity, const OutputPolicy& policy)
    : root_(std::move(root)),
      layout_(layout),
      sequence_dir_(root_ / layout.sequenceDir()),
      identity_hash_(identity.scenario_hash),
      identity_seed_(identity.seed) {
  const OutputFolder folder = checkOutputFolder(root_, policy, identity);
  if (folder == OutputFolder::kComplete) {
    start_ = Start::kAlreadyComplete;
    return;
  }
  if (folder == OutputFolder::kResume) {
    loadCheckpoint();
    return;
  }
  std::error_code ec;
  created_root_ = !fs::exists(root_, ec);
  try {
    if (folder == OutputFolder::kStartOver)
      startOver();
    makeDirectories(sequence_dir_);
    makeDirectories(root_ / kStateDir);
    checkpoint(0, json());  // marks the folder as an interrupted run of ours from now on
  } catch (const Error&) {
    removeCreated();
    throw;
  }
}

DatasetWriter::~DatasetWriter() {
  if (finished_ || start_ == Start::kAlreadyComplete)
    return;
  if (start_ == Start::kFresh && committed_sample_ == 0) {
    // Not one frame complete: nothing worth resuming, so the run leaves no trace.
    append_files_.clear();
    removeCreated();
    return;
  }
  rollBack();
  if (committed_sample_ > resume_sample_)  // this run got further: say how to go on
    logWarn(
        fmt::format("{} keeps the run up to sample {}: continue it with --resume (checkpoint {})",
                    root_.string(), committed_sample_, checkpointFile().string()));
}

void DatasetWriter::removeCreated() noexcept {
  std::error_code ec;
  if (created_root_) {
    fs::remove_all(root_, ec);
    return;
  }
  for (const auto& entry : DatasetLayout::ownEntries())
    fs::remove_all(root_ / entry, ec);
}

fs::path DatasetWriter::checkpointFile() const {
  return root_ / kCheckpoint;
}

fs::path DatasetWriter::inside(const fs::path& relative) const {
  if (!DatasetLayout::isInside(relative))
    throw RuntimeError(fmt::format("refusing to write {}: the path leaves the dataset folder {}",
                                   messageValue(relative.string()), root_.string()));
  return root_ / relative;
}

void removeOwnEntries(const fs::path& root) {
  for (const auto& entry : DatasetLayout::ownEntries())
    removeAll(root / entry);
}

void DatasetWriter::startOver() {
  removeOwnEntries(root_);
}

void DatasetWriter::loadCheckpoint() {
  const fs::path file = checkpointFile();
  const json cp = readRecord(file);
  const auto refuse = [&](const std::string& why) {
    throw ConfigError(
        fmt::format("cannot resume from {}: {}; pass --force to start over", file.string(), why));
  };
  if (!cp.is_object() || !cp.contains("next_sample") || !cp["next_sample"].is_number_integer() ||
      !cp.contains("files") || !cp["files"].is_object() || !cp.contains("state"))
    refuse("it lacks next_sample, files or state");
  resume_sample_ = cp["next_sample"].get<std::int64_t>();
  if (resume_sample_ < 0)
    refuse(fmt::format("next_sample {} is negative", resume_sample_));
  resume_state_ = cp["state"];
  for (const auto& [key, length] : cp["files"].items()) {
    if (!DatasetLayout::isInside(key) || fs::path(key).lexically_normal() != fs::path(key))
      refuse(fmt::format("it lists {}, which is not a path inside the dataset", messageValue(key)));
    if (!length.is_number_integer() || length.get<std::int64_t>() < 0)
      refuse(fmt::format("the length of {} is not a byte count", key));
    const std::int64_t want = length.get<std::int64_t>();
    std::error_code ec;
    const fs::path path = root_ / key;
    if (!fs::is_regular_file(path, ec))
      refuse(fmt::format("it records {} bytes of {}, which is missing", want, key));
    const auto have = static_cast<std::int64_t>(fs::file_size(path, ec));
    if (ec || have < want)
      refuse(fmt::format("it records {} bytes of {}, which holds {}", want, key, have));
    resume_lengths_[key] = want;
  }
  start_ = Start::kResume;
  committed_lengths_ = resume_lengths_;
  committed_sample_ = resume_sample_;
  // Temporary files of the killed process are garbage; whole files it renamed into place
  // after its last checkpoint are rewritten identically by the resumed run.
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(root_, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_regular_file() && isAtomicTemporary(it->path())) {
      fs::remove(it->path(), ec);
    }
  }
}

void DatasetWriter::writeFile(const fs::path& relative, std::string_view bytes) {
  const fs::path path = inside(relative);
  makeDirectories(path.parent_path());
  writeFileAtomic(path, bytes);
}

AppendFile& DatasetWriter::appendFile(const fs::path& relative) {
  const std::string key = relative.generic_string();
  if (const auto it = append_files_.find(key); it != append_files_.end())
    return *it->second;
  const fs::path path = inside(relative);
  makeDirectories(path.parent_path());
  const auto it = resume_lengths_.find(key);
  if (start_ == Start::kResume && committed_sample_ > 0 && it == resume_lengths_.end())
    throw ConfigError(
        fmt::format("cannot resume from {}: it does not record {}; pass --force to "
                    "start over",
                    checkpointFile().string(), key));
  // Made before it is filed, so that no slot ever holds a file that failed to open.
  auto file = std::make_unique<AppendFile>(path, it != resume_lengths_.end() ? it->second : -1);
  committed_lengths_[key] = it != resume_lengths_.end() ? it->second : 0;
  return *append_files_.emplace(key, std::move(file)).first->second;
}

void DatasetWriter::checkpoint(std::int64_t next_sample, const json& state) {
  json files = json::object();
  for (auto& [key, file] : append_files_) {
    files[key] = file->flush();
  }
  // Files of the interrupted run that this run has not reopened yet keep their lengths.
  for (const auto& [key, length] : resume_lengths_) {
    if (!files.contains(key))
      files[key] = length;
  }
  const json cp = {{"scenario_hash", identity_hash_},
                   {"seed", identity_seed_},
                   {"next_sample", next_sample},
                   {"files", files},
                   {"state", state}};
  writeFileAtomic(root_ / kCheckpoint, cp.dump(1) + "\n");
  committed_lengths_ = files.get<std::map<std::string, std::int64_t>>();
  committed_sample_ = next_sample;
}

void DatasetWriter::finish(const json& manifest) {
  for (auto& [key, file] : append_files_)
    file->flush();
  append_files_.clear();
  writeFileAtomic(root_ / kManifest, manifest.dump(2) + "\n", /*sync=*/true);
  removeAll(root_ / kStateDir);
  finished_ = true;
}

void DatasetWriter::rollBack() noexcept {
  // A failed or cancelled run leaves complete frames only: every append file is cut back to
  // the last checkpoint, so the folder can be resumed or inspected without partial lines.
  for (auto& [key, file] : append_files_) {
    try {
      const auto it = committed_lengths_.find(key);
      file->truncate(it != committed_lengths_.end() ? it->second : 0);
    } catch (const std::exception& e) {
      logWarn(e.what());
    }
  }
}

}  // namespace trainsim::io
