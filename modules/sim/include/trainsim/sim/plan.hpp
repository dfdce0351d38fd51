#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "trainsim/core/time.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/trajectory.hpp"
#include "trainsim/track/layout.hpp"
#include "trainsim/track/route_design.hpp"
#include "trainsim/track/vehicle.hpp"

namespace trainsim::sim {

/// The train's run over the main track sampled at T_S: sample k is the motion at k·T_S with
/// the body on its two bogies, everything in closed form.
class TrainTrajectory final : public Trajectory {
 public:
  TrainTrajectory(const track::Track& track, const track::MotionProfile& motion,
                  track::VehicleGeometry vehicle, Eigen::Vector3d reference_point, TimeNs period);

  TimeNs samplePeriod() const override { return period_; }
  std::int64_t sampleCount() const override { return count_; }
  TrajectorySample at(TimeNs t) const override;

  track::MotionState motion(std::int64_t k) const;
  /// The motion at time t, clamped to [0, endTime()].
  track::MotionState motionAt(TimeNs t) const;
  /// The body on its bogies for a motion state (e.g. motion(k)).
  track::BodyState body(const track::MotionState& m) const;
  const Eigen::Vector3d& referencePoint() const { return reference_; }

 private:
  const track::Track& track_;
  const track::MotionProfile& motion_;
  track::VehicleGeometry vehicle_;
  Eigen::Vector3d reference_;
  TimeNs period_;
  std::int64_t count_;
};

/// Everything the plan stage produces (PRODUCT.md §1, stages 1–3).
struct Plan {
  track::RouteOptions options;
  track::DesignedRoute route;
  track::Layout layout;
  std::vector<track::Violation> violations;  ///< design rules and fitting, chainage order
  track::MotionLimits limits;
  track::MotionProfile motion;
  std::unique_ptr<TrainTrajectory> trajectory;
};

/// Builds route, layout, motion and trajectory from a resolved scenario.
std::unique_ptr<Plan> makePlan(const scenario::Scenario& scenario);

std::string railroadJson(const Plan& plan);
std::string designReportJson(const Plan& plan);
/// trajectory.csv: one row per sample, `t_ns` first, every column named with its unit.
std::string trajectoryCsv(const Plan& plan);

/// route.blocks items that lay out `route` again (route.source = "blocks"): the studio's
/// "edit as blocks" of a generated or imported route. Grades become each block's mean grade.
scenario::Json blockListJson(const track::Route& route);

/// Writes railroad.json, trajectory.csv and design_report.json through `write(name, bytes)`.
void writePlan(const Plan& plan,
               const std::function<void(const std::string&, const std::string&)>& write);

}  // namespace trainsim::sim
