#include "trainsim/track/motion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"

namespace trainsim::track {
namespace {

// Jerk-limited change of speed from rest-acceleration to rest-acceleration.
struct Change {
  double accel;  // magnitude limit
  double jerk;

  double time(double v0, double v1) const {
    const double dv = std::abs(v1 - v0);
    if (dv * jerk < accel * accel)
      return 2.0 * std::sqrt(dv / jerk);
    return dv / accel + accel / jerk;
  }
  // The acceleration profile is symmetric in time, so the mean speed is (v0 + v1)/2.
  double distance(double v0, double v1) const { return 0.5 * (v0 + v1) * time(v0, v1); }

  void append(std::vector<MotionSegment>& out, double v0, double v1) const {
    const double dv = std::abs(v1 - v0);
    if (dv <= 0.0)
      return;
    const double sign = v1 > v0 ? 1.0 : -1.0;
    double ramp, hold;
    if (dv * jerk < accel * accel) {
      ramp = std::sqrt(dv / jerk);
      hold = 0.0;
    } else {
      ramp = accel / jerk;
      hold = dv / accel - accel / jerk;
    }
    out.push_back({0, 0, 0, 0, sign * jerk, ramp});
    if (hold > 0.0)
      out.push_back({0, 0, 0, 0, 0.0, hold});
    out.push_back({0, 0, 0, 0, -sign * jerk, ramp});
  }
};

// Largest v <= cap reachable from v0 within distance d (the change is monotonic in v).
double reach(const Change& c, double v0, double d, double cap) {
  if (cap <= v0 || c.distance(v0, cap) <= d)
    return cap;
  double lo = v0, hi = cap;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (c.distance(v0, mid) <= d ? lo : hi) = mid;
  }
  return lo;
}

struct Section {
  double u0, u1;
  double limit;
  double stop_dwell = -1.0;  // >= 0: the train stops at u1 for this long
};

double maxUphill(const Route& route, double s0, double s1) {
  const VerticalProfile& p = route.track.vertical();
  double worst = -1.0;
  for (std::size_t i = 0; i < p.elements().size(); ++i) {
    const double a = p.elementStart(i), b = p.elementStart(i + 1);
    if (b < s0 || a > s1)
      continue;
    const VerticalElement& e = p.elements()[i];
    worst = std::max({worst, e.sin_pitch_start, e.sin_pitch_start + e.curvature_1_m * e.length_m});
  }
  return worst;
}

}  // namespace

double TrainDynamics::availableAccel(double v, double sin_grade) const {
  const double traction = std::min(max_traction_n, max_power_w / std::max(v, 1e-6));
  const double resistance = davis_a_n + davis_b_n_s_m * v + davis_c_n_s2_m2 * v * v;
  return (traction - resistance) / (mass_kg * rotating_mass_factor) -
         kStandardGravity_m_s2 * sin_grade;
}

double SpeedLimit::at(double u) const {
  const auto it = std::upper_bound(u_begin_m.begin(), u_begin_m.end(), u);
  return limit_m_s[it == u_begin_m.begin() ? 0
                                           : static_cast<std::size_t>(it - u_begin_m.begin()) - 1];
}

MotionProfile::MotionProfile(std::vector<MotionSegment> segments, SpeedLimit limit)
    : segments_(std::move(segments)), limit_(std::move(limit)) {}

double MotionProfile::duration() const {
  return segments_.empty() ? 0.0 : segments_.back().t0_s + segments_.back().duration_s;
}

MotionProfile MotionProfile::withStandstill(double before_s, double after_s) const {
  if (segments_.empty())
    return *this;
  std::vector<MotionSegment> out;
  out.reserve(segments_.size() + 2);
  if (before_s > 0.0)
    out.push_back({0.0, segments_.front().u0_m, 0.0, 0.0, 0.0, before_s});
  for (MotionSegment s : segments_) {
    s.t0_s += before_s;
    out.push_back(s);
  }
  if (after_s > 0.0) {
    const double end_t = duration() + before_s;
    out.push_back({end_t, at(duration()).u_m, 0.0, 0.0, 0.0, after_s});
  }
  return MotionProfile(std::move(out), limit_);
}

MotionProfile MotionProfile::standstill(double u_m, double duration_s, SpeedLimit limit) {
  return MotionProfile({{0.0, u_m, 0.0, 0.0, 0.0, duration_s}}, std::move(limit));
}

