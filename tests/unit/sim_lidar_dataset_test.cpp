// The LiDAR's dataset, read back as a user's tools would: a reader written here to the KITTI
// odometry and SemanticKITTI specifications (velodyne/*.bin float32 x y z intensity, labels/*.label
// uint32 class | instance << 16, calib.txt Tr, poses.txt, times.txt), the point_info side files,
// instances.csv and classes.yaml. Every sampled point is put back into the world through
// poses.txt and Tr alone and checked against an independent double-precision brute-force ray
// cast into the same scene; the whole dataset is byte-identical on 1 and 2 threads. PCL reads
// the PCD copies back to the same points, labels, rings and times.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <unistd.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <Eigen/Geometry>

#include "trainsim/core/frames.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/lidar/fog.hpp"
#include "trainsim/lidar/intensity.hpp"
#include "trainsim/scene/semantics.hpp"
#include "trainsim/sim/generate.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::sim {
namespace {

namespace fs = std::filesystem;

constexpr double kMountX = 10.0, kMountZ = 4.0, kMountYawDeg = 4.0, kMountPitchDeg = -2.0;

scenario::Json lidarScenario() {
  return {{"seed", 11},
          {"route", {{"generator", {{"length_m", 600}, {"station", {{"probability", 0.5}}}}}}},
          {"dataset", {{"frame_period_ns", 2'000'000'000}}},
          {"sensors",
           {{"lidars",
             {{{"model", "vlp16"},
               {"period_ns", 2'000'000'000},
               {"columns", 900},
               {"range_sigma_m", 0.0},
               {"pcd", true},
               {"mount",
                {{"x_m", kMountX},
                 {"z_m", kMountZ},
                 {"yaw_deg", kMountYawDeg},
                 {"pitch_deg", kMountPitchDeg}}}}}}}}};
}

scenario::Scenario resolved() {
  return scenario::Scenario::resolve(lidarScenario(), scenarioSchema());
}

fs::path generateOnce(const std::string& folder, int threads) {
  // CTest runs each test as its own process, several at once: a folder per process.
  const fs::path out = fs::temp_directory_path() / fmt::format("{}_{}", folder, ::getpid());
  fs::remove_all(out);
  GenerateOptions options;
  options.out = out;
  options.threads = threads;
  generate(resolved(), options);
  return out;
}

// One generated dataset shared by the tests of a process, removed when it exits.
struct Dataset {
  fs::path root = generateOnce("trainsim_lidar_dataset", 2);
  ~Dataset() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
};
const fs::path& dataset() {
  static const Dataset d;
  return d.root;
}

fs::path sequence() {
  return dataset() / "sequences" / "00";
}

std::string bytes(const fs::path& p) {
  return io::readFile(p, std::size_t{1} << 30);
}

// --- A reader written to the KITTI / SemanticKITTI specifications -------------------------

struct KittiPoint {
  Eigen::Vector3f xyz;
  float intensity;
};

std::vector<KittiPoint> readVelodyne(const fs::path& p) {
  const std::string b = bytes(p);
  EXPECT_EQ(b.size() % 16, 0u) << p;
  std::vector<KittiPoint> out(b.size() / 16);
  for (std::size_t i = 0; i < out.size(); ++i) {
    float v[4];
    std::memcpy(v, b.data() + 16 * i, 16);
    out[i] = {{v[0], v[1], v[2]}, v[3]};
  }
  return out;
}

std::vector<std::uint32_t> readLabels(const fs::path& p) {
  const std::string b = bytes(p);
  EXPECT_EQ(b.size() % 4, 0u) << p;
  std::vector<std::uint32_t> out(b.size() / 4);
  std::memcpy(out.data(), b.data(), b.size());
  return out;
}

struct PointInfo {
  float time_s, range_m;
  std::uint16_t ring;
  std::uint8_t return_index, material;
};

std::vector<PointInfo> readPointInfo(const fs::path& p) {
  const std::string b = bytes(p);
  EXPECT_EQ(b.size() % 12, 0u) << p;
  std::vector<PointInfo> out(b.size() / 12);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const char* r = b.data() + 12 * i;
    std::memcpy(&out[i].time_s, r, 4);
    std::memcpy(&out[i].range_m, r + 4, 4);
    std::memcpy(&out[i].ring, r + 8, 2);
    std::memcpy(&out[i].return_index, r + 10, 1);
    std::memcpy(&out[i].material, r + 11, 1);
  }
  return out;
}

// A 3×4 row-major line as a 4×4 transform ("Tr: …" or a poses.txt line).
Eigen::Isometry3d transformFrom(std::istringstream& line) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      line >> m(r, c);
  EXPECT_FALSE(line.fail());
  return Eigen::Isometry3d(m);
}

std::map<std::string, Eigen::Isometry3d> readCalib() {
  std::ifstream in(sequence() / "calib.txt");
  std::map<std::string, Eigen::Isometry3d> out;
  for (std::string text; std::getline(in, text);) {
    std::istringstream line(text);
    std::string key;
    line >> key;
    out[key.substr(0, key.size() - 1)] = transformFrom(line);
  }
  return out;
}

std::vector<Eigen::Isometry3d> readPoses() {
  std::ifstream in(sequence() / "poses.txt");
  std::vector<Eigen::Isometry3d> out;
  for (std::string text; std::getline(in, text);) {
    std::istringstream line(text);
    out.push_back(transformFrom(line));
  }
  return out;
}

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);)
    out.push_back(l);
  return out;
}

