#include "trainsim/track/earth.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numbers>

namespace trainsim::track {
namespace {

constexpr double kMaxStep_m = 5.0;
constexpr double kMaxTurn_rad = 0.03;  // design heading change per RK4 step

// Columns: east, north, up of the local frame at (lat, lon), in ECEF.
Eigen::Matrix3d ecefFromEnu(double lat, double lon) {
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  Eigen::Matrix3d r;
  r << -so, -sl * co, cl * co, co, -sl * so, cl * so, 0.0, cl, sl;
  return r;
}

double stepFor(const HorizontalElement& e) {
  const double k = std::max(std::abs(e.curvature_start_1_m), std::abs(e.curvature_end_1_m));
  return k > 0.0 ? std::min(kMaxStep_m, kMaxTurn_rad / k) : kMaxStep_m;
}

}  // namespace

Eigen::Vector3d EarthPlacement::Point::along() const {
  return std::sin(azimuth_rad) * east + std::cos(azimuth_rad) * north;
}
Eigen::Vector3d EarthPlacement::Point::left() const {
  return std::sin(azimuth_rad) * north - std::cos(azimuth_rad) * east;
}

double EarthPlacement::designAzimuth(const HorizontalAlignment& horizontal, double s) const {
  // Heading is counter-clockwise from east, azimuth clockwise from north.
  return azimuth0_ - (horizontal.headingAt(s) - heading0_);
}

EarthPlacement::State EarthPlacement::advance(const HorizontalAlignment& horizontal,
                                              const VerticalProfile& vertical, State y, double s,
                                              double to) const {
  const double span = s - y.s;
  if (span == 0.0)
    return y;
  // A fixed number of steps for the whole knot interval (up to `to`), so that the result is a
  // smooth function of s within it.
  const double step = stepFor(horizontal.elements()[horizontal.elementAt(
      std::clamp(y.s + 0.5 * (to - y.s), 0.0, horizontal.length()))]);
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(to - y.s) / step)));
  const double h = span / n;
  const double h0 = anchor_.height_m;
  // y' = f(s, y) for y = (lat, lon, delta).
  const auto f = [&](double at, const Eigen::Vector3d& v) {
    const double azimuth = designAzimuth(horizontal, at) + v.z();
    const double height = h0 + vertical.at(at).z_m;
    const EllipsoidRadii r = wgs84Radii(v.x());
    const double sa = std::sin(azimuth), ca = std::cos(azimuth);
    return Eigen::Vector3d(ca / (r.meridian_m + height),
                           sa / ((r.prime_vertical_m + height) * std::cos(v.x())),
                           sa * std::tan(v.x()) / (r.prime_vertical_m + height));
  };
  Eigen::Vector3d v(y.lat, y.lon, y.delta);
  double at = y.s;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d k1 = f(at, v);
    const Eigen::Vector3d k2 = f(at + h / 2, v + h / 2 * k1);
    const Eigen::Vector3d k3 = f(at + h / 2, v + h / 2 * k2);
    const Eigen::Vector3d k4 = f(at + h, v + h * k3);
    v += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    at = y.s + (i + 1) * h;
  }
  return {s, v.x(), v.y(), v.z()};
}

int EarthPlacement::subdivisions(const HorizontalAlignment& horizontal, std::size_t i) const {
  const double a = horizontal.elementStart(i), b = horizontal.elementStart(i + 1);
  return std::max(1, static_cast<int>(std::ceil((b - a) / knot_spacing_m_)));
}

EarthPlacement::State EarthPlacement::nextKnot(const HorizontalAlignment& horizontal,
                                               const VerticalProfile& vertical, const State& y,
                                               std::uint32_t& element, std::uint32_t& k) const {
  if (k == 0 || static_cast<int>(k) == subdivisions(horizontal, element)) {
    if (k != 0)
      ++element;
    k = 0;
  }
  ++k;
  const int n = subdivisions(horizontal, element);
  const double a = horizontal.elementStart(element), b = horizontal.elementStart(element + 1);
  const double s = static_cast<int>(k) == n ? b : a + (b - a) * static_cast<int>(k) / n;
  return advance(horizontal, vertical, y, s, s);
}

