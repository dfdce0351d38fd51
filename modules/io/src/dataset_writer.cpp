#include "trainsim/io/dataset_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
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

json readJson(const fs::path& path) {
  try {
    return json::parse(readFile(path));
  } catch (const json::exception& e) {
    throw IoError(
        fmt::format("{} is damaged ({}); use --force to start over", path.string(), e.what()));
  }
}

}  // namespace

DatasetWriter::DatasetWriter(fs::path root, const DatasetLayout& layout,
                             const RunIdentity& identity, const OutputPolicy& policy)
    : root_(std::move(root)),
      layout_(layout),
      sequence_dir_(root_ / layout.sequenceDir()),
      identity_hash_(identity.scenario_hash),
      identity_seed_(identity.seed) {
  if (policy.force && policy.resume) {
    throw ConfigError("--force and --resume exclude each other");
  }
  std::error_code exists_ec;
  const bool existed = fs::exists(root_, exists_ec);
  prepare(identity, policy);
  if (start_ == Start::kAlreadyComplete) {
    return;
  }
  try {
    makeDirectories(sequence_dir_);
    makeDirectories(root_ / kStateDir);
    if (start_ == Start::kFresh) {
      checkpoint(0, json());  // marks the folder as an interrupted run of ours from now on
    }
  } catch (const IoError&) {
    // Leave nothing behind: a folder this writer created goes again; in an existing folder
    // only the entries a fresh run creates are removed.
    std::error_code ec;
    if (!existed) {
      fs::remove_all(root_, ec);
    } else if (start_ == Start::kFresh) {
      fs::remove_all(root_ / DatasetLayout::kSequences, ec);
      fs::remove_all(root_ / kStateDir, ec);
    }
    throw;
  }
}

DatasetWriter::~DatasetWriter() {
  if (!finished_ && start_ != Start::kAlreadyComplete)
    rollBack();
}

void DatasetWriter::prepare(const RunIdentity& identity, const OutputPolicy& policy) {
  const std::string where = root_.string();
  std::error_code ec;
  const fs::file_status status = fs::status(root_, ec);
  if (!fs::exists(status)) {
    makeDirectories(root_);
    return;
  }
  if (!fs::is_directory(status)) {
    throw ConfigError("output " + where + " exists and is not a folder");
  }
  if (isEmptyDirectory(root_))
    return;

  const bool interrupted = fs::exists(root_ / kCheckpoint);
  const bool complete = !interrupted && fs::exists(root_ / kManifest);
  if (policy.force) {
    startOver();
    return;
  }
  if (interrupted || complete) {
    if (!policy.resume) {
      throw ConfigError(
          interrupted
              ? "output " + where +
                    " holds an interrupted run: pass --resume to continue it or --force to "
                    "start over"
              : "output " + where + " already holds a dataset: pass --force to overwrite it");
    }
    if (complete) {
      const json manifest = readJson(root_ / kManifest);
      if (manifest.value("scenario_hash", "") != identity.scenario_hash ||
          manifest.value("seed", std::uint64_t{0}) != identity.seed) {
        throw ConfigError("output " + where +
                          " holds a dataset of a different scenario or seed; pass --force to "
                          "overwrite it");
      }
      start_ = Start::kAlreadyComplete;
      return;
    }
    loadCheckpoint(identity);
    return;
  }
  throw ConfigError("output " + where +
                    " is not empty and was not written by trainsim: choose an empty folder or "
                    "pass --force (which removes only TrainSim's own entries from it)");
}

void DatasetWriter::startOver() {
  for (const auto& entry : DatasetLayout::ownEntries()) {
    removeAll(root_ / entry);
  }
}

void DatasetWriter::loadCheckpoint(const RunIdentity& identity) {
  const json cp = readJson(root_ / kCheckpoint);
  if (cp.value("scenario_hash", "") != identity.scenario_hash ||
      cp.value("seed", std::uint64_t{0}) != identity.seed) {
    throw ConfigError(fmt::format(
        "output {} holds an interrupted run of another scenario or seed (hash {}, seed {}); "
        "pass --force to start over",
        root_.string(), cp.value("scenario_hash", "?"), cp.value("seed", std::uint64_t{0})));
  }
  start_ = Start::kResume;
  resume_sample_ = cp.at("next_sample").get<std::int64_t>();
  resume_state_ = cp.at("state");
  resume_lengths_ = cp.at("files").get<std::map<std::string, std::int64_t>>();
  committed_lengths_ = resume_lengths_;
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
  const fs::path path = root_ / relative;
  makeDirectories(path.parent_path());
  writeFileAtomic(path, bytes);
}

AppendFile& DatasetWriter::appendFile(const fs::path& relative) {
  const std::string key = relative.generic_string();
  auto& slot = append_files_[key];
  if (!slot) {
    const fs::path path = root_ / relative;
    makeDirectories(path.parent_path());
    const auto it = resume_lengths_.find(key);
    slot = std::make_unique<AppendFile>(path, it != resume_lengths_.end() ? it->second : -1);
    committed_lengths_[key] = it != resume_lengths_.end() ? it->second : 0;
  }
  return *slot;
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
