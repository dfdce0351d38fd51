#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

#include "route_builder.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/track/route_design.hpp"

namespace trainsim::track {
namespace {

struct Waypoint {
  Eigen::Vector3d p;  // x east, y north, z height (local map frame)
  double radius_m = 0.0;
  double vertical_radius_m = 0.0;
  BlockType leg = BlockType::kStraight;
  int line = 0;
};

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos)
    return {};
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ','))
    out.push_back(trim(field));
  if (!line.empty() && line.back() == ',')
    out.emplace_back();
  return out;
}

constexpr double kMaxWaypointDistance = 2e6;  // m, the longest route a scenario may ask for
constexpr double kMaxWaypointHeight = 1e4;    // m, above or below the geodetic origin
constexpr double kMaxWaypointGrade = 0.5;     // 500 per mille

// A million waypoints; a longer file is a mistake (a point cloud, a log), not a route.
constexpr std::size_t kMaxWaypointFileBytes = std::size_t{64} << 20;

std::vector<Waypoint> readWaypoints(const std::filesystem::path& csv,
                                    const GeodeticAnchor& anchor) {
  std::string text;
  try {
    text = io::readFile(csv, kMaxWaypointFileBytes);
  } catch (const IoError& e) {  // a missing or unreadable input file is bad input: exit 2
    throw ConfigError(e.what());
  }
  const std::string where = csv.string();
  std::istringstream in(text);
  std::string line;
  int number = 0;
  std::map<std::string, std::size_t> column;
  std::vector<Waypoint> points;
  bool ned = false;
  while (std::getline(in, line)) {
    ++number;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#')
      continue;
    const std::vector<std::string> fields = splitCsv(t);
    if (column.empty()) {
      for (std::size_t i = 0; i < fields.size(); ++i)
        if (!column.emplace(fields[i], i).second)
          throw ConfigError(fmt::format("{}:{}: the header names column '{}' twice", where, number,
                                        messageValue(fields[i])));
      ned = column.count("n_m") && column.count("e_m") && column.count("d_m");
      const bool lla = column.count("latitude_deg") && column.count("longitude_deg") &&
                       (column.count("height_m") || column.count("altitude_m"));
      if (!ned && !lla)
        throw ConfigError(
            fmt::format("{}:{}: the header needs the columns n_m,e_m,d_m or "
                        "latitude_deg,longitude_deg,height_m (got '{}')",
                        where, number, messageValue(t)));
      continue;
    }
    if (fields.size() > column.size())  // the header's names are unique
      throw ConfigError(fmt::format(
          "{}:{}: {} fields, but the header names {} columns (a decimal comma? use '.')", where,
          number, fields.size(), column.size()));
    auto number_at = [&](const std::string& name, bool required) -> std::optional<double> {
      const auto it = column.find(name);
      if (it == column.end() || it->second >= fields.size() || fields[it->second].empty()) {
        if (required)
          throw ConfigError(fmt::format("{}:{}: column '{}' is empty", where, number, name));
        return std::nullopt;
      }
      const std::string& f = fields[it->second];
      double value = 0.0;
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), value);
      if (ec != std::errc() || end != f.data() + f.size() || !std::isfinite(value))
        throw ConfigError(fmt::format("{}:{}: column '{}': '{}' is not a number", where, number,
                                      messageValue(name), messageValue(f)));
      return value;
    };
    Waypoint w;
    w.line = number;
    if (ned) {
      w.p = {*number_at("e_m", true), *number_at("n_m", true), -*number_at("d_m", true)};
    } else {
      const double lat = *number_at("latitude_deg", true);
      const double lon = *number_at("longitude_deg", true);
      const double h = *number_at(column.count("height_m") ? "height_m" : "altitude_m", true);
      if (std::abs(lat) > 90.0 || std::abs(lon) > 180.0)
        throw ConfigError(fmt::format("{}:{}: latitude/longitude out of range", where, number));
      // Horizontal position in the anchor's azimuthal equidistant projection (distances and
      // azimuths from the anchor are the ground's), where the route is designed before it is
      // laid on the ellipsoid; height above the ellipsoid relative to the anchor, so that
      // grades are measured against the local level and the heights are kept.
      const Eigen::Vector2d en = anchor.toAzimuthalEquidistant(lat, lon);
      w.p = {en.x(), en.y(), h - anchor.origin().height_m};
    }
    // Within the route's reach (2000 km) and the Earth's heights, so that no later sum
    // overflows or loses the metres.
    if (w.p.head<2>().norm() > kMaxWaypointDistance || std::abs(w.p.z()) > kMaxWaypointHeight)
      throw ConfigError(fmt::format(
          "{}:{}: the waypoint lies {:.3g} m from the origin and {:.3g} m above it (at most "
          "{:.0f} km and {:.0f} m)",
          where, number, w.p.head<2>().norm(), w.p.z(), kMaxWaypointDistance / 1e3,
          kMaxWaypointHeight));
    w.radius_m = number_at("radius_m", false).value_or(0.0);
    w.vertical_radius_m = number_at("vertical_radius_m", false).value_or(0.0);
    if (w.radius_m < 0.0 || w.vertical_radius_m < 0.0)
      throw ConfigError(fmt::format("{}:{}: radii must not be negative", where, number));
    if (const auto it = column.find("block"); it != column.end() && it->second < fields.size()) {
      const std::string& b = fields[it->second];
      const std::optional<BlockType> type = enumFromName<BlockType>(b);
      if (type == BlockType::kStation || type == BlockType::kTunnel || type == BlockType::kBridge)
        w.leg = *type;
      else if (!(b.empty() || type == BlockType::kStraight || type == BlockType::kCurve))
        throw ConfigError(fmt::format(
            "{}:{}: column 'block': '{}' is not one of station, tunnel, bridge, straight, curve",
            where, number, messageValue(b)));
    }
    points.push_back(w);
  }
  if (column.empty())
    throw ConfigError(fmt::format("{}: no header line", where));
  if (points.size() < 2)
    throw ConfigError(fmt::format("{}: a route needs at least two waypoints", where));
  if (!ned) {
    // Chainage is measured at the rail's height, the projection on the ellipsoid: scale the
    // plane by (R + h)/R at the waypoints' mean height (R the anchor's Gaussian radius), so
    // that the route laid back on the Earth passes its points to (Δh/R)·d + d³/R².
    double mean = 0.0;
    for (const Waypoint& w : points)
      mean += (w.p.z() + anchor.origin().height_m) / static_cast<double>(points.size());
    const double scale = 1.0 + mean / anchor.gaussianRadius();
    for (Waypoint& w : points)
      w.p.head<2>() *= scale;
  }
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const double run = (points[i + 1].p - points[i].p).head<2>().norm();
    if (run < 1e-3)
      throw ConfigError(fmt::format("{}:{}: waypoint repeats the one on line {}", where,
                                    points[i + 1].line, points[i].line));
    // Steeper than this is a wall, not a grade (rack railways stop near 250 per mille); the
    // vertical profile could not even be laid (it would reach a vertical tangent).
    const double grade = (points[i + 1].p.z() - points[i].p.z()) / run;
    if (std::abs(grade) > kMaxWaypointGrade)
      throw ConfigError(fmt::format(
          "{}:{}: the grade from line {} is {:.0f} per mille (at most {:.0f}): check the heights",
          where, points[i + 1].line, points[i].line, grade * 1e3, kMaxWaypointGrade * 1e3));
  }
  return points;
}