std::int64_t frames() {
  return static_cast<std::int64_t>(lines(sequence() / "times.txt").size());
}

fs::path frameFile(const char* folder, std::int64_t frame, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "%06lld.%s", static_cast<long long>(frame), ext);
  return sequence() / folder / name;
}

TEST(LidarDataset, FilesAgreeFrameByFrameWithEachOtherAndTheTables) {
  const std::int64_t n = frames();
  ASSERT_GE(n, 20);
  // lidar.csv: one row per scan with its point count.
  const std::vector<std::string> csv = lines(sequence() / "lidar.csv");
  ASSERT_EQ(static_cast<std::int64_t>(csv.size()), n + 1);
  // instances.csv: id, scene instance, class name.
  std::map<std::uint32_t, std::string> instance_class;
  std::set<std::uint32_t> signals;
  for (const std::string& l : lines(sequence() / "instances.csv")) {
    if (l.rfind("instance,", 0) == 0)
      continue;
    std::istringstream s(l);
    std::string id, scene_id, cls;
    std::getline(s, id, ',');
    std::getline(s, scene_id, ',');
    std::getline(s, cls, ',');
    EXPECT_EQ(instance_class.count(std::stoul(id)), 0u);
    EXPECT_EQ(std::stoul(id), instance_class.size() + 1) << "ids are dense from 1";
    instance_class[static_cast<std::uint32_t>(std::stoul(id))] = cls;
    const auto asset = scene::trackAsset(std::stoull(scene_id));
    if (asset && asset->kind == 12)  // a signal
      signals.insert(static_cast<std::uint32_t>(std::stoul(id)));
  }
  EXPECT_GT(instance_class.size(), 10u);
  std::int64_t points = 0;
  std::set<std::uint32_t> seen;
  std::map<std::uint32_t, std::set<std::string>> classes_of;
  for (std::int64_t f = 0; f < n; ++f) {
    const auto cloud = readVelodyne(frameFile("velodyne", f, "bin"));
    const auto labels = readLabels(frameFile("labels", f, "label"));
    const auto info = readPointInfo(frameFile("point_info", f, "bin"));
    ASSERT_EQ(labels.size(), cloud.size()) << f;
    ASSERT_EQ(info.size(), cloud.size()) << f;
    const std::string& row = csv[static_cast<std::size_t>(f + 1)];
    EXPECT_EQ(row.substr(0, row.find(',')), std::to_string(f));
    EXPECT_EQ(std::stoul(row.substr(row.find(',', row.find(',') + 1) + 1)), cloud.size());
    ASSERT_GT(cloud.size(), 3000u);  // of 14 400 beams; the roof hides about a third
    points += static_cast<std::int64_t>(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const std::uint32_t cls = labels[i] & 0xFFFF, inst = labels[i] >> 16;
      ASSERT_LT(cls, scene::classes().size());
      EXPECT_NE(cls, scene::cls::kSky);
      EXPECT_NE(cls, scene::cls::kUnlabelled);
      if (inst != 0) {
        ASSERT_EQ(instance_class.count(inst), 1u) << inst;
        classes_of[inst].insert(scene::semanticClass(static_cast<scene::ClassId>(cls)).name);
        seen.insert(inst);
      }
      EXPECT_TRUE(std::isfinite(cloud[i].xyz.norm()));
      EXPECT_GE(cloud[i].intensity, 0.0f);
      EXPECT_LE(cloud[i].intensity, 1.0f);
      EXPECT_LT(info[i].ring, 16);
      EXPECT_GE(info[i].time_s, 0.0f);
      EXPECT_LT(info[i].time_s, 0.1f);
      EXPECT_GE(info[i].range_m, 0.9f);
      EXPECT_LE(info[i].range_m, 100.0f);
      EXPECT_EQ(info[i].return_index, 0);
      EXPECT_LT(info[i].material, scene::materials().size());
    }
  }
  EXPECT_EQ(seen.size(), instance_class.size()) << "every listed instance was seen";
  // An object's points may carry several classes (a tree's crown and trunk, a signal's post and
  // head); instances.csv names a signal a signal, seen or not beyond its post, and anything else
  // the class it was first seen as; no object spans more than two.
  for (const auto& [inst, names] : classes_of) {
    if (signals.contains(inst)) {
      EXPECT_EQ(instance_class[inst], "signal") << inst;
    } else {
      EXPECT_EQ(names.count(instance_class[inst]), 1u) << inst;
    }
    EXPECT_LE(names.size(), 2u) << inst;
  }
  // The manifest's summary counts the same points.
  const nlohmann::json manifest = nlohmann::json::parse(bytes(dataset() / "manifest.json"));
  std::int64_t listed = -1;
  for (const auto& s : manifest.at("sensors"))
    if (s.at("kind") == "lidar")
      listed = s.at("summary").at("points").get<std::int64_t>();
  EXPECT_EQ(listed, points);
}

