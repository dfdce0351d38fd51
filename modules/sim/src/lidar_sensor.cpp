#include "lidar_sensor.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <ranges>

#include <Eigen/Geometry>

#include "class_counts.hpp"
#include "lidar_config.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/io/packed.hpp"
#include "trainsim/io/pcd.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/instance_table.hpp"
#include "trainsim/sim/sensor_params.hpp"
#include "trainsim/sim/sensor_registry.hpp"

namespace trainsim::sim {
namespace {

static_assert(std::endian::native == std::endian::little,
              "KITTI .bin and .label files are little-endian; this writer copies memory as is");

// The sensor's pose over one scan: exact at knots kKnotNs apart, between them cubic Hermite in
// position (with the velocity) and slerp in attitude. A train's motion over 1 ms is smooth to
// far below a micrometre this way, and a 2083-column scan costs ~100 trajectory evaluations
// instead of one per column.
class ScanPoses {
 public:
  static constexpr TimeNs kKnotNs = 1'000'000;

  ScanPoses(const Trajectory& trajectory, const Eigen::Isometry3d& T_body_sensor, TimeNs t0,
            double span_s) {
    // At least two knots, covering [t0, t0 + span].
    const auto knots =
        std::max<std::int64_t>(2, static_cast<std::int64_t>(std::ceil(span_s * 1e9 / kKnotNs)) + 1);
    const Eigen::Vector3d& r = T_body_sensor.translation();
    for (std::int64_t i = 0; i < knots; ++i) {
      const TimeNs t = t0 + i * kKnotNs;
      const TrajectorySample s = trajectory.at(t);
      const Eigen::Matrix3d R = s.q_world_body.toRotationMatrix();
      Knot k;
      k.p = s.p_world + R * r;
      // Outside the trajectory the train stands at its end (Trajectory::at clamps).
      const bool inside = t >= 0 && t <= trajectory.endTime();
      k.v = inside ? Eigen::Vector3d(s.v_world + R * s.w_body.cross(r)) : Eigen::Vector3d::Zero();
      k.q = s.q_world_body * Eigen::Quaterniond(T_body_sensor.linear());
      if (!knots_.empty() && knots_.back().q.dot(k.q) < 0.0)
        k.q.coeffs() = -k.q.coeffs();
      knots_.push_back(k);
    }
  }

  // The sensor's world pose `t` seconds after t0.
  Eigen::Isometry3d at(double t) const {
    const double x = std::clamp(t * 1e9 / kKnotNs, 0.0, static_cast<double>(knots_.size() - 1));
    const auto i = std::min(static_cast<std::size_t>(x), knots_.size() - 2);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const Knot& a = knots_[i];
    const Knot& b = knots_[i + 1];
    const double u = x - static_cast<double>(i), h = kKnotNs * 1e-9;
    const double u2 = u * u, u3 = u2 * u;
    T.translation() = (2 * u3 - 3 * u2 + 1) * a.p + (u3 - 2 * u2 + u) * h * a.v +
                      (-2 * u3 + 3 * u2) * b.p + (u3 - u2) * h * b.v;
    T.linear() = a.q.slerp(u, b.q).toRotationMatrix();
    return T;
  }

 private:
  struct Knot {
    Eigen::Vector3d p, v;
    Eigen::Quaterniond q;
  };
  std::vector<Knot> knots_;
};

// One scan's files, made in render(); the labels wait for the instance table in commit().
struct LidarScan {
  std::string bin;   // float32 x y z intensity per point
  std::string info;  // kPointInfoBytes per point
  std::vector<scene::ClassId> cls;
  std::vector<scene::InstanceId> instance;
  std::vector<io::PcdPoint> pcd;  // labels filled in commit()
  std::int64_t rays = 0;
  std::size_t tiles = 0;
};

// point_info/*.bin, per point, little-endian, packed: float32 firing time after the scan's
// start (s), float32 measured range (m), uint16 ring (0 = highest laser), uint8 return index
// (0: the strongest, last or only return; 1: the last of a dual pair), uint8 material id
// (resources/materials.json).
constexpr std::size_t kPointInfoBytes = 12;

class LidarSensor final : public SensorOf<LidarScan> {
 public:
  LidarSensor(const SensorSetup& setup, const LidarConfig& c)
      : trajectory_(setup.context.trajectory),
        scene_(setup.context.scene),
        rays_(setup.context.rays),
        cancel_(setup.context.cancel),
        instances_(setup.context.instances),
        name_(c.basics.name),
        period_(c.basics.period_ns),
        index_(setup.index),
        T_body_cam0_(setup.context.T_body_cam0),
        anchor_(setup.context.anchor),
        scanner_(scannerParams(c, trainSection().read(setup.context.scenario.json()), setup.path)),
        random_(setup.context.scenario.seed(), name_ + ".returns"),
        point_info_(c.point_info),
        pcd_(c.pcd) {
    if (scene_ == nullptr || rays_ == nullptr || instances_ == nullptr)
      throw RuntimeError(
          fmt::format("{}: a LiDAR needs the scene (the run did not make it)", setup.path));
    T_body_sensor_ = bodyFromSensor(c.basics.mount.mount());
  }