// Below this a "railway" curve is a fitting failure, not a design to report on.
constexpr double kSmallestRadius_m = 50.0;

double wrapAngle(double a) {
  return std::remainder(a, 2.0 * std::numbers::pi);
}

// A curve at a point of intersection: tangent length from the PI to where the transition
// starts, and the elements' lengths.
struct CurveFit {
  double radius = 0.0;
  double transition = 0.0;
  double arc = 0.0;
  double cant = 0.0;
  double tangent = 0.0;
};

CurveFit fitCurve(const DesignRules& rules, TransitionShape shape, double v, double deflection,
                  double radius) {
  CurveFit f;
  f.radius = radius;
  const double delta = std::abs(deflection);
  f.cant = rules.appliedCant(v, radius);
  const double deficiency = std::max(0.0, rules.equilibriumCant(v, radius) - f.cant);
  f.transition =
      std::ceil(std::max(20.0, rules.minTransitionLength(v, f.cant, deficiency)) / 5.0) * 5.0;
  if (f.transition / radius > delta)  // no room for an arc: two transitions back to back
    f.transition = radius * delta;
  const double tau = f.transition / (2.0 * radius);
  f.arc = radius * (delta - 2.0 * tau);
  if (f.transition > 0.0) {
    const Eigen::Vector2d end = detail::transitionEnd(f.transition, radius, shape);
    const double shift = end.y() - radius * (1.0 - std::cos(tau));
    const double k = end.x() - radius * std::sin(tau);
    f.tangent = (radius + shift) * std::tan(delta / 2.0) + k;
  } else {
    f.tangent = radius * std::tan(delta / 2.0);
  }
  return f;
}