// KITTI's order: ring by ring from the highest laser, each ring counter-clockwise from just past
// +x, so the community's ring recovery (a new ring where the azimuth crosses +x from quadrant 4
// to quadrant 1) never splits a ring, and finds every boundary between rings that have returns
// on both sides of +x.
TEST(LidarDataset, RingsComeBackByTheQuadrantRuleInKittiOrder) {
  const auto quadrantFourToOne = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return a.x() >= 0 && a.y() < 0 && b.x() > 0 && b.y() >= 0;
  };
  int boundaries = 0;
  for (std::int64_t f = 0; f < frames(); f += 7) {
    const auto cloud = readVelodyne(frameFile("velodyne", f, "bin"));
    const auto info = readPointInfo(frameFile("point_info", f, "bin"));
    for (std::size_t i = 1; i < cloud.size(); ++i) {
      ASSERT_GE(info[i].ring, info[i - 1].ring) << "ring-major order, frame " << f;
      const bool split = quadrantFourToOne(cloud[i - 1].xyz, cloud[i].xyz);
      if (info[i].ring == info[i - 1].ring) {
        ASSERT_FALSE(split) << "a ring split at point " << i << " of frame " << f;
      } else if (info[i - 1].ring >= 8) {
        // The lower half of a VLP-16 on a roof sees the ground all round.
        EXPECT_TRUE(split) << "ring " << info[i].ring << " not found in frame " << f;
        ++boundaries;
      }
    }
  }
  EXPECT_GT(boundaries, 40);
}