  std::string name() const override { return name_; }
  std::string kind() const override { return kLidarKind; }
  TimeNs period() const override { return period_; }
  std::vector<std::string> outputs() const override {
    std::vector<std::string> files = sensorFiles(kReadingsCsv, name_);
    files.push_back(io::DatasetLayout::velodyneFolder(index_) + "/");
    files.push_back(io::DatasetLayout::labelsFolder(index_) + "/");
    if (point_info_)
      files.push_back(io::DatasetLayout::pointInfoFolder(index_) + "/");
    if (pcd_)
      files.push_back(io::DatasetLayout::pcdFolder(index_) + "/");
    return files;
  }

  std::vector<std::string> calibration() const override {
    return {kittiCalibLine(index_ == 0 ? "Tr" : fmt::format("Tr_{}", index_),
                           kittiTr(T_body_cam0_, T_body_sensor_).matrix().topRows<3>())};
  }

  void begin(io::DatasetWriter& writer, const nlohmann::json& state) override {
    writer_ = &writer;
    csv_ = &writer.appendFile(writer.layout().inSequence(outputs().front()));
    class_points_.restore(state);
    if (state.is_null())
      csv_->write("frame,t_ns,points,rays,tiles\n");
  }

  nlohmann::json state() const override { return class_points_.state(); }
  nlohmann::json summary() const override { return class_points_.summary(); }

 private:
  LidarScan read(std::int64_t k) const override {
    const TimeNs t0 = k * trajectory_.samplePeriod();
    const lidar::ScanPattern& pattern = scanner_.params().pattern;
    const ScanPoses poses(trajectory_, T_body_sensor_, t0, pattern.revolution());
    // The tiles within range of the sensor wherever it is during the scan.
    const Eigen::Isometry3d start = poses.at(0.0), end = poses.at(pattern.revolution());
    const Eigen::Vector3d centre = 0.5 * (start.translation() + end.translation());
    const double reach =
        pattern.range_max_m + 0.5 * (end.translation() - start.translation()).norm() + 1.0;
    const scene::SceneWindow window = scene_->window(centre, reach);
    const lidar::RayScene scene = rays_->scene(window.tiles);
    // The frames' memory is reused from scan to scan (one per scan in flight).
    std::unique_ptr<lidar::LidarFrame> reused = frames_.take();
    const lidar::LidarFrame& frame = *reused;
    scanner_.scan(
        scene, [&](double t) { return poses.at(t); }, random_,
        static_cast<std::uint64_t>(k / (period_ / trajectory_.samplePeriod())), *reused, cancel_,
        anchor_.rotationAnchorFromLocalEnu(centre).col(2));

    LidarScan out;
    out.rays = frame.rays;
    out.tiles = window.tiles.size();
    const std::size_t n = frame.points.size();
    out.bin.resize(n * 16);
    if (point_info_)
      out.info.resize(n * kPointInfoBytes);
    out.cls.reserve(n);
    out.instance.reserve(n);
    if (pcd_)
      out.pcd.reserve(n);
    char* bin = out.bin.data();
    char* info = out.info.data();
    const auto lasers = static_cast<int>(scanner_.params().pattern.lasers.size());
    for (const lidar::LidarPoint& p : frame.points) {
      const Eigen::Vector3f xyz = scanner_.written(p);
      io::putPacked(bin, xyz.x());
      io::putPacked(bin, xyz.y());
      io::putPacked(bin, xyz.z());
      io::putPacked(bin, p.intensity);
      const float time = point_info_ || pcd_ ? scanner_.time(p) : 0.0f;
      if (point_info_) {
        io::putPacked(info, time);
        io::putPacked(info, p.range_m);
        io::putPacked(info, p.ring);
        io::putPacked(info, p.return_index);
        io::putPacked(info, p.material);
      }
      out.cls.push_back(p.cls);
      out.instance.push_back(frame.instance(p));
      if (pcd_)
        out.pcd.push_back({xyz.x(), xyz.y(), xyz.z(), p.intensity,
                           static_cast<std::uint16_t>(lasers - 1 - p.ring), time, 0});
    }
    frames_.give(std::move(reused));
    return out;
  }

