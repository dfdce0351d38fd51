#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "trainsim/core/time.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/trajectory.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/route_design.hpp"
#include "trainsim/track/vehicle.hpp"

namespace trainsim::environment {
class Environment;
}
namespace trainsim::terrain {
class Railway;
}

namespace trainsim::sim {

struct RouteStage;

/// The train's run over the main track: the motion at any time with the body on its two
/// bogies, everything in closed form, sampled at T_S. Owns its motion profile and shares the
/// route stage it runs on, so it holds no reference into a struct that contains it.
class TrainTrajectory final : public Trajectory {
 public:
  TrainTrajectory(std::shared_ptr<const RouteStage> route, track::MotionProfile motion,
                  track::VehicleGeometry vehicle, Eigen::Vector3d reference_point, TimeNs period);

  TimeNs samplePeriod() const override { return period_; }
  std::int64_t sampleCount() const override { return count_; }
  TrajectorySample at(TimeNs t) const override;
  /// Where either bogie pivot passes the start of a track element, and where a motion segment
  /// begins.
  std::vector<TimeNs> breakpoints(TimeNs t0, TimeNs t1) const override;

  track::MotionState motion(std::int64_t k) const;
  /// The motion at time t, clamped to [0, endTime()].
  track::MotionState motionAt(TimeNs t) const;
  /// The body on its bogies for a motion state (e.g. motion(k)).
  track::BodyState body(const track::MotionState& m) const;
  const Eigen::Vector3d& referencePoint() const { return reference_; }
  const track::MotionProfile& profile() const { return motion_; }

 private:
  std::shared_ptr<const RouteStage> route_;
  track::MotionProfile motion_;
  track::VehicleGeometry vehicle_;
  Eigen::Vector3d reference_;
  TimeNs period_;
  std::int64_t count_;
  std::vector<double> track_breaks_;  // Track::breakpointDistances()
};

/// The plan is a chain of immutable stages (docs/REFERENCES.md P1, stages 1–3; later terrain
/// and scene). Each is a pure function of the scenario sections it reads (pipelineStages()) and
/// of the stages before it, and is identified by `key`, a hash of exactly those inputs, so a
/// Planner can reuse a stage whose inputs did not change.
struct RouteStage {
  std::uint64_t key = 0;
  track::RouteOptions options;
  track::DesignedRoute route;
  std::vector<track::Violation> violations;  ///< fitting and design rules
};
struct LayoutStage {
  std::uint64_t key = 0;
  track::Layout layout;
  std::vector<track::Violation> violations;  ///< track clearance
};
struct MotionStage {
  std::uint64_t key = 0;
  track::MotionLimits limits;
  TrainTrajectory trajectory;
};

/// The world along the railway (terrain, track assets, objects): built only when something
/// looks at it (a LiDAR, a camera, `plan --scene`), sharing the route and layout stages it
/// stands on. Tiles are made on demand (Environment::stream()).
struct EnvironmentStage {
  std::uint64_t key = 0;
  std::shared_ptr<const RouteStage> route;
  std::shared_ptr<const LayoutStage> layout;
  std::shared_ptr<const terrain::Railway> railway;
  std::shared_ptr<const environment::Environment> environment;
};

/// Everything the plan stage produces: shared, immutable stages (cheap to copy).
class Plan {
 public:
  Plan(std::shared_ptr<const RouteStage> route, std::shared_ptr<const LayoutStage> layout,
       std::shared_ptr<const MotionStage> motion);

  const RouteStage& routeStage() const { return *route_; }
  const track::RouteOptions& options() const { return route_->options; }
  const track::DesignedRoute& route() const { return route_->route; }
  const track::Layout& layout() const { return layout_->layout; }
  const track::MotionLimits& limits() const { return motion_->limits; }
  const track::MotionProfile& motion() const { return motion_->trajectory.profile(); }
  const TrainTrajectory& trajectory() const { return motion_->trajectory; }
  /// Design rules, fitting and clearance, in chainage order.
  const std::vector<track::Violation>& violations() const { return violations_; }