double MotionProfile::timeAtDistance(double u) const {
  if (segments_.empty() || u <= segments_.front().u0_m)
    return 0.0;
  const auto end_u = [](const MotionSegment& s) {
    const double d = s.duration_s;
    return s.u0_m + s.v0_m_s * d + s.a0_m_s2 * d * d / 2.0 + s.jerk_m_s3 * d * d * d / 6.0;
  };
  // Segment ends are non-decreasing in u: the first segment that reaches u.
  const auto it = std::partition_point(segments_.begin(), segments_.end(),
                                       [&](const MotionSegment& s) { return end_u(s) < u; });
  if (it == segments_.end())
    return duration();
  // Bisection to 1 ps or to adjacent doubles, whichever comes first: a segment longer than
  // 8192 s has no two doubles 1 ps apart, and a bare `while (hi - lo > 1e-12)` never ends.
  double lo = 0.0, hi = it->duration_s;
  for (int i = 0; i < 128 && hi - lo > 1e-12; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi)
      break;
    const double um = it->u0_m + it->v0_m_s * mid + it->a0_m_s2 * mid * mid / 2.0 +
                      it->jerk_m_s3 * mid * mid * mid / 6.0;
    (um < u ? lo : hi) = mid;
  }
  return it->t0_s + hi;
}

MotionState MotionProfile::at(double t) const {
  if (segments_.empty())
    return {};
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                             [](double x, const MotionSegment& s) { return x < s.t0_s; });
  const MotionSegment& s = it == segments_.begin() ? segments_.front() : *(it - 1);
  const double dt = std::clamp(t - s.t0_s, 0.0, s.duration_s);
  const double j = s.jerk_m_s3;
  MotionState m;
  m.jerk_m_s3 = (t - s.t0_s <= s.duration_s) ? j : 0.0;
  m.a_m_s2 = s.a0_m_s2 + j * dt;
  m.v_m_s = s.v0_m_s + s.a0_m_s2 * dt + j * dt * dt / 2.0;
  if (m.v_m_s < 1e-12)  // rounding residue where the train comes to rest
    m.v_m_s = 0.0;
  m.u_m = s.u0_m + s.v0_m_s * dt + s.a0_m_s2 * dt * dt / 2.0 + j * dt * dt * dt / 6.0;
  return m;
}