  void write(std::int64_t k, LidarScan& scan) override {
    const std::int64_t frame = k / (period_ / trajectory_.samplePeriod());
    std::string labels(scan.cls.size() * 4, '\0');
    char* out = labels.data();
    for (std::size_t i = 0; i < scan.cls.size(); ++i) {
      const std::uint32_t id = instances_->id(scan.instance[i], scan.cls[i]);
      const std::uint32_t label = static_cast<std::uint32_t>(scan.cls[i]) | (id << 16);
      io::putPacked(out, label);
      if (pcd_)
        scan.pcd[i].label = label;
      class_points_.add(scan.cls[i]);
    }
    const io::DatasetLayout& layout = writer_->layout();
    const auto file = [&](const std::string& folder, const char* extension) {
      return layout.inSequence(io::DatasetLayout::frameFile(folder, frame, extension));
    };
    writer_->writeFile(file(io::DatasetLayout::velodyneFolder(index_), "bin"), scan.bin);
    writer_->writeFile(file(io::DatasetLayout::labelsFolder(index_), "label"), labels);
    if (point_info_)
      writer_->writeFile(file(io::DatasetLayout::pointInfoFolder(index_), "bin"), scan.info);
    if (pcd_)
      writer_->writeFile(file(io::DatasetLayout::pcdFolder(index_), "pcd"),
                         io::encodePcd(scan.pcd));
    csv_->write(fmt::format("{},{},{},{},{}\n", frame, k * trajectory_.samplePeriod(),
                            scan.cls.size(), scan.rays, scan.tiles));
  }

  const Trajectory& trajectory_;
  scene::SceneStream* scene_;
  std::shared_ptr<lidar::RayWorld> rays_;
  const std::atomic<bool>* cancel_ = nullptr;
  std::shared_ptr<InstanceTable> instances_;
  std::string name_;
  TimeNs period_;
  int index_;
  Eigen::Isometry3d T_body_cam0_;
  GeodeticAnchor anchor_;  // the local vertical, for the fog's layer
  Eigen::Isometry3d T_body_sensor_ = Eigen::Isometry3d::Identity();
  lidar::Scanner scanner_;
  RandomStream random_;
  bool point_info_, pcd_;
  mutable ObjectPool<lidar::LidarFrame> frames_;
  io::DatasetWriter* writer_ = nullptr;
  io::AppendFile* csv_ = nullptr;
  ClassCounts class_points_{"class_points", "points"};
};

}  // namespace

scenario::Param declareLidar() {
  return lidarBinding().declare(
      "lidar",
      "A rotating multi-beam LiDAR cast into the scene with Embree: KITTI velodyne/*.bin "
      "(float32 x y z intensity, ring by ring), SemanticKITTI labels/*.label (class | instance "
      "<< 16) and per-point point_info/*.bin, one file each per scan.");
}

void checkLidar(const scenario::Json& item, const std::string& path,
                std::vector<scenario::Problem>& problems) {
  lidarBinding().problems(lidarBinding().read(item), path, problems);
}

void checkLidarClearOfTheBody(const scenario::Json& item, const TrainConfig& train,
                              const std::string& path, std::vector<scenario::Problem>& problems) {
  if (const std::string why = insideTheBody(poseOnBody(readMount(item), train),
                                            devicePattern(lidarBinding().read(item)), train);
      !why.empty())
    problems.push_back({mountPath(path), why});
}

std::vector<std::string> warnLidar(const scenario::Json&, const scenario::Json& item,
                                   const std::string& path, int) {
  return lidarWarnings(lidarBinding().read(item), path);
}

std::unique_ptr<Sensor> createLidar(const SensorSetup& setup) {
  return std::make_unique<LidarSensor>(setup, lidarBinding().read(setup.config));
}

}  // namespace trainsim::sim
