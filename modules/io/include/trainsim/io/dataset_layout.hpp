#pragma once

// The one owner of a dataset's paths (docs/REFERENCES.md P3) and of manifest.json. Writers,
// sensors, the studio and the tests ask it for a path rather than spelling one:
//
//   OUT/manifest.json scenario.json railroad.json trajectory.csv design_report.json classes.yaml
//   OUT/sequences/NN/  times.txt poses.txt calib.txt  <sensor>.csv …
//                      velodyne/ labels/ point_info/ (first LiDAR), velodyne_1/ … (second), …
//                      image_2/ depth_2/ semantic_2/ instance_2/ (first camera), image_3/ …
//
// Paths are relative to the dataset root unless a function says otherwise.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace trainsim::io {

class DatasetLayout {
 public:
  static constexpr const char* kManifest = "manifest.json";
  static constexpr const char* kScenario = "scenario.json";
  static constexpr const char* kRailroad = "railroad.json";
  static constexpr const char* kTrajectory = "trajectory.csv";
  static constexpr const char* kDesignReport = "design_report.json";
  static constexpr const char* kClasses = "classes.yaml";
  static constexpr const char* kSequences = "sequences";
  /// `plan --scene`: terrain tiles, objects.csv, scene.vtm.
  static constexpr const char* kScene = "scene";
  /// Run state while a run is in progress (the checkpoint); removed when it completes.
  static constexpr const char* kStateDir = ".trainsim";
  static constexpr const char* kCheckpoint = ".trainsim/checkpoint.json";
  /// In the sequence folder.
  static constexpr const char* kTimes = "times.txt";
  static constexpr const char* kPoses = "poses.txt";
  static constexpr const char* kCalib = "calib.txt";
  /// The sequence's 16-bit instance ids (the .label files' upper half) and what they are.
  static constexpr const char* kInstances = "instances.csv";

  /// KITTI sequence 0..99 (sequences/00 … sequences/99). Throws ConfigError outside.
  explicit DatasetLayout(int sequence = 0);

  int sequence() const { return sequence_; }
  /// "00".."99".
  std::string sequenceName() const;
  /// sequences/NN.
  std::filesystem::path sequenceDir() const;
  /// A file of the sequence folder, relative to the root: sequences/NN/<name>.
  std::filesystem::path inSequence(std::string_view name) const;

  /// Files the run writes into the sequence folder itself (no sensor may take their names).
  static std::vector<std::string> sequenceFiles();
  /// Top-level entries TrainSim writes into a dataset folder (and may remove with --force).
  static std::vector<std::string> ownEntries();
  /// Whether `relative` stays inside the dataset root: relative, no "..", no empty or "."
  /// component. Every path the writers open is checked (defence in depth behind the
  /// scenario's name rules).
  static bool isInside(const std::filesystem::path& relative);

  /// Folders of LiDAR `index` (0 = the first) in the sequence folder: velodyne, velodyne_1, …
  /// and labels, labels_1, … (KITTI and SemanticKITTI read the first pair unchanged).
  static std::string velodyneFolder(int index);
  static std::string labelsFolder(int index);
  /// point_info, point_info_1, …: per point ring, firing time, return index, range, material
  /// (a folder of its own: SemanticKITTI's tools read every file in velodyne/ as a scan).
  static std::string pointInfoFolder(int index);
  static std::string pcdFolder(int index);
  /// Folders of camera `index` (0 = the first): image_2, image_3, … and depth_N, semantic_N,
  /// instance_N with the same N (KITTI numbers the left colour camera 2).
  static std::string imageFolder(int index);
  static std::string depthFolder(int index);
  static std::string semanticFolder(int index);
  /// semantic_rgb_N: the semantic image in the classes' colours, for people to look at.
  static std::string semanticPreviewFolder(int index);
  static std::string instanceFolder(int index);
  /// A frame's file in a per-frame folder: <folder>/000042.<extension>, relative to the
  /// sequence folder.
  static std::string frameFile(std::string_view folder, std::int64_t frame,
                               std::string_view extension);

 private:
  int sequence_;
};

/// One sensor in manifest.json.
struct ManifestSensor {
  std::string name;
  std::string kind;
  std::int64_t readings = 0;
  std::vector<std::string> files;  ///< relative to the dataset root; the readings file first
  nlohmann::json summary;          ///< what the sensor reports about the run (null: nothing)
};

/// manifest.json: written last, the mark of a complete dataset.
struct Manifest {
  std::string version;
  std::string scenario_hash;
  std::uint64_t seed = 0;
  std::string sequence;      ///< "00"
  std::string sequence_dir;  ///< "sequences/00"
  std::int64_t sample_period_ns = 0;
  std::int64_t samples = 0;
  std::int64_t frames = 0;
  std::vector<ManifestSensor> sensors;
  std::vector<std::string> not_simulated;  ///< pipeline stages not built yet
  /// The class table the labels use: per class its id, name, colour, whether it has instances,
  /// and its nearest SemanticKITTI, RailSem19 and OSDaR23 names (classes.yaml has the same with
  /// the point counts). Null when not known (a manifest written before it was added).
  nlohmann::json classes;

  nlohmann::json toJson() const;
  /// Throws IoError naming `source` if the document is not a TrainSim manifest.
  static Manifest fromJson(const nlohmann::json& doc, const std::string& source);
  /// Reads ROOT/manifest.json.
  static Manifest read(const std::filesystem::path& root);
};

}  // namespace trainsim::io
