#include "trainsim/sim/plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "obstacle_stop.hpp"
#include "trainsim/core/cancel.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/core/geodesy.hpp"
#include "trainsim/core/hash.hpp"
#include "trainsim/core/log.hpp"
#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/io/dataset_writer.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/sim/config.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/terrain/railway.hpp"

namespace trainsim::sim {

TrainTrajectory::TrainTrajectory(std::shared_ptr<const RouteStage> route,
                                 track::MotionProfile motion, track::VehicleGeometry vehicle,
                                 Eigen::Vector3d reference_point, TimeNs period)
    : route_(std::move(route)),
      motion_(std::move(motion)),
      vehicle_(vehicle),
      reference_(std::move(reference_point)),
      period_(period),
      // Up to the first sample at or after the end of the run, where the train is at rest.
      count_(static_cast<std::int64_t>(std::ceil(motion_.duration() / toSeconds(period))) + 1),
      track_breaks_(route_->route.route.track.breakpointDistances()) {}

std::vector<TimeNs> TrainTrajectory::breakpoints(TimeNs t0, TimeNs t1) const {
  t0 = std::clamp<TimeNs>(t0, 0, endTime());
  t1 = std::clamp<TimeNs>(t1, 0, endTime());
  std::vector<TimeNs> out;
  if (t1 <= t0)
    return out;
  const auto add = [&](double t_s) {
    const TimeNs t = fromSeconds(t_s);
    if (t > t0 && t < t1)
      out.push_back(t);
  };
  const auto& segments = motion_.segments();
  for (auto it =
           std::lower_bound(segments.begin(), segments.end(), toSeconds(t0) - 1e-6,
                            [](const track::MotionSegment&s, double t) { return s.t0_s < t; });
       it != segments.end() && it->t0_s < toSeconds(t1) + 1e-6; ++it)
    add(it->t0_s);
  // Distances where either pivot meets a track breakpoint; the front pivot is at u.
  const double u0 = motionAt(t0).u_m, u1 = motionAt(t1).u_m;
  // Pivots (position), and wheelsets (roll), behind the front pivot.
  const double L = vehicle_.bogie_spacing_m, h = vehicle_.wheelbase_m / 2.0;
  for (const double offset : {0.0, L, -h, h, L - h, L + h}) {
    auto it = std::upper_bound(track_breaks_.begin(), track_breaks_.end(), u0 - offset);
    for (; it != track_breaks_.end() && *it + offset < u1; ++it)
      add(motion_.timeAtDistance(*it + offset));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

track::MotionState TrainTrajectory::motion(std::int64_t k) const {
  return motionAt(k * period_);
}

track::MotionState TrainTrajectory::motionAt(TimeNs t) const {
  return motion_.at(toSeconds(std::clamp<TimeNs>(t, 0, endTime())));
}

track::BodyState TrainTrajectory::body(const track::MotionState& m) const {
  return track::bodyState(route_->route.route.track, vehicle_, m);
}

TrajectorySample TrainTrajectory::at(TimeNs t) const {
  TrajectorySample s;
  s.t_ns = std::clamp<TimeNs>(t, 0, endTime());
  const track::MotionState m = motion_.at(toSeconds(s.t_ns));
  const track::BodyState b = body(m);
  s.chainage_m = b.front_track.chainage_m;
  s.distance_m = m.u_m;
  s.p_world = b.pointPosition(reference_);
  s.q_world_body = Eigen::Quaterniond(b.r_world_body);
  s.v_world = b.pointVelocity(reference_);
  s.a_world = b.pointAcceleration(reference_);
  s.w_body = b.w_body;
  s.alpha_body = b.alpha_body;
  s.speed_m_s = m.v_m_s;
  s.accel_m_s2 = m.a_m_s2;
  return s;
}

Plan::Plan(std::shared_ptr<const RouteStage> route, std::shared_ptr<const LayoutStage> layout,
           std::shared_ptr<const MotionStage> motion)
    : route_(std::move(route)), layout_(std::move(layout)), motion_(std::move(motion)) {
  violations_ = route_->violations;
  violations_.insert(violations_.end(), layout_->violations.begin(), layout_->violations.end());
  std::stable_sort(violations_.begin(), violations_.end(),
                   [](const track::Violation& a, const track::Violation& b) {
                     return a.chainage_begin_m < b.chainage_begin_m;
                   });
}

namespace {

// The pipeline's stage table (docs/REFERENCES.md P1) and the scenario sections each stage
// reads; a stage's key hashes exactly these sections (and its upstream stages' keys).
const std::vector<PipelineStage>& stageTable() {
  static const std::vector<PipelineStage> stages = [] {
    const std::string seed = scenario::seedParam().key;
    return std::vector<PipelineStage>{
        {"route",
         "route, vertical profile, cant and design rules",
         {seed, geodeticOriginSection().key, routeSection().key, designSection().key},
         true},
        {"layout", "double and auxiliary tracks", {seed, layoutSection().key}, true},
        {"motion",
         "speed profile and trajectory",
         {trainSection().key, trajectorySection().key, objectsSection().key, terrainSection().key},
         true},
        {"terrain",
         "terrain, objects and track assets",
         {seed, terrainSection().key, assetsSection().key, objectsSection().key},
         true},
        {"lidar", "LiDAR", {}, true},
        {"cameras", "cameras", {}, true},
    };
  }();
  return stages;
}

std::uint64_t stageKey(const scenario::Scenario& sc, std::string_view stage,
                       std::initializer_list<std::uint64_t> upstream) {
  std::string bytes(stage);
  for (const PipelineStage& s : stageTable())
    if (stage == s.name)
      for (const std::string& section : s.sections)
        bytes += sc.json().at(section).dump();
  for (std::uint64_t k : upstream)
    bytes += fmt::format("|{:016x}", k);
  // A waypoint route is also a function of its file: its size and modification time.
  if (stage != "route")
    return fnv1a64(bytes);
  if (const RouteConfig route = routeSection().read(sc.json());
      route.source == RouteSource::kWaypoints) {
    std::error_code ec;
    const std::filesystem::path file = route.waypoints_file;
    const auto size = std::filesystem::file_size(file, ec);
    const auto time = std::filesystem::last_write_time(file, ec);
    bytes += fmt::format("|{}|{}", ec ? 0 : size, time.time_since_epoch().count());
  }
  return fnv1a64(bytes);
}

std::shared_ptr<const RouteStage> buildRoute(const scenario::Scenario& sc, std::uint64_t key) {
  const RouteConfig config = routeSection().read(sc.json());
  track::RouteOptions opt = config.options;
  opt.rules = designSection().read(sc.json());
  auto route_of = [&]() {
    switch (config.source) {
      case RouteSource::kBlocks:
        return track::buildBlockRoute(config.blocks, opt);
      case RouteSource::kWaypoints:
        try {
          return track::importWaypoints(config.waypoints_file, geodeticAnchor(sc.json()),
                                        config.waypoints, opt);
        } catch (const ConfigError& e) {  // the file's problems, said of the key naming it
          throw ConfigError(
              fmt::format("{}: {}", routeSection().path(&RouteConfig::waypoints_file), e.what()));
        }
      case RouteSource::kGenerated:
        break;
    }
    return track::generateRoute(config.generator, opt, sc.seed());
  };
  track::DesignedRoute route = route_of();
  // The design (chainage, curvature, grade and cant against the local level) laid on the
  // WGS-84 ellipsoid; world positions in the anchor's Earth-fixed ENU frame.
  route.route.track.placeOnEarth(geodeticOriginSection().read(sc.json()));
  std::vector<track::Violation> violations = route.fitting;
  for (track::Violation& v : track::checkDesign(route.route, opt.rules))
    violations.push_back(std::move(v));
  return std::make_shared<const RouteStage>(
      RouteStage{key, opt, std::move(route), std::move(violations)});
}

std::shared_ptr<const LayoutStage> buildLayoutStage(const scenario::Scenario& sc,
                                                    const RouteStage& route, std::uint64_t key) {
  auto stage = std::make_shared<LayoutStage>();
  stage->key = key;
  const track::LayoutParams lp = layoutSection().read(sc.json());
  stage->layout = track::buildLayout(route.route.route, lp, sc.seed());
  for (const track::ClearanceIssue& c :
       track::checkClearance(route.route.route.track, stage->layout, lp.track_centre_distance_m)) {
    stage->violations.push_back(
        {"track_clearance", 0.0, 0.0, -1, c.clearance_m, lp.track_centre_distance_m, "m",
         fmt::format("track {} comes within {:.3f} m of track {} at {:.1f} m along it", c.track_id,
                     c.clearance_m, c.other_track_id, c.distance_along_m)});
  }
  return stage;
}

std::shared_ptr<const MotionStage> buildMotion(const scenario::Scenario& sc,
                                               std::shared_ptr<const RouteStage> route,
                                               const track::Layout& layout, std::uint64_t key) {
  const TrainConfig train = trainSection().read(sc.json());
  const track::MotionLimits& limits = train.limits;
  const track::VehicleGeometry& vehicle = train.vehicle;
  const track::Route& r = route->route.route;
  const double u_length = r.track.distanceLength();
  // Every wheelset on the track: the rear one at the start, the front one 1 m before the end.
  const double u_start = vehicle.bogie_spacing_m + vehicle.wheelbase_m / 2.0;
  const double u_end = u_length - 1.0 - vehicle.wheelbase_m / 2.0;
  if (u_end <= u_start + 1.0)
    throw ConfigError(trainSection().path(scenario::nested(
                          &TrainConfig::vehicle, &track::VehicleGeometry::bogie_spacing_m)) +
                      ": the route is too short for the train");
  const TrajectoryConfig clock = trajectorySection().read(sc.json());
  // The run ends short of the first obstacle in the train's way.
  double u_stop = u_end;
  if (train.stop_for_obstacles && !clock.static_only) {
    const auto obstacles = objectsSection().read(sc.json()).obstacles;
    if (const auto stop = detail::obstacleStop(r, layout, terrainSection().read(sc.json()),
                                               obstacles, train, u_start);
        stop && stop->u_m < u_end) {
      u_stop = stop->u_m;
      const environment::Obstacle& o = obstacles[stop->index];
      logInfo(fmt::format(
          "plan: the train stops {:g} m short of objects.obstacles[{}], a {} in its way at "
          "main chainage {:g} m; the run ends there (train.stop_for_obstacles)",
          train.obstacle_margin_m, stop->index, nameOf(o.kind), o.chainage_m));
    }
  }
  throwIfCancelled();
  const track::MotionProfile run =
      track::planMotion(r, route->route.stops, limits, train.dynamics, u_start, u_stop);
  track::MotionProfile motion =
      clock.static_only
          ? track::MotionProfile::standstill(
                u_start, clock.standstill_start_s + clock.standstill_end_s, run.limit())
          : run.withStandstill(clock.standstill_start_s, clock.standstill_end_s);
  // The run's sample count is bounded before anything is sized by it: a billion samples is a
  // 2.8-hour run at 10 kHz or 116 days at 100 Hz, beyond any dataset anyone writes.
  constexpr double kMaxSamples = 1e9;
  const double samples = motion.duration() / toSeconds(clock.sample_period_ns);
  if (!(samples <= kMaxSamples))
    throw ConfigError(fmt::format(
        "{}: a run of {:.0f} s at this period has {:.3g} samples (at most {:.0e}): raise the "
        "period or shorten the route",
        trajectorySection().path(&TrajectoryConfig::sample_period_ns), motion.duration(), samples,
        kMaxSamples));
  return std::make_shared<MotionStage>(
      MotionStage{key, limits,
                  TrainTrajectory(std::move(route), std::move(motion), vehicle,
                                  train.reference_point, clock.sample_period_ns)});
}

}  // namespace

std::span<const PipelineStage> pipelineStages() {
  return stageTable();
}

std::vector<std::string> stagesNotRun() {
  std::vector<std::string> out;
  for (const PipelineStage& s : stageTable())
    if (!s.implemented)
      out.emplace_back(s.description);
  return out;
}

Plan Planner::plan(const scenario::Scenario& sc) {
  const std::lock_guard lock(mutex_);
  const std::uint64_t route_key = stageKey(sc, "route", {});
  if (!route_ || route_->key != route_key) {
    throwIfCancelled();
    route_ = buildRoute(sc, route_key);
    ++route_builds_;
  }
  const std::uint64_t layout_key = stageKey(sc, "layout", {route_key});
  if (!layout_ || layout_->key != layout_key) {
    throwIfCancelled();
    layout_ = buildLayoutStage(sc, *route_, layout_key);
    ++layout_builds_;
  }
  // The layout too: an obstacle given on any of its tracks may stand in the train's way.
  const std::uint64_t motion_key = stageKey(sc, "motion", {route_key, layout_key});
  if (!motion_ || motion_->key != motion_key) {
    throwIfCancelled();
    motion_ = buildMotion(sc, route_, layout_->layout, motion_key);
    ++motion_builds_;
  }
  // Obstacles stand on the layout's tracks, clear of a tunnel's rock: one that cannot is left
  // out, said here (validate says so too).
  const auto obstacles = objectsSection().read(sc.json()).obstacles;
  const terrain::TerrainParams terrain = terrainSection().read(sc.json());
  for (std::size_t i = 0; i < obstacles.size(); ++i)
    if (const auto why = environment::obstacleLeftOut(layout_->layout, route_->route.route.blocks,
                                                      terrain, obstacles[i]))
      logWarn(fmt::format("objects.obstacles[{}] left out: {}", i, *why));
  Plan plan(route_, layout_, motion_);
  const track::Route& route = plan.route().route;
  logInfo(fmt::format(
      "plan: route {:.0f} m, {} blocks, {} tracks, {} design-rule violations, "
      "run of {:.1f} s ({} samples)",
      route.track.length(), route.blocks.size(), plan.layout().tracks.size(),
      plan.violations().size(), plan.motion().duration(), plan.trajectory().sampleCount()));
  return plan;
}

std::int64_t Planner::builds(std::string_view name) const {
  const std::lock_guard lock(mutex_);
  if (name == "route")
    return route_builds_;
  if (name == "layout")
    return layout_builds_;
  if (name == "motion")
    return motion_builds_;
  throw RuntimeError(fmt::format("no plan stage '{}'", name));
}

std::shared_ptr<const EnvironmentStage> makeEnvironment(const Plan& plan,
                                                        const scenario::Scenario& scenario) {
  return scenario::namingItsSource(scenario, [&] {
    auto stage = std::make_shared<EnvironmentStage>();
    stage->key = stageKey(scenario, "terrain", {plan.routeStage().key, plan.layoutShared()->key});
    stage->route = plan.routeShared();
    stage->layout = plan.layoutShared();
    stage->railway =
        std::make_shared<const terrain::Railway>(stage->route->route.route, stage->layout->layout);
    environment::EnvironmentParams params{terrainSection().read(scenario.json()),
                                          assetsSection().read(scenario.json()),
                                          objectsSection().read(scenario.json())};
    stage->environment = std::make_shared<const environment::Environment>(
        stage->railway, std::move(params), scenario.seed());
    return std::shared_ptr<const EnvironmentStage>(stage);
  });
}

std::unique_ptr<Plan> makePlan(const scenario::Scenario& scenario) {
  return scenario::namingItsSource(scenario, [&] {
    Planner planner;
    return std::make_unique<Plan>(planner.plan(scenario));
  });
}

namespace {

// Text formatted into a buffer and handed to a TextSink in pieces of about 64 KiB, so memory
// does not grow with the route; each piece is checked for non-finite values on its way out,
// and cancellation is polled between pieces.
class ChunkedSink {
 public:
  ChunkedSink(const TextSink& sink, const char* file) : sink_(sink), file_(file) {}
  ChunkedSink(const ChunkedSink&) = delete;
  ChunkedSink& operator=(const ChunkedSink&) = delete;

  fmt::memory_buffer& buffer() { return buffer_; }
  /// Hands the buffer on once it holds a piece's worth.
  void handOnIfFull() {
    if (buffer_.size() > (1u << 16)) {
      handOn();
      throwIfCancelled();
    }
  }
  /// Hands on whatever the buffer holds.
  void handOn() {
    io::requireFinite({buffer_.data(), buffer_.size()}, file_);
    sink_({buffer_.data(), buffer_.size()});
    buffer_.clear();
  }

 private:
  const TextSink& sink_;
  const char* file_;
  fmt::memory_buffer buffer_;
};

// To the micrometre, without a negative zero.
double micro(double v) {
  return std::round(v * 1e6) / 1e6 + 0.0;
}

}  // namespace

void writeRailroadJson(const Plan& plan, const TextSink& sink) {
  // Streamed: each block and track head through nlohmann::json, each polyline point by point,
  // so no document of the whole layout (nor of the route's blocks) is ever held in memory.
  const nlohmann::json head = {
      {"format", "trainsim-railroad"},
      {"frame",
       "world: the Earth-fixed ENU frame tangent to the WGS-84 ellipsoid at geodetic_origin, "
       "metres (not a map plane: z drops by d^2/2R with the distance d from the origin)"},
      {"main_track", {{"length_m", plan.route().route.track.length()}}}};
  std::string text = head.dump(1);
  // Reopen main_track (its closing brace and the document's) to add its blocks.
  text.erase(text.rfind('}'));
  text.erase(text.rfind('}'));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
    text.pop_back();
  text += ",\n  \"blocks\": [";
  sink(text);
  const auto& route_blocks = plan.route().route.blocks;
  for (std::size_t i = 0; i < route_blocks.size(); ++i) {
    const track::Block& b = route_blocks[i];
    const nlohmann::json jb = {{"id", b.id},
                               {"type", nameOf(b.type)},
                               {"chainage_begin_m", b.chainage_begin_m},
                               {"chainage_end_m", b.chainage_end_m},
                               {"speed_limit_m_s", b.speed_limit_m_s},
                               {"radius_m", b.radius_m},
                               {"cant_m", b.cant_m},
                               {"stop", b.stop}};
    sink(fmt::format("{}\n   {}", i == 0 ? "" : ",", jb.dump()));
  }
  sink("\n  ]\n },\n \"tracks\": [");
  const auto& tracks = plan.layout().tracks;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const track::LayoutTrack& t = tracks[i];
    // The track's keys in nlohmann's (sorted) order, its blocks ("blocks" sorts first) one by
    // one, then the polyline.
    sink(fmt::format("{}\n  {{\"blocks\":[", i == 0 ? "" : ","));
    for (std::size_t k = 0; k < t.blocks.size(); ++k) {
      const track::LayoutBlock& b = t.blocks[k];
      nlohmann::json jb = {{"type", nameOf(b.type)}, {"begin_m", b.begin_m}, {"end_m", b.end_m}};
      if (b.part != track::TrackPart::kWhole)
        jb["part"] = nameOf(b.part);
      if (b.main_block_id >= 0)
        jb["main_block_id"] = b.main_block_id;
      sink(k == 0 ? jb.dump() : "," + jb.dump());
    }
    nlohmann::json jt = {{"id", t.id},
                         {"kind", nameOf(t.kind)},
                         {"offset_m", t.offset_m},
                         {"main_chainage_begin_m", t.main_chainage_begin_m},
                         {"main_chainage_end_m", t.main_chainage_end_m}};
    if (t.joins_track >= 0)
      jt["joins_track"] = t.joins_track;
    text = jt.dump();
    sink(fmt::format("],{},\"polyline_m\":[", std::string_view(text).substr(1, text.size() - 2)));
    ChunkedSink points(sink, io::DatasetLayout::kRailroad);
    bool first = true;
    track::forEachPolylinePoint(
        plan.route().route.track, t, [&](const Eigen::Vector3d& p, double, double) {
          fmt::format_to(std::back_inserter(points.buffer()), "{}\n   [{},{},{}]", first ? "" : ",",
                         micro(p.x()), micro(p.y()), micro(p.z()));
          first = false;
          points.handOnIfFull();
        });
    points.handOn();
    sink("]}");
  }
  sink("\n ]\n}\n");
}

std::string railroadJson(const Plan& plan) {
  std::string out;
  writeRailroadJson(plan, [&](std::string_view text) { out.append(text); });
  return out;
}

std::string designReportJson(const Plan& plan) {
  nlohmann::json list = nlohmann::json::array();
  std::map<std::string, int> counts;
  for (const track::Violation& v : plan.violations()) {
    ++counts[v.rule];
    list.push_back({{"rule", v.rule},
                    {"chainage_begin_m", v.chainage_begin_m},
                    {"chainage_end_m", v.chainage_end_m},
                    {"block_id", v.block_id},
                    {"value", v.value},
                    {"limit", v.limit},
                    {"unit", v.unit},
                    {"message", v.message}});
  }
  const track::DesignRules& r = plan.options().rules;
  const nlohmann::json doc = {{"format", "trainsim-design-report"},
                              {"design_speed_km_h", r.design_speed_m_s * 3.6},
                              {"min_radius_m", r.minRadius(r.design_speed_m_s)},
                              {"min_vertical_radius_m", r.minVerticalRadius(r.design_speed_m_s)},
                              {"route_length_m", plan.route().route.track.length()},
                              {"violation_count", plan.violations().size()},
                              {"violations_by_rule", counts},
                              {"violations", list}};
  return doc.dump(2) + "\n";
}

void writeTrajectoryCsv(const Plan& plan, const TextSink& sink) {
  const TrainTrajectory& traj = plan.trajectory();
  const track::Route& route = plan.route().route;
  ChunkedSink chunks(sink, io::DatasetLayout::kTrajectory);
  fmt::memory_buffer& out = chunks.buffer();
  fmt::format_to(std::back_inserter(out),
                 "t_ns,chainage_m,distance_m,speed_m_s,accel_m_s2,jerk_m_s3,speed_limit_m_s,"
                 "front_x_m,front_y_m,front_z_m,rear_x_m,rear_y_m,rear_z_m,x_m,y_m,z_m,"
                 "yaw_rad,pitch_rad,roll_rad,ve_m_s,vn_m_s,vu_m_s,ae_m_s2,an_m_s2,au_m_s2,"
                 "vx_m_s,vy_m_s,vz_m_s,ax_m_s2,ay_m_s2,az_m_s2,wx_rad_s,wy_rad_s,wz_rad_s,"
                 "alpha_x_rad_s2,alpha_y_rad_s2,alpha_z_rad_s2,curvature_1_m,cant_m,block_id,"
                 "track_id\n");
  const Eigen::Vector3d& ref = traj.referencePoint();
  for (std::int64_t k = 0; k < traj.sampleCount(); ++k) {
    const track::MotionState m = traj.motion(k);
    const track::BodyState b = traj.body(m);
    const Eigen::Vector3d p = b.pointPosition(ref);
    const Eigen::Vector3d v = b.pointVelocity(ref);
    const Eigen::Vector3d a = b.pointAcceleration(ref);
    const Eigen::Vector3d vb = b.r_world_body.transpose() * v;
    const Eigen::Vector3d ab = b.r_world_body.transpose() * a;
    const track::TrackPoint& f = b.front_track;
    fmt::format_to(std::back_inserter(out),
                   "{},{:.6f},{:.6f},{:.9g},{:.9g},{:.9g},{:.9g},"
                   "{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},"
                   "{:.12g},{:.12g},{:.12g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
                   "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},"
                   "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{},0\n",
                   k * traj.samplePeriod(), f.chainage_m, m.u_m, m.v_m_s, m.a_m_s2, m.jerk_m_s3,
                   plan.motion().limit().at(m.u_m), b.front.x(), b.front.y(), b.front.z(),
                   b.rear.x(), b.rear.y(), b.rear.z(), p.x(), p.y(), p.z(), b.yaw_rad, b.pitch_rad,
                   b.roll_rad, v.x(), v.y(), v.z(), a.x(), a.y(), a.z(), vb.x(), vb.y(), vb.z(),
                   ab.x(), ab.y(), ab.z(), b.w_body.x(), b.w_body.y(), b.w_body.z(),
                   b.alpha_body.x(), b.alpha_body.y(), b.alpha_body.z(), f.curvature_1_m, f.cant_m,
                   route.blockAt(f.chainage_m).id);
    chunks.handOnIfFull();
  }
  chunks.handOn();
}

std::string trajectoryCsv(const Plan& plan) {
  std::string out;
  writeTrajectoryCsv(plan, [&](std::string_view text) { out.append(text); });
  return out;
}

void writePlan(const Plan& plan, const std::filesystem::path& folder) {
  const auto stream = [&](const char* name, void (*write)(const Plan&, const TextSink&)) {
    io::AtomicFile file(folder / name);
    write(plan, [&](std::string_view text) { file.write(text); });
    file.commit();
  };
  stream(io::DatasetLayout::kRailroad, &writeRailroadJson);
  io::writeFileAtomic(folder / io::DatasetLayout::kDesignReport, designReportJson(plan));
  stream(io::DatasetLayout::kTrajectory, &writeTrajectoryCsv);
}

void writePlanFolder(const Plan& plan, const scenario::Scenario& scenario,
                     const std::filesystem::path& out, bool force) {
  namespace fs = std::filesystem;
  const io::OutputFolder state = io::checkOutputFolder(out, {force, false});
  std::error_code ec;
  const bool created = !fs::exists(out, ec);
  try {
    if (state == io::OutputFolder::kStartOver)
      io::removeOwnEntries(out);
    fs::create_directories(out, ec);
    if (ec)
      throw IoError("cannot create folder " + out.string() + ": " + ec.message());
    io::writeFileAtomic(out / io::DatasetLayout::kScenario, scenario.text());
    writePlan(plan, out);
  } catch (...) {
    if (created) {
      fs::remove_all(out, ec);
    } else {
      for (const char* f : {io::DatasetLayout::kScenario, io::DatasetLayout::kRailroad,
                            io::DatasetLayout::kDesignReport, io::DatasetLayout::kTrajectory})
        fs::remove(out / f, ec);
    }
    throw;
  }
}

scenario::Json blockListJson(const track::Route& route) {
  // What a designer would type: each number to 12 significant digits, so that a cant of
  // 0.085 m reads 85 mm while lengths keep the micrometres that rebuild the same chainages.
  const auto round = [](scenario::Json& j) {
    for (auto& [key, value] : j.items())
      if (value.is_number_float())
        value = scenario::jsonDefault(value.get<double>(), scenario::units::kNone);
  };
  scenario::Json list = scenario::Json::array();
  for (const track::BlockSpec& b : track::blockSpecs(route)) {
    scenario::Json item = routeBlockJson(b);
    round(item);
    list.push_back(std::move(item));
  }
  return list;
}

}  // namespace trainsim::sim