  std::shared_ptr<const RouteStage> routeShared() const { return route_; }
  std::shared_ptr<const LayoutStage> layoutShared() const { return layout_; }
  std::shared_ptr<const MotionStage> motionShared() const { return motion_; }

 private:
  std::shared_ptr<const RouteStage> route_;
  std::shared_ptr<const LayoutStage> layout_;
  std::shared_ptr<const MotionStage> motion_;
  std::vector<track::Violation> violations_;
};

/// One stage of the pipeline (docs/REFERENCES.md P1): its name, what it makes, the scenario
/// sections it reads (its key hashes them with the keys of the stages it builds on), and whether
/// it is built yet. generate() reports the stages that are not as "not simulated yet".
struct PipelineStage {
  std::string name;
  std::string description;
  std::vector<std::string> sections;  ///< top-level scenario keys, from the section bindings
  bool implemented;
};
std::span<const PipelineStage> pipelineStages();
/// Descriptions of the stages not implemented yet, in pipeline order.
std::vector<std::string> stagesNotRun();

/// Builds plans and keeps the stages of the last one: a stage whose key (its sections, the
/// keys before it, and for waypoint routes the file's size and time) did not change is
/// reused, so an edit to `train` re-plans the motion only. Thread-safe (one plan at a time).
class Planner {
 public:
  Plan plan(const scenario::Scenario& scenario);
  /// How many times the stage `name` ("route", "layout", "motion") has been built.
  std::int64_t builds(std::string_view name) const;

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const RouteStage> route_;
  std::shared_ptr<const LayoutStage> layout_;
  std::shared_ptr<const MotionStage> motion_;
  std::int64_t route_builds_ = 0, layout_builds_ = 0, motion_builds_ = 0;
};

/// Builds route, layout, motion and trajectory from a resolved scenario (a fresh Planner).
std::unique_ptr<Plan> makePlan(const scenario::Scenario& scenario);

/// The environment of a plan, from the scenario's terrain, assets and objects sections.
std::shared_ptr<const EnvironmentStage> makeEnvironment(const Plan& plan,
                                                        const scenario::Scenario& scenario);

/// What `plan --scene` writes into OUT/scene/: every terrain tile as a 16-bit PNG with its JSON
/// metadata (terrain/tile_I_J.png), every trackside object (objects.csv), and the tiles along
/// the main track between main chainage `from_m` and `to_m` as scene.vtm for ParaView, with
/// those tiles' height maps also as VTK image data (terrain/tile_I_J.vti).
struct SceneExport {
  double from_m = 0.0;
  double to_m = 1000.0;
};
void writeScene(const EnvironmentStage& stage, const std::filesystem::path& folder,
                const SceneExport& window);

/// Receives a large output piece by piece (an io::AtomicFile, or a string in tests).
using TextSink = std::function<void(std::string_view)>;

/// railroad.json: the main track's blocks and every layout track with its polyline.
void writeRailroadJson(const Plan& plan, const TextSink& sink);
std::string railroadJson(const Plan& plan);
std::string designReportJson(const Plan& plan);
/// trajectory.csv: one row per sample, `t_ns` first, every column named with its unit.
void writeTrajectoryCsv(const Plan& plan, const TextSink& sink);
std::string trajectoryCsv(const Plan& plan);

/// route.blocks items that lay out `route` again (route.source = "blocks"): the studio's
/// "edit as blocks" of a generated or imported route. Grades become each block's mean grade.
scenario::Json blockListJson(const track::Route& route);

/// Writes railroad.json, trajectory.csv and design_report.json into `folder`, each atomically
/// and streamed (io::AtomicFile), so memory does not grow with the route.
void writePlan(const Plan& plan, const std::filesystem::path& folder);

/// `trainsim plan`: writes scenario.json and the plan (writePlan) into `out` under the folder
/// rules every run follows (io::checkOutputFolder: a foreign non-empty folder only with
/// `force`, which removes TrainSim's own entries only). Whatever fails, nothing half-written
/// stays: a folder it created goes again, in an existing one the files it began are removed.
void writePlanFolder(const Plan& plan, const scenario::Scenario& scenario,
                     const std::filesystem::path& out, bool force);

}  // namespace trainsim::sim