EarthPlacement::EarthPlacement(const HorizontalAlignment& horizontal,
                               const VerticalProfile& vertical, const GeodeticPoint& anchor,
                               double knot_spacing_m)
    : anchor_(anchor), knot_spacing_m_(knot_spacing_m) {
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id.fetch_add(1, std::memory_order_relaxed);
  const double deg = std::numbers::pi / 180.0;
  const GeodeticAnchor frame(anchor);
  const HorizontalState start = horizontal.at(0.0);
  heading0_ = start.heading_rad;
  GeodeticPoint g = anchor;
  if (start.position_m.norm() == 0.0) {
    azimuth0_ = std::numbers::pi / 2 - heading0_;
  } else {
    g = frame.fromAzimuthalEquidistant(start.position_m, anchor.height_m);
    azimuth0_ = frame.azimuthOfProjectedDirection(start.position_m, heading0_);
  }
  const double lat0 = anchor.latitude_deg * deg, lon0 = anchor.longitude_deg * deg;
  ecef0_ = wgs84Ecef(lat0, lon0, anchor.height_m);
  r_world_ecef_ = ecefFromEnu(lat0, lon0).transpose();

  // Knots at every element start and at most knot_spacing_m apart, of which every
  // kKnotsPerChunk-th is kept.
  std::size_t total = 1;
  for (std::size_t i = 0; i < horizontal.elements().size(); ++i)
    total += static_cast<std::size_t>(subdivisions(horizontal, i));
  knot_count_ = total;
  anchors_.reserve((total - 1) / kKnotsPerChunk + 1);
  State y{0.0, g.latitude_deg * deg, g.longitude_deg * deg, 0.0};
  std::uint32_t element = 0, k = 0;
  anchors_.push_back({y, element, k});
  for (std::size_t j = 1; j < total; ++j) {
    y = nextKnot(horizontal, vertical, y, element, k);
    if (j % kKnotsPerChunk == 0)
      anchors_.push_back({y, element, k});
  }
}

const std::vector<EarthPlacement::State>& EarthPlacement::chunk(
    const HorizontalAlignment& horizontal, const VerticalProfile& vertical, std::size_t c) const {
  // A few chunks per thread: a trajectory's pivots and wheelsets straddle at most two.
  struct Entry {
    std::uint64_t owner = 0;
    std::size_t chunk = 0;
    std::vector<State> knots;
  };
  thread_local std::array<Entry, 4> cache;
  thread_local std::size_t next = 0;
  for (Entry& e : cache)
    if (e.owner == id_ && e.chunk == c)
      return e.knots;
  Entry& e = cache[next];
  next = (next + 1) % cache.size();
  e.owner = id_;
  e.chunk = c;
  const Anchor& a = anchors_[c];
  const std::size_t first = c * kKnotsPerChunk;
  const std::size_t count = std::min(kKnotsPerChunk + 1, knot_count_ - first);
  e.knots.assign(1, a.state);
  std::uint32_t element = a.element, k = a.k;
  while (e.knots.size() < count)
    e.knots.push_back(nextKnot(horizontal, vertical, e.knots.back(), element, k));
  return e.knots;
}

EarthPlacement::Point EarthPlacement::at(const HorizontalAlignment& horizontal,
                                         const VerticalProfile& vertical, double s) const {
  const auto anchor = std::upper_bound(anchors_.begin(), anchors_.end(), s,
                                       [](double x, const Anchor& a) { return x < a.state.s; });
  const std::size_t c =
      anchor == anchors_.begin() ? 0 : static_cast<std::size_t>(anchor - anchors_.begin()) - 1;
  const std::vector<State>& knots = chunk(horizontal, vertical, c);
  const auto it = std::upper_bound(knots.begin(), knots.end(), s,
                                   [](double x, const State& k) { return x < k.s; });
  const auto from = it == knots.begin() ? knots.begin() : it - 1;
  const double to = from + 1 == knots.end() ? s : (from + 1)->s;
  const State y = advance(horizontal, vertical, *from, s, to);
  Point p;
  p.latitude_rad = y.lat;
  p.longitude_rad = y.lon;
  p.height_m = anchor_.height_m + vertical.at(s).z_m;
  p.azimuth_rad = designAzimuth(horizontal, s) + y.delta;
  p.position = r_world_ecef_ * (wgs84Ecef(y.lat, y.lon, p.height_m) - ecef0_);
  const Eigen::Matrix3d enu = r_world_ecef_ * ecefFromEnu(y.lat, y.lon);
  p.east = enu.col(0);
  p.north = enu.col(1);
  p.up = enu.col(2);
  const EllipsoidRadii r = wgs84Radii(y.lat);
  const double mh = r.meridian_m + p.height_m, nh = r.prime_vertical_m + p.height_m;
  const double sa = std::sin(p.azimuth_rad), ca = std::cos(p.azimuth_rad);
  p.normal_curvature_1_m = sa * sa / nh + ca * ca / mh;
  // The up vector turns with the ground: d(up)/ds = e sin α/(N+h) + n cos α/(M+h); along a
  // curve α turns at −κ, which is the part of the second derivative that matters (the rest is
  // of order 1/R²).
  p.up_d1 = p.east * sa / nh + p.north * ca / mh;
  const double turn = -horizontal.curvatureAt(s);  // dα/ds
  p.up_d2 = turn * (p.east * ca / nh - p.north * sa / mh);
  return p;
}

}  // namespace trainsim::track
