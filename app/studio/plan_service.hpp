#pragma once

#include <Eigen/Geometry>
#include <QFutureWatcher>
#include <QObject>
#include <QTimer>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/plan.hpp"

namespace trainsim::studio {

/// A track of the layout as the views draw it: its polyline and the block type of each segment.
struct TrackLine {
  int id = 0;
  track::TrackKind kind = track::TrackKind::kMain;
  std::vector<Eigen::Vector3d> points;
  std::vector<track::LayoutBlockType> segment_type;  ///< of segment i (points i → i+1)
};

/// A design-rule violation placed on the main track.
struct ViolationMark {
  std::string rule;
  std::string message;
  double chainage_m = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// A chainage label on the main track.
struct ChainageMark {
  double chainage_m = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// Ground-truth series of the planned run for the plots, at most ~20 000 points.
struct TrajectorySeries {
  std::vector<double> t_s, chainage_m, speed_m_s, accel_m_s2, roll_rate, pitch_rate, yaw_rate,
      curvature_1_m;
};

/// Where the train is at one time: the body reference point and its attitude.
struct TrainPose {
  double t_s = 0.0;
  double chainage_m = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond attitude = Eigen::Quaterniond::Identity();
};

/// One finished plan and everything the views need from it, computed off the GUI thread.
struct PlanSnapshot {
  std::uint64_t generation = 0;
  std::shared_ptr<const scenario::Scenario> scenario;
  std::unique_ptr<sim::Plan> plan;  ///< shares the planner's immutable stages
  std::vector<TrackLine> tracks;
  std::vector<ViolationMark> violations;
  std::vector<ChainageMark> chainage_marks;
  TrajectorySeries series;
  double duration_s = 0.0;
  double train_length_m = 0.0;

  /// The train at time t (clamped to the run), from the planned trajectory.
  TrainPose poseAt(double t_s) const;
};

/// Builds the snapshot of a resolved scenario (route, layout, motion, trajectory, report),
/// re-planning through `planner` only the stages the scenario changed. Throws what
/// sim::Planner::plan throws.
std::unique_ptr<PlanSnapshot> buildSnapshot(const scenario::Scenario& scenario,
                                            sim::Planner& planner);

/// Plans scenarios off the GUI thread. Requests are debounced; while one plan runs, only the
/// newest request is kept and runs next, so the views always end on the latest scenario.
class PlanService : public QObject {
  Q_OBJECT

 public:
  explicit PlanService(QObject* parent = nullptr);
  ~PlanService() override;

  void request(const scenario::Scenario& scenario);
  /// The planner that keeps the last plan's stages (its build counts, for tests).
  const sim::Planner& planner() const { return *planner_; }

 signals:
  void started();
  void planned(std::shared_ptr<const trainsim::studio::PlanSnapshot> snapshot);
  void failed(const QString& message);

 private:
  struct Outcome {
    std::shared_ptr<const PlanSnapshot> snapshot;
    QString error;
  };
  void launch();
  void onFinished();

  std::shared_ptr<sim::Planner> planner_ = std::make_shared<sim::Planner>();
  QTimer debounce_;
  std::optional<scenario::Scenario> pending_;
  QFutureWatcher<Outcome> watcher_;
  bool running_ = false;
  std::uint64_t generation_ = 0;
};

/// The colour of a block type in every view (RGB 0..255).
struct Rgb {
  int r, g, b;
};
Rgb blockColour(track::LayoutBlockType type);
/// Block types in legend order.
std::span<const track::LayoutBlockType> blockTypes();

}  // namespace trainsim::studio
