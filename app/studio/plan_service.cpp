#include "plan_service.hpp"

#include <QtConcurrent/QtConcurrent>
#include <algorithm>
#include <cmath>

#include "trainsim/core/error.hpp"
#include "trainsim/sim/config.hpp"

namespace trainsim::studio {
namespace {

// One chainage label per this many metres, chosen so a route gets at most ~12 labels.
double labelStep(double length_m) {
  for (double step : {100.0, 250.0, 500.0, 1000.0, 2000.0, 5000.0, 10000.0, 25000.0, 50000.0}) {
    if (length_m / step <= 12.0)
      return step;
  }
  return 100000.0;
}

track::LayoutBlockType typeAt(const track::LayoutTrack& t, double d) {
  for (const track::LayoutBlock& b : t.blocks) {
    if (d >= b.begin_m && d < b.end_m)
      return b.type;
  }
  return t.blocks.empty() ? track::LayoutBlockType::kStraight : t.blocks.back().type;
}

}  // namespace

std::span<const track::LayoutBlockType> blockTypes() {
  using enum track::LayoutBlockType;
  static constexpr track::LayoutBlockType kLegend[] = {kStraight, kCurve,   kStation,  kTunnel,
                                                       kBridge,   kTurnout, kParallel, kDeadEnd};
  return kLegend;
}

Rgb blockColour(track::LayoutBlockType type) {
  switch (type) {
    case track::LayoutBlockType::kCurve:
      return {230, 140, 20};
    case track::LayoutBlockType::kStation:
      return {40, 110, 230};
    case track::LayoutBlockType::kTunnel:
      return {120, 120, 120};
    case track::LayoutBlockType::kBridge:
      return {160, 60, 200};
    case track::LayoutBlockType::kTurnout:
    case track::LayoutBlockType::kSwitch:
      return {220, 40, 140};
    case track::LayoutBlockType::kParallel:
      return {40, 170, 170};
    case track::LayoutBlockType::kDeadEnd:
      return {150, 100, 50};
    case track::LayoutBlockType::kStraight:
      break;
  }
  return {40, 160, 60};
}

std::unique_ptr<PlanSnapshot> buildSnapshot(const scenario::Scenario& scenario,
                                            sim::Planner& planner) {
  auto snap = std::make_unique<PlanSnapshot>();
  snap->scenario = std::make_shared<const scenario::Scenario>(scenario);
  snap->plan = std::make_unique<sim::Plan>(planner.plan(scenario));
  const sim::Plan& plan = *snap->plan;
  snap->train_length_m = sim::trainSection().read(scenario.json()).limits.train_length_m;

  for (const track::LayoutTrack& t : plan.layout().tracks) {
    track::Polyline polyline = track::samplePolyline(plan.route().route.track, t);
    TrackLine line{t.id, t.kind, std::move(polyline.points), {}};
    line.segment_type.reserve(line.points.size());
    for (std::size_t i = 0; i + 1 < line.points.size(); ++i)
      line.segment_type.push_back(
          typeAt(t, 0.5 * (polyline.distance_m[i] + polyline.distance_m[i + 1])));
    snap->tracks.push_back(std::move(line));
  }

  const track::Track& main = plan.route().route.track;
  const double length = main.length();
  const double step = labelStep(length);
  for (double s = 0.0; s <= length + 1e-9; s += step)
    snap->chainage_marks.push_back({s, main.atChainage(std::min(s, length)).position});
  for (const track::Violation& v : plan.violations()) {
    const double s = std::clamp(0.5 * (v.chainage_begin_m + v.chainage_end_m), 0.0, length);
    snap->violations.push_back({v.rule, v.message, s, main.atChainage(s).position});
  }

  const sim::TrainTrajectory& traj = plan.trajectory();
  const std::int64_t n = traj.sampleCount();
  const double period_s = static_cast<double>(traj.samplePeriod()) * 1e-9;
  snap->duration_s = static_cast<double>(n - 1) * period_s;
  const std::int64_t stride = std::max<std::int64_t>(1, n / 20000);
  TrajectorySeries& ts = snap->series;
  for (std::int64_t k = 0; k < n; k += stride) {
    const sim::TrajectorySample s = traj.sample(k);
    ts.t_s.push_back(static_cast<double>(k) * period_s);
    ts.chainage_m.push_back(s.chainage_m);
    ts.speed_m_s.push_back(s.speed_m_s);
    ts.accel_m_s2.push_back(s.accel_m_s2);
    ts.roll_rate.push_back(s.w_body.x());
    ts.pitch_rate.push_back(s.w_body.y());
    ts.yaw_rate.push_back(s.w_body.z());
    ts.curvature_1_m.push_back(main.horizontal().at(std::min(s.chainage_m, length)).curvature_1_m);
  }
  return snap;
}

TrainPose PlanSnapshot::poseAt(double t_s) const {
  const sim::TrainTrajectory& traj = plan->trajectory();
  const double period_s = static_cast<double>(traj.samplePeriod()) * 1e-9;
  const auto k = std::clamp<std::int64_t>(std::llround(t_s / period_s), 0, traj.sampleCount() - 1);
  const sim::TrajectorySample s = traj.sample(k);
  return {static_cast<double>(k) * period_s, s.chainage_m, s.p_world, s.q_world_body};
}

PlanService::PlanService(QObject* parent) : QObject(parent) {
  debounce_.setSingleShot(true);
  debounce_.setInterval(150);
  connect(&debounce_, &QTimer::timeout, this, &PlanService::launch);
  connect(&watcher_, &QFutureWatcherBase::finished, this, &PlanService::onFinished);
}

PlanService::~PlanService() {
  watcher_.waitForFinished();
}

void PlanService::request(const scenario::Scenario& scenario) {
  pending_ = scenario;
  ++generation_;
  if (!running_)
    debounce_.start();
}

void PlanService::launch() {
  if (running_ || !pending_)
    return;
  scenario::Scenario sc = std::move(*pending_);
  pending_.reset();
  running_ = true;
  emit started();
  const std::uint64_t generation = generation_;
  watcher_.setFuture(
      QtConcurrent::run([sc = std::move(sc), generation, planner = planner_]() -> Outcome {
        try {
          std::unique_ptr<PlanSnapshot> snap = buildSnapshot(sc, *planner);
          snap->generation = generation;
          return {std::shared_ptr<const PlanSnapshot>(std::move(snap)), {}};
        } catch (const std::exception& e) {
          return {nullptr, QString::fromStdString(e.what())};
        }
      }));
}

void PlanService::onFinished() {
  running_ = false;
  const Outcome out = watcher_.result();
  if (pending_) {  // a newer scenario arrived meanwhile: plan that one, drop this result
    launch();
    return;
  }
  if (out.snapshot)
    emit planned(out.snapshot);
  else
    emit failed(out.error);
}

}  // namespace trainsim::studio