// Largest radius in [1 m, r_max] whose tangent fits in `room`.
double fittingRadius(const DesignRules& rules, TransitionShape shape, double v, double deflection,
                     double room, double r_max) {
  if (fitCurve(rules, shape, v, deflection, r_max).tangent <= room)
    return r_max;
  double lo = 1.0, hi = r_max;
  for (int i = 0; i < 80; ++i) {
    const double mid = std::sqrt(lo * hi);
    (fitCurve(rules, shape, v, deflection, mid).tangent <= room ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

DesignedRoute importWaypoints(const std::filesystem::path& csv, const GeodeticAnchor& anchor,
                              const WaypointParams& params, const RouteOptions& options) {
  const std::vector<Waypoint> w = readWaypoints(csv, anchor);
  const DesignRules& rules = options.rules;
  const std::size_t n = w.size();
  std::vector<double> leg(n - 1), heading(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Eigen::Vector2d d = (w[i + 1].p - w[i].p).head<2>();
    leg[i] = d.norm();
    heading[i] = std::atan2(d.y(), d.x());
  }
  std::vector<Violation> fitting;
  std::vector<std::optional<Violation>> reduced_at(n);
  std::vector<CurveFit> curves(n);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double deflection = wrapAngle(heading[i] - heading[i - 1]);
    if (std::abs(deflection) > 0.9 * std::numbers::pi)
      throw ConfigError(fmt::format("{}:{}: the route turns back at this waypoint ({:.1f} deg)",
                                    csv.string(), w[i].line,
                                    deflection * 180.0 / std::numbers::pi));
    if (std::abs(deflection) < 1e-9)
      continue;
    // Curves are designed for the line speed; stations, tunnels and bridges sit on the straights.
    const double v = rules.design_speed_m_s;
    auto share = [&](std::size_t l) { return w[l].leg == BlockType::kStraight ? 0.5 : 0.25; };
    const bool given = w[i].radius_m > 0.0;
    const double room_before =
        given ? leg[i - 1] - curves[i - 1].tangent
              : std::min(leg[i - 1] - curves[i - 1].tangent, share(i - 1) * leg[i - 1]);
    const double room_after = (i + 2 == n || given) ? leg[i] : share(i) * leg[i];
    const double room = std::min(room_before, room_after);
    double radius = given ? w[i].radius_m
                          : fittingRadius(rules, options.transition_shape, v, deflection, room,
                                          params.radius_max_m);
    CurveFit f = fitCurve(rules, options.transition_shape, v, deflection, radius);
    if (f.tangent > room) {
      radius = fittingRadius(rules, options.transition_shape, v, deflection, room, radius);
      f = fitCurve(rules, options.transition_shape, v, deflection, radius);
      reduced_at[i] =
          Violation{"radius_fit",
                    0.0,
                    0.0,
                    -1,
                    radius,
                    w[i].radius_m,
                    "m",
                    fmt::format("waypoint on line {}: radius {:.0f} m does not fit between "
                                "its neighbours; reduced to {:.1f} m",
                                w[i].line, w[i].radius_m, radius)};
    }
    if (radius < kSmallestRadius_m)
      throw ConfigError(fmt::format(
          "{}:{}: the curve at this waypoint does not fit between its neighbours (radius "
          "{:.1f} m); move the waypoints apart or give smaller radii",
          csv.string(), w[i].line, radius));
    f.radius = std::copysign(radius, deflection);
    curves[i] = f;
  }

  detail::RouteBuilder builder(options, w[0].p.head<2>(), heading[0]);
  std::vector<Pvi> pvis{{0.0, w[0].p.z(), 0.0}};
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double straight = leg[i] - curves[i].tangent - curves[i + 1].tangent;
    if (straight < -1e-6)
      throw ConfigError(fmt::format(
          "{}:{}: the curves at this waypoint and the next (line {}) overlap by {:.1f} m; move "
          "the waypoints apart or give smaller radii",
          csv.string(), w[i].line, w[i + 1].line, -straight));
    builder.straight(std::max(0.0, straight), w[i].leg);
    if (i + 2 == n)
      break;
    const CurveFit& f = curves[i + 1];
    const double start = builder.chainage();
    if (f.radius != 0.0)
      builder.curve(f.radius, f.arc, f.transition, f.cant);
    const double mid = 0.5 * (start + builder.chainage());
    const double v = rules.design_speed_m_s;
    const double rv = w[i + 1].vertical_radius_m > 0.0
                          ? w[i + 1].vertical_radius_m
                          : std::ceil(rules.minVerticalRadius(v) / 100.0) * 100.0;
    pvis.push_back({mid, w[i + 1].p.z(), rv});
    // Curves reduced to fit are reported at the chainage where they were laid out.
    if (reduced_at[i + 1]) {
      reduced_at[i + 1]->chainage_begin_m = start;
      reduced_at[i + 1]->chainage_end_m = builder.chainage();
      fitting.push_back(*reduced_at[i + 1]);
    }
  }
  const double length = builder.chainage();
  pvis.push_back({length, w[n - 1].p.z(), 0.0});
  std::vector<std::pair<std::size_t, double>> reduced;
  VerticalProfile vertical = VerticalProfile::fromPvis(pvis, &reduced);
  for (const auto& [index, r] : reduced) {
    fitting.push_back({"vertical_fit", pvis[index].chainage_m, pvis[index].chainage_m, -1, r,
                       pvis[index].radius_m, "m",
                       fmt::format("vertical curve at waypoint on line {} reduced from {:.0f} m to "
                                   "{:.0f} m to fit between its neighbours",
                                   w[index].line, pvis[index].radius_m, r)});
  }
  DesignedRoute out = builder.finish(std::move(vertical));
  for (Violation& v : fitting)
    v.block_id = out.route.blockAt(v.chainage_begin_m).id;
  out.fitting = std::move(fitting);

  // The element chain must end on the last waypoint; anything else is a bug in the fit.
  const Eigen::Vector2d end = out.route.track.horizontal().at(length).position_m;
  if ((end - w[n - 1].p.head<2>()).norm() > 1e-6 * std::max(1.0, length))
    throw RuntimeError(fmt::format("{}: fitted alignment misses the last waypoint by {:.3g} m",
                                   csv.string(), (end - w[n - 1].p.head<2>()).norm()));
  return out;
}

}  // namespace trainsim::track