MotionProfile planMotion(const Route& route, const std::vector<std::pair<double, double>>& stops,
                         const MotionLimits& limits, const TrainDynamics& dynamics, double u_start,
                         double u_end) {
  const VerticalProfile& vp = route.track.vertical();
  // Speed limit for the front bogie: a block's limit holds from its start until the rear has
  // left it, i.e. over [begin, end + train length] in u.
  std::vector<double> cuts{u_start, u_end};
  struct Span {
    double a, b, v;
  };
  std::vector<Span> spans;
  for (const Block& b : route.blocks) {
    const double a = vp.at(b.chainage_begin_m).distance_m;
    const double e = vp.at(b.chainage_end_m).distance_m + limits.train_length_m;
    spans.push_back({a, e, b.speed_limit_m_s});
    cuts.push_back(a);
    cuts.push_back(e);
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  SpeedLimit limit;
  for (double c : cuts) {
    double v = route.blocks.empty() ? 0.0 : std::numeric_limits<double>::infinity();
    for (const Span& s : spans) {
      if (s.a <= c && c < s.b)
        v = std::min(v, s.v);
    }
    if (!std::isfinite(v))
      v = route.blocks.back().speed_limit_m_s;
    if (!limit.limit_m_s.empty() && limit.limit_m_s.back() == v)
      continue;
    limit.u_begin_m.push_back(c);
    limit.limit_m_s.push_back(v);
  }

  // Sections between limit changes and stops.
  std::vector<std::pair<double, double>> stop_u;
  for (const auto& [s, dwell] : stops) {
    const double u = vp.at(s).distance_m;
    if (u > u_start + 1.0 && u < u_end - 1.0)
      stop_u.emplace_back(u, dwell);
  }
  std::sort(stop_u.begin(), stop_u.end());
  std::vector<double> bounds{u_start, u_end};
  for (double c : limit.u_begin_m)
    if (c > u_start && c < u_end)
      bounds.push_back(c);
  for (const auto& s : stop_u)
    bounds.push_back(s.first);
  std::sort(bounds.begin(), bounds.end());
  bounds.erase(std::unique(bounds.begin(), bounds.end()), bounds.end());
  std::vector<Section> sections;
  for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
    Section sec{bounds[i], bounds[i + 1], limit.at(0.5 * (bounds[i] + bounds[i + 1]))};
    for (const auto& [u, dwell] : stop_u)
      if (u == bounds[i + 1])
        sec.stop_dwell = dwell;
    sections.push_back(sec);
  }

  // Acceleration available in each section; sections the train cannot climb at their limit
  // get the highest speed it can still gain at 0.05 m/s² (its balancing speed, less a margin).
  std::vector<Change> accel(sections.size(), Change{limits.accel_m_s2, limits.jerk_m_s3});
  const Change brake{limits.brake_m_s2, limits.jerk_m_s3};
  if (dynamics.enabled) {
    for (std::size_t i = 0; i < sections.size(); ++i) {
      Section& sec = sections[i];
      const double climb = maxUphill(route, vp.chainageAt(sec.u0), vp.chainageAt(sec.u1));
      auto worst = [&](double vmax) {
        double a = limits.accel_m_s2;
        for (int k = 0; k <= 16; ++k)
          a = std::min(a, dynamics.availableAccel(vmax * k / 16.0, climb));
        return a;
      };
      // Sections where the train could gain less than 0.05 m/s² (or its configured limit, if
      // lower) run at the speed where it still can.
      const double floor = std::min(limits.accel_m_s2, 0.05);
      if (worst(sec.limit) < floor) {
        double lo = 0.0, hi = sec.limit;
        for (int k = 0; k < 60; ++k) {
          const double mid = 0.5 * (lo + hi);
          (worst(mid) >= floor ? lo : hi) = mid;
        }
        if (lo < 0.5)
          throw ConfigError(fmt::format(
              "train.dynamics: the train cannot start on the climb at chainage {:.0f} m; its "
              "traction is too weak for the grade",
              vp.chainageAt(sec.u0)));
        sec.limit = lo;
      }
      accel[i].accel = worst(sec.limit);
    }
  }

  // Boundary speeds: capped by both neighbours' limits and stops, then made reachable forward
  // (acceleration) and backward (braking).
  const std::size_t n = sections.size();
  std::vector<double> w(n + 1, 0.0);
  for (std::size_t b = 1; b < n; ++b)
    w[b] = sections[b - 1].stop_dwell >= 0.0 ? 0.0
                                             : std::min(sections[b - 1].limit, sections[b].limit);
  for (std::size_t i = 0; i < n; ++i)
    w[i + 1] = std::min(w[i + 1], reach(accel[i], w[i], sections[i].u1 - sections[i].u0, 1e9));
  for (std::size_t i = n; i-- > 0;)
    w[i] = std::min(w[i], reach(brake, w[i + 1], sections[i].u1 - sections[i].u0, 1e9));

  std::vector<MotionSegment> segments;
  for (std::size_t i = 0; i < n; ++i) {
    const Section& sec = sections[i];
    const double len = sec.u1 - sec.u0;
    auto need = [&](double top) {
      return accel[i].distance(w[i], top) + brake.distance(top, w[i + 1]);
    };
    double lo = std::max(w[i], w[i + 1]), hi = sec.limit;
    if (need(hi) <= len) {
      lo = hi;
    } else {
      for (int k = 0; k < 100; ++k) {
        const double mid = 0.5 * (lo + hi);
        (need(mid) <= len ? lo : hi) = mid;
      }
    }
    const double peak = lo;
    (peak >= w[i] ? accel[i] : brake).append(segments, w[i], peak);
    const double cruise = len - need(peak);
    if (peak > 0.0 && cruise > 0.0)
      segments.push_back({0, 0, 0, 0, 0.0, cruise / peak});
    (w[i + 1] >= peak ? accel[i] : brake).append(segments, peak, w[i + 1]);
    if (sec.stop_dwell > 0.0)
      segments.push_back({0, 0, 0, 0, 0.0, sec.stop_dwell});
  }
  std::erase_if(segments, [](const MotionSegment& s) { return s.duration_s <= 1e-12; });
  // Chain the segments: each starts where the previous ends.
  double t = 0.0, u = u_start, v = 0.0, a = 0.0;
  for (MotionSegment& s : segments) {
    s.t0_s = t;
    s.u0_m = u;
    s.v0_m_s = v;
    s.a0_m_s2 = a;
    const double dt = s.duration_s, j = s.jerk_m_s3;
    t += dt;
    u += v * dt + a * dt * dt / 2.0 + j * dt * dt * dt / 6.0;
    v += a * dt + j * dt * dt / 2.0;
    a += j * dt;
    if (std::abs(v) < 1e-9)
      v = 0.0;
    if (std::abs(a) < 1e-12)
      a = 0.0;
  }
  return MotionProfile(std::move(segments), std::move(limit));
}

}  // namespace trainsim::track
