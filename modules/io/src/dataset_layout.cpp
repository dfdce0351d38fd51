#include "trainsim/io/dataset_layout.hpp"

#include <fmt/format.h>

#include "trainsim/core/error.hpp"
#include "trainsim/io/file_io.hpp"

namespace trainsim::io {
namespace {

constexpr const char* kFormat = "trainsim-dataset";
constexpr int kKittiFirstColourCamera = 2;

std::string numbered(std::string_view base, int index) {
  return index == 0 ? std::string(base) : fmt::format("{}_{}", base, index);
}

std::string cameraFolder(std::string_view base, int index) {
  return fmt::format("{}_{}", base, index + kKittiFirstColourCamera);
}

}  // namespace

DatasetLayout::DatasetLayout(int sequence) : sequence_(sequence) {
  if (sequence < 0 || sequence > 99)
    throw ConfigError(fmt::format("dataset sequence {} is outside 0..99", sequence));
}

std::string DatasetLayout::sequenceName() const {
  return fmt::format("{:02}", sequence_);
}

std::filesystem::path DatasetLayout::sequenceDir() const {
  return std::filesystem::path(kSequences) / sequenceName();
}

std::filesystem::path DatasetLayout::inSequence(std::string_view name) const {
  return sequenceDir() / name;
}

std::vector<std::string> DatasetLayout::sequenceFiles() {
  return {kTimes, kPoses, kCalib, kInstances};
}

std::vector<std::string> DatasetLayout::ownEntries() {
  return {kManifest, kScenario,  kRailroad, kTrajectory, kDesignReport,
          kClasses,  kSequences, kScene,    kStateDir};
}

bool DatasetLayout::isInside(const std::filesystem::path& relative) {
  if (relative.empty() || relative.has_root_path())
    return false;
  for (const auto& part : relative) {
    const std::string s = part.string();
    if (s.empty() || s == "." || s == "..")
      return false;
  }
  return true;
}

std::string DatasetLayout::velodyneFolder(int index) {
  return numbered("velodyne", index);
}
std::string DatasetLayout::labelsFolder(int index) {
  return numbered("labels", index);
}
std::string DatasetLayout::pointInfoFolder(int index) {
  return numbered("point_info", index);
}
std::string DatasetLayout::pcdFolder(int index) {
  return numbered("pcd", index);
}
std::string DatasetLayout::imageFolder(int index) {
  return cameraFolder("image", index);
}
std::string DatasetLayout::depthFolder(int index) {
  return cameraFolder("depth", index);
}
std::string DatasetLayout::semanticFolder(int index) {
  return cameraFolder("semantic", index);
}
std::string DatasetLayout::semanticPreviewFolder(int index) {
  return cameraFolder("semantic_rgb", index);
}
std::string DatasetLayout::instanceFolder(int index) {
  return cameraFolder("instance", index);
}

std::string DatasetLayout::frameFile(std::string_view folder, std::int64_t frame,
                                     std::string_view extension) {
  return fmt::format("{}/{:06}.{}", folder, frame, extension);
}

nlohmann::json Manifest::toJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const ManifestSensor& s : sensors) {
    nlohmann::json item = {
        {"name", s.name}, {"kind", s.kind}, {"readings", s.readings}, {"files", s.files}};
    if (!s.summary.is_null())
      item["summary"] = s.summary;
    list.push_back(std::move(item));
  }
  nlohmann::json out = {
      {"format", kFormat},
      {"version", version},
      {"scenario_hash", scenario_hash},
      {"seed", seed},
      {"sequence", sequence},
      {"sequence_dir", sequence_dir},
      {"trajectory", {{"sample_period_ns", sample_period_ns}, {"samples", samples}}},
      {"frames", frames},
      {"sensors", list},
      {"not_simulated", not_simulated},
  };
  if (!classes.is_null())
    out["classes"] = classes;
  return out;
}

Manifest Manifest::fromJson(const nlohmann::json& doc, const std::string& source) {
  try {
    if (doc.at("format") != kFormat)
      throw IoError(fmt::format("{} is not a TrainSim dataset manifest", source));
    Manifest m;
    m.version = doc.at("version").get<std::string>();
    m.scenario_hash = doc.at("scenario_hash").get<std::string>();
    m.seed = doc.at("seed").get<std::uint64_t>();
    m.sequence = doc.at("sequence").get<std::string>();
    m.sequence_dir = doc.at("sequence_dir").get<std::string>();
    const nlohmann::json& t = doc.at("trajectory");
    m.sample_period_ns = t.at("sample_period_ns").get<std::int64_t>();
    m.samples = t.at("samples").get<std::int64_t>();
    m.frames = doc.at("frames").get<std::int64_t>();
    for (const nlohmann::json& s : doc.at("sensors"))
      m.sensors.push_back({s.at("name").get<std::string>(), s.at("kind").get<std::string>(),
                           s.at("readings").get<std::int64_t>(),
                           s.at("files").get<std::vector<std::string>>(),
                           s.value("summary", nlohmann::json())});
    m.not_simulated = doc.at("not_simulated").get<std::vector<std::string>>();
    m.classes = doc.value("classes", nlohmann::json());
    return m;
  } catch (const nlohmann::json::exception& e) {
    throw IoError(fmt::format("{}: not a readable TrainSim manifest ({})", source, e.what()));
  }
}

Manifest Manifest::read(const std::filesystem::path& root) {
  const std::filesystem::path file = root / DatasetLayout::kManifest;
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(readFile(file));
  } catch (const nlohmann::json::exception& e) {
    throw IoError(fmt::format("{}: malformed JSON ({})", file.string(), e.what()));
  }
  return fromJson(doc, file.string());
}

}  // namespace trainsim::io