TEST(LidarDataset, CalibrationAndClassTableAreWhatTheToolsExpect) {
  const auto calib = readCalib();
  ASSERT_EQ(calib.count("Tr"), 1u);
  // No camera: P0–P3 are [I | 0] (camera 0's frame, unit focal length), as pykitti's odometry
  // loader reads all four.
  ASSERT_EQ(calib.size(), 5u);
  for (const char* p : {"P0", "P1", "P2", "P3"}) {
    ASSERT_EQ(calib.count(p), 1u) << p;
    EXPECT_TRUE(calib.at(p).matrix().isIdentity(0.0)) << p;
  }
  // Tr maps the velodyne frame into camera 0 (the body reference point with KITTI camera
  // axes): the mount, worked out here independently.
  const Eigen::Matrix3d R_body_velo =
      (Eigen::AngleAxisd(kMountYawDeg * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(-kMountPitchDeg * kRadPerDeg, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  Eigen::Matrix3d R_cam_body;  // x right = -y body, y down = -z body, z forward = x body
  R_cam_body << 0, -1, 0, 0, 0, -1, 1, 0, 0;
  const Eigen::Isometry3d& Tr = calib.at("Tr");
  EXPECT_LT((Tr.linear() - R_cam_body * R_body_velo).norm(), 1e-12);
  EXPECT_LT((Tr.translation() - R_cam_body * Eigen::Vector3d(kMountX, 0, kMountZ)).norm(), 1e-12);

  // classes.yaml in SemanticKITTI's layout: every class under labels, color_map and
  // learning_map; content sums to 1.
  const std::vector<std::string> yaml = lines(dataset() / "classes.yaml");
  std::map<std::string, int> entries;
  std::string section;
  double content = 0.0;
  for (const std::string& l : yaml) {
    if (l.empty() || l[0] == '#')
      continue;
    if (l[0] != ' ') {
      section = l.substr(0, l.find(':'));
      continue;
    }
    ++entries[section];
    if (section == "content")
      content += std::stod(l.substr(l.find(':') + 1));
  }
  for (const char* key : {"labels", "color_map", "content", "learning_map", "learning_map_inv",
                          "learning_ignore", "semantickitti_map"})
    EXPECT_EQ(entries[key], static_cast<int>(scene::classes().size())) << key;
  EXPECT_NEAR(content, 1.0, 1e-6);

  // manifest.json carries the same class table (PRODUCT.md's dataset layout), read back here
  // as plain JSON.
  const auto manifest = nlohmann::json::parse(io::readFile(dataset() / "manifest.json"));
  const nlohmann::json& classes = manifest.at("classes");
  ASSERT_EQ(classes.size(), scene::classes().size());
  for (const scene::SemanticClass& c : scene::classes()) {
    const nlohmann::json& row = classes.at(c.id);
    EXPECT_EQ(row.at("id"), c.id);
    EXPECT_EQ(row.at("name"), c.name);
    EXPECT_EQ(row.at("colour"), nlohmann::json::array({c.colour[0], c.colour[1], c.colour[2]}));
    EXPECT_EQ(row.at("thing"), c.thing);
    EXPECT_EQ(row.at("semantickitti"), c.semantickitti);
  }
}

// --- An independent reference: brute-force ray casting in double ----------------------------

struct Triangle {
  Eigen::Vector3d a, b, c;
  scene::ClassId cls;
};

struct BruteForce {
  std::vector<Triangle> triangles;

  explicit BruteForce(const std::vector<std::shared_ptr<const scene::Tile>>& tiles) {
    for (const auto& tile : tiles)
      for (const scene::Object& o : tile->objects) {
        const auto& parts = o.mesh->parts;
        for (std::size_t t = 0; t < o.mesh->triangles.size(); ++t) {
          const auto part = std::prev(std::upper_bound(
              parts.begin(), parts.end(), t,
              [](std::size_t i, const scene::MeshPart& p) { return i < p.first_triangle; }));
          const auto& tri = o.mesh->triangles[t];
          triangles.push_back(
              {o.worldVertex(tri[0]), o.worldVertex(tri[1]), o.worldVertex(tri[2]), part->cls});
        }
      }
  }

  // Nearest hit along the unit ray (Möller–Trumbore), within t_max.
  std::pair<double, scene::ClassId> cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                         double t_max) const {
    const Eigen::Vector3d lo = o.cwiseMin(o + t_max * d).array() - 0.01;
    const Eigen::Vector3d hi = o.cwiseMax(o + t_max * d).array() + 0.01;
    double best = t_max;
    scene::ClassId cls = 0;
    for (const Triangle& tr : triangles) {
      if (std::max({tr.a.x(), tr.b.x(), tr.c.x()}) < lo.x() ||
          std::min({tr.a.x(), tr.b.x(), tr.c.x()}) > hi.x() ||
          std::max({tr.a.y(), tr.b.y(), tr.c.y()}) < lo.y() ||
          std::min({tr.a.y(), tr.b.y(), tr.c.y()}) > hi.y() ||
          std::max({tr.a.z(), tr.b.z(), tr.c.z()}) < lo.z() ||
          std::min({tr.a.z(), tr.b.z(), tr.c.z()}) > hi.z())
        continue;
      const Eigen::Vector3d e1 = tr.b - tr.a, e2 = tr.c - tr.a, p = d.cross(e2);
      const double det = e1.dot(p);
      if (std::abs(det) < 1e-15)
        continue;
      const Eigen::Vector3d s = o - tr.a;
      const double u = s.dot(p) / det;
      if (u < 0 || u > 1)
        continue;
      const Eigen::Vector3d q = s.cross(e1);
      const double v = d.dot(q) / det;
      if (v < 0 || u + v > 1)
        continue;
      const double t = e2.dot(q) / det;
      if (t > 1e-6 && t < best) {
        best = t;
        cls = tr.cls;
      }
    }
    return {best, cls};
  }
};

// A train standing on a 300 m straight single track for `standstill_s`, with one LiDAR `lidar`
// scanning once a second, generated into a folder of the process's own named `name`.
fs::path generateStanding(const std::string& name, double standstill_s,
                          const scenario::Json& lidar) {
  const scenario::Json input = {
      {"seed", 5},
      {"route", {{"source", "blocks"}, {"blocks", {{{"type", "straight"}, {"length_m", 300}}}}}},
      {"layout", {{"double_track", false}}},
      {"trajectory", {{"static_only", true}, {"standstill_start_s", standstill_s}}},
      {"dataset", {{"frame_period_ns", 1'000'000'000}}},
      {"sensors", {{"lidars", scenario::Json::array({lidar})}}}};
  const fs::path out = fs::temp_directory_path() / fmt::format("{}_{}", name, ::getpid());
  fs::remove_all(out);
  GenerateOptions options;
  options.out = out;
  generate(scenario::Scenario::resolve(input, scenarioSchema()), options);
  return out;
}

TEST(LidarDataset, RangeNoiseDefaultsToTheDevicesDatasheetValue) {
  // A VLP-16 (datasheet 3 cm, 1 sigma) with no range_sigma_m on a train standing still: two
  // scans of the same scene from the same pose, so each firing's two ranges differ by the noise
  // alone, with sigma 0.03 * sqrt(2).
  const fs::path out = generateStanding("trainsim_lidar_sigma", 2,
                                        {{"model", "vlp16"}, {"period_ns", 1'000'000'000}});
  const fs::path seq = out / "sequences" / "00" / "point_info";
  std::map<std::pair<std::uint16_t, float>, float> first;  // (ring, firing time) -> range
  for (const PointInfo& p : readPointInfo(seq / "000000.bin"))
    first[{p.ring, p.time_s}] = p.range_m;
  double sum = 0.0, sum2 = 0.0;
  std::size_t n = 0;
  for (const PointInfo& p : readPointInfo(seq / "000001.bin"))
    if (const auto it = first.find({p.ring, p.time_s}); it != first.end()) {
      const double e = double(p.range_m) - double(it->second);
      sum += e;
      sum2 += e * e;
      ++n;
    }
  fs::remove_all(out);
  ASSERT_GT(n, 10'000u);
  const double sigma = std::sqrt((sum2 / n - (sum / n) * (sum / n)) / 2.0);
  EXPECT_NEAR(sigma, 0.03, 0.03 * 0.03) << n << " firings";
}

TEST(LidarDataset, FogDimsTheSceneAndReturnsItsOwnEchoLabelledFog) {
  // A VLP-16 on a train standing in fog of 60 m visibility, last returns, detecting a 10 %
  // target out to 40 m in clear air: the fog's echoes (class fog, instance 0) lie within the
  // waveform's top, and no surface is returned beyond where the fog dims its material, seen
  // head-on, under the detectable power.
  const double V = 60.0, range_10 = 40.0;
  const fs::path out = generateStanding("trainsim_lidar_fog", 1,
                                        {{"model", "vlp16"},
                                         {"period_ns", 1'000'000'000},
                                         {"returns", "last"},
                                         {"range_10_percent_m", range_10},
                                         {"fog_visibility_m", V}});
  const fs::path seq = out / "sequences" / "00";
  const auto labels = readLabels(seq / "labels" / "000000.label");
  const auto info = readPointInfo(seq / "point_info" / "000000.bin");
  fs::remove_all(out);
  ASSERT_EQ(labels.size(), info.size());
  lidar::FogParams params;
  params.visibility_m = V;
  const lidar::FogModel fog(params);
  // How far each material is detected head-on (its brightest: ρ e^(−2αR) / R² = 0.1 /
  // range_10², by bisection).
  const auto reach = [&](scene::MaterialId m) {
    const double rho = lidar::reflectivity(scene::material(m), 1.0);
    double lo = 0.5, hi = 500.0;
    for (int i = 0; i < 100; ++i) {
      const double mid = 0.5 * (lo + hi);
      (rho * std::exp(-2.0 * 3.912 / V * mid) / (mid * mid) >= 0.1 / (range_10 * range_10) ? lo
                                                                                           : hi) =
          mid;
    }
    return lo;
  };
  std::size_t fogs = 0, surfaces = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if ((labels[i] & 0xFFFFu) == scene::cls::kFog) {
      ++fogs;
      EXPECT_EQ(labels[i] >> 16, 0u);
      EXPECT_GE(info[i].range_m, fog.nearRange() - 0.15);  // 3 cm range noise, 5 σ
      EXPECT_LE(info[i].range_m, fog.farRange() + 0.15);
    } else {
      ++surfaces;
      EXPECT_LE(info[i].range_m, reach(info[i].material) + 0.15)
          << scene::material(info[i].material).name;
    }
  }
  EXPECT_GT(fogs, 1000u);
  EXPECT_GT(surfaces, 1000u);
}

// The mount, from the scenario's numbers: the LiDAR's pose in body axes.
Eigen::Isometry3d bodyFromVelodyne() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(kMountYawDeg * kRadPerDeg, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-kMountPitchDeg * kRadPerDeg, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(kMountX, 0, kMountZ);
  return T;
}

TEST(LidarDataset, NothingUnderTheTrainsRoofIsSeenThroughIt) {
  // The default body (train.body: roof 3.8 m, 2.9 m wide, front edge at x = 10 m, 24 m long)
  // hides the track under and behind the sensor, which sits on the roof's front edge. In body
  // axes no point may lie in the body's footprint below the roof. The footprint is taken 6 m
  // short of the front edge: the .bin is deskewed to the scan's time, which moves a point by the
  // train's travel between its firing and that time (under 4.5 m at 160 km/h in 0.1 s).
  const Eigen::Isometry3d T_body_velo = bodyFromVelodyne();
  int under = 0, behind = 0;
  for (std::int64_t f = 0; f < frames(); ++f)
    for (const KittiPoint& p : readVelodyne(frameFile("velodyne", f, "bin"))) {
      const Eigen::Vector3d b = T_body_velo * p.xyz.cast<double>();
      if (b.x() < kMountX)
        ++behind;
      if (b.x() > -14.0 && b.x() < 4.0 && std::abs(b.y()) < 1.2 && b.z() < 3.5)
        ++under;
    }
  EXPECT_EQ(under, 0);
  // What the roof does not hide behind the sensor is still there: the ground beside the train
  // and everything above the roof's plane.
  EXPECT_GT(behind, 1000);
}

TEST(LidarDataset, EveryPointLiesWhereAnIndependentRayCastFindsTheScene) {
  const scenario::Scenario sc = resolved();
  const std::unique_ptr<Plan> plan = makePlan(sc);
  const auto environment = makeEnvironment(*plan, sc);
  const auto stream = environment->environment->stream(32);
  const Trajectory& trajectory = plan->trajectory();
  const auto calib = readCalib();
  const Eigen::Isometry3d Tr = calib.at("Tr");
  const std::vector<Eigen::Isometry3d> poses = readPoses();
  const std::vector<std::string> times = lines(sequence() / "times.txt");

  // The mount, from the scenario, as the reference the sensor is fired from.
  const Eigen::Isometry3d T_body_velo = bodyFromVelodyne();
  const auto bodyPose = [&](TimeNs t) {
    const TrajectorySample s = trajectory.at(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = s.q_world_body.toRotationMatrix();
    T.translation() = s.p_world;
    return T;
  };
  // World from camera 0 at frame 0: poses.txt is relative to it.
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  T_body_cam.linear() = rotationBodyFromKittiCamera();
  const Eigen::Isometry3d T_world_cam0 = bodyPose(0) * T_body_cam;

  int checked = 0, within = 0, same_class = 0;
  double worst = 0.0;
  for (std::int64_t f = 1; f < frames(); f += 9) {
    const auto cloud = readVelodyne(frameFile("velodyne", f, "bin"));
    const auto labels = readLabels(frameFile("labels", f, "label"));
    const auto info = readPointInfo(frameFile("point_info", f, "bin"));
    const TimeNs t0 = static_cast<TimeNs>(std::llround(std::stod(times[f]) * 1e9));
    // Points of frame f, in the world, through the files only: KITTI's LiDAR pose
    // T_velo0_velo_f = Tr⁻¹ · pose_f · Tr, anchored at frame 0's camera.
    const Eigen::Isometry3d T_world_velo = T_world_cam0 * poses[f] * Tr;
    const Eigen::Vector3d centre = T_world_velo.translation();
    const BruteForce reference(stream->window(centre, 110.0).tiles);
    for (std::size_t i = 0; i < cloud.size(); i += cloud.size() / 40) {
      const scene::ClassId cls = labels[i] & 0xFFFF;
      if (cls == scene::cls::kWire)
        continue;  // wires are capsules, not triangles (checked exactly in unit_lidar)
      const Eigen::Vector3d world = T_world_velo * cloud[i].xyz.cast<double>();
      // The firing position: the mount on the body at the firing time.
      const TimeNs fired = t0 + static_cast<TimeNs>(std::llround(info[i].time_s * 1e9));
      const Eigen::Vector3d origin = (bodyPose(fired) * T_body_velo).translation();
      const double range = (world - origin).norm();
      const auto [hit, hit_cls] = reference.cast(origin, (world - origin) / range, range + 1.0);
      ++checked;
      const double error = std::abs(hit - range);
      worst = std::max(worst, error);
      within += error <= 1e-3;
      same_class += hit_cls == cls;
      EXPECT_NEAR(range, info[i].range_m, 2e-3);
    }
  }
  ASSERT_GT(checked, 150);
  // Grazing silhouettes may fall either side of an edge in float and double: a few percent.
  EXPECT_GE(within, checked * 97 / 100) << "worst " << worst << " m";
  EXPECT_GE(same_class, checked * 97 / 100);
  std::printf("checked %d points: %d within 1 mm, %d of the same class, worst %.4f m\n", checked,
              within, same_class, worst);
}

// A field of a PCL cloud read through PCL's own field table.
template <typename T>
T pclField(const pcl::PCLPointCloud2& cloud, const char* name, std::size_t point) {
  const int f = pcl::getFieldIndex(cloud, name);
  EXPECT_GE(f, 0) << name;
  T value{};
  std::memcpy(&value, cloud.data.data() + point * cloud.point_step + cloud.fields[f].offset,
              sizeof value);
  return value;
}

TEST(LidarDataset, PclReadsThePcdFilesAsTheKittiFiles) {
  const std::int64_t n = frames();
  for (std::int64_t f = 0; f < n; f += 7) {
    const fs::path pcd = frameFile("pcd", f, "pcd");
    pcl::PCLPointCloud2 cloud;
    ASSERT_EQ(pcl::io::loadPCDFile(pcd.string(), cloud), 0) << pcd;
    const auto kitti = readVelodyne(frameFile("velodyne", f, "bin"));
    const auto labels = readLabels(frameFile("labels", f, "label"));
    const auto info = readPointInfo(frameFile("point_info", f, "bin"));
    ASSERT_EQ(cloud.width * cloud.height, kitti.size());
    const std::map<std::string, std::uint8_t> types = {
        {"x", pcl::PCLPointField::FLOAT32},   {"y", pcl::PCLPointField::FLOAT32},
        {"z", pcl::PCLPointField::FLOAT32},   {"intensity", pcl::PCLPointField::FLOAT32},
        {"ring", pcl::PCLPointField::UINT16}, {"time", pcl::PCLPointField::FLOAT32},
        {"label", pcl::PCLPointField::UINT32}};
    ASSERT_EQ(cloud.fields.size(), types.size());
    for (const pcl::PCLPointField& field : cloud.fields)
      EXPECT_EQ(types.at(field.name), field.datatype) << field.name;
    // PCL's own point types take the fields they know by name.
    pcl::PointCloud<pcl::PointXYZI> xyzi;
    pcl::PointCloud<pcl::PointXYZL> xyzl;
    pcl::fromPCLPointCloud2(cloud, xyzi);
    pcl::fromPCLPointCloud2(cloud, xyzl);
    // The ring as Velodyne's ROS driver numbers it (LeGO-LOAM takes its ground rows from ring
    // 0 up): 0 the lowest laser, where point_info counts from the highest as KITTI's order does.
    constexpr int kVlp16Lasers = 16;
    std::map<int, std::pair<double, int>> elevation;  // PCD ring -> sum of elevations, count
    for (std::size_t i = 0; i < kitti.size(); ++i) {
      ASSERT_EQ(xyzi[i].getVector3fMap(), kitti[i].xyz) << pcd << " point " << i;
      ASSERT_EQ(xyzi[i].intensity, kitti[i].intensity);
      ASSERT_EQ(xyzl[i].label, labels[i]);
      const int ring = pclField<std::uint16_t>(cloud, "ring", i);
      ASSERT_EQ(ring, kVlp16Lasers - 1 - info[i].ring);
      ASSERT_EQ(pclField<float>(cloud, "time", i), info[i].time_s);
      const Eigen::Vector3d p = kitti[i].xyz.cast<double>();
      elevation[ring].first += std::atan2(p.z(), p.head<2>().norm());
      ++elevation[ring].second;
    }
    double below = -M_PI;
    for (const auto& [ring, sum] : elevation) {
      const double mean = sum.first / sum.second;
      EXPECT_GT(mean, below) << "ring " << ring << ", frame " << f;
      below = mean;
    }
  }
}

TEST(LidarDataset, SameBytesOnOneAndTwoThreads) {
  const fs::path one = generateOnce("trainsim_lidar_dataset_t1", 1);
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dataset())) {
    if (!entry.is_regular_file())
      continue;
    const fs::path relative = fs::relative(entry.path(), dataset());
    ASSERT_TRUE(fs::exists(one / relative)) << relative;
    ASSERT_EQ(bytes(entry.path()), bytes(one / relative)) << relative;
    ++files;
  }
  EXPECT_GT(files, 60u);
  fs::remove_all(one);
}

}  // namespace
}  // namespace trainsim::sim
