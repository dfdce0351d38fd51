#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "trainsim/core/frames.hpp"
#include "trainsim/track/route.hpp"

namespace trainsim::track {
namespace {

constexpr double kNoCantBelow_m_s = 40.0 / 3.6;  // docs/REFERENCES.md R1.2 (Bane NOR)

double kmh(double v) {
  return v * 3.6;
}

}  // namespace

double DesignRules::equilibriumCant(double v, double radius_m) const {
  return kCantBase_m * v * v / (kStandardGravity_m_s2 * std::abs(radius_m));
}

double DesignRules::minRadius(double v) const {
  // Below 40 km/h curves get no cant (appliedCant), so only the deficiency is available.
  const double cant = v < kNoCantBelow_m_s ? 0.0 : max_cant_m;
  return kCantBase_m * v * v / (kStandardGravity_m_s2 * (cant + max_cant_deficiency_m));
}

double DesignRules::appliedCant(double v, double radius_m) const {
  if (v < kNoCantBelow_m_s)
    return 0.0;
  const double e = equilibriumCant(v, radius_m);
  const double wanted = std::max(e - max_cant_deficiency_m, 2.0 / 3.0 * e);
  const double rounded = std::ceil(wanted / 0.005 - 1e-9) * 0.005;
  return std::min(rounded, max_cant_m);
}

double DesignRules::curveSpeed(double radius_m, double cant_m) const {
  return std::sqrt((std::abs(cant_m) + max_cant_deficiency_m) * kStandardGravity_m_s2 *
                   std::abs(radius_m) / kCantBase_m);
}

double DesignRules::minTransitionLength(double v, double cant_change_m,
                                        double deficiency_change_m) const {
  return std::max({v * std::abs(cant_change_m) / max_cant_rate_m_s,
                   v * std::abs(deficiency_change_m) / max_deficiency_rate_m_s,
                   std::abs(cant_change_m) / max_cant_gradient});
}

double DesignRules::blockSpeed(BlockType type) const {
  switch (type) {
    case BlockType::kStation:
      return std::min(design_speed_m_s, station_speed_m_s);
    case BlockType::kTunnel:
      return std::min(design_speed_m_s, tunnel_speed_m_s);
    case BlockType::kBridge:
      return std::min(design_speed_m_s, bridge_speed_m_s);
    default:
      return design_speed_m_s;
  }
}

const Block& Route::blockAt(double s) const {
  const auto it = std::upper_bound(blocks.begin(), blocks.end(), s,
                                   [](double x, const Block& b) { return x < b.chainage_begin_m; });
  return it == blocks.begin() ? blocks.front() : *(it - 1);
}

double speedLimitAt(const Route& route, double s) {
  return route.blockAt(s).speed_limit_m_s;
}

namespace {

class Checker {
 public:
  Checker(const Route& route, const DesignRules& rules) : route_(route), rules_(rules) {}

  // The speed a stretch is designed for: the design speed, lowered by any station, tunnel or
  // bridge overlapping [a, b]. Curve speed limits are a consequence of the geometry, not a
  // design target, so they do not excuse a tight curve.
  double speedOver(double a, double b) const {
    double v = rules_.design_speed_m_s;
    for (const Block& blk : route_.blocks) {
      if (blk.chainage_end_m > a && blk.chainage_begin_m < b)
        v = std::min(v, rules_.blockSpeed(blk.type));
    }
    return v;
  }
  // Cant deficiency with the sign of the curve: equilibrium cant banked into the curve
  // (negative for left-hand curves, where the right rail is raised) minus the applied cant.
  double signedDeficiency(double v, double k, double d) const {
    if (k == 0.0)
      return -d;
    const double e = rules_.equilibriumCant(v, 1.0 / k);
    return (k > 0.0 ? -e : e) - d;
  }

  void add(std::string rule, double a, double b, double value, double limit, std::string unit,
           std::string message) {
    out_.push_back({std::move(rule), a, b, route_.blockAt(a).id, value, limit, std::move(unit),
                    std::move(message)});
  }

  void horizontal() {
    const HorizontalAlignment& h = route_.track.horizontal();
    const CantProfile& cant = route_.track.cant();
    for (std::size_t i = 0; i < h.elements().size(); ++i) {
      const HorizontalElement& e = h.elements()[i];
      const double a = h.elementStart(i), b = h.elementStart(i + 1);
      const double v = speedOver(a, b);
      if (i > 0) {
        const double k_prev = h.elements()[i - 1].curvature_end_1_m;
        if (std::abs(k_prev - e.curvature_start_1_m) > 1e-9)
          add("curvature_jump", a, a, std::abs(k_prev - e.curvature_start_1_m), 0.0, "1/m",
              fmt::format("curvature jumps from {:.6g} to {:.6g} 1/m without a transition", k_prev,
                          e.curvature_start_1_m));
      }
      if (i > 0 && e.type == HorizontalElement::Type::kTransition && e.curvature_start_1_m == 0.0) {
        const HorizontalElement& prev = h.elements()[i - 1];
        if (prev.type == HorizontalElement::Type::kTransition && prev.curvature_end_1_m == 0.0 &&
            prev.curvature_start_1_m * e.curvature_end_1_m < 0.0)
          add("reverse_curve_straight", a, a, 0.0, rules_.minElementLength(v), "m",
              "reverse curves meet without a straight between their transitions");
      }
      if (e.type != HorizontalElement::Type::kTransition && i > 0 && i + 1 < h.elements().size() &&
          e.length_m < rules_.minElementLength(v) - 1e-6)
        add("element_length", a, b, e.length_m, rules_.minElementLength(v), "m",
            fmt::format("{} of {:.1f} m is shorter than {:.1f} m ({:.1f} s at {:.0f} km/h)",
                        e.type == HorizontalElement::Type::kArc ? "arc" : "straight", e.length_m,
                        rules_.minElementLength(v), rules_.min_element_duration_s, kmh(v)));
      if (e.type == HorizontalElement::Type::kTransition) {
        const double d0 = cant.at(a).cant_m, d1 = cant.at(b).cant_m;
        // Signed deficiency, so that a transition from a left to a right curve counts the
        // whole swing.
        const double di = signedDeficiency(v, e.curvature_end_1_m, d1) -
                          signedDeficiency(v, e.curvature_start_1_m, d0);
        const double need = rules_.minTransitionLength(v, d1 - d0, di);
        if (e.length_m < need - 1e-6)
          add("transition_length", a, b, e.length_m, need, "m",
              fmt::format("transition of {:.1f} m is shorter than {:.1f} m needed for the cant "
                          "and deficiency change at {:.0f} km/h",
                          e.length_m, need, kmh(v)));
      }
    }
  }

  // Radius, cant and deficiency per curve block, at its sharpest point (the arc, or where
  // two transitions meet when there is no arc).
  void curves() {
    const HorizontalAlignment& h = route_.track.horizontal();
    const CantProfile& cant = route_.track.cant();
    for (const Block& blk : route_.blocks) {
      if (blk.type != BlockType::kCurve)
        continue;
      const double a = blk.chainage_begin_m, b = blk.chainage_end_m;
      double k = 0.0, at = a;
      for (std::size_t i = 0; i < h.elements().size(); ++i) {
        const double e0 = h.elementStart(i), e1 = h.elementStart(i + 1);
        if (e1 <= a || e0 >= b)
          continue;
        const HorizontalElement& e = h.elements()[i];
        for (const auto& [kk, ss] :
             {std::pair{e.curvature_start_1_m, e0}, std::pair{e.curvature_end_1_m, e1}}) {
          if (std::abs(kk) > std::abs(k)) {
            k = kk;
            at = e.type == HorizontalElement::Type::kArc ? 0.5 * (e0 + e1) : ss;
          }
        }
      }
      if (k == 0.0)
        continue;
      const double v = speedOver(a, b);
      const double r = 1.0 / std::abs(k);
      const double d = cant.at(at).cant_m;
      if (r < rules_.minRadius(v) - 1e-6)
        add("min_radius", a, b, r, rules_.minRadius(v), "m",
            fmt::format("curve radius {:.0f} m is below the minimum {:.0f} m for {:.0f} km/h; the "
                        "curve limits the speed to {:.0f} km/h",
                        r, rules_.minRadius(v), kmh(v), kmh(rules_.curveSpeed(r, d))));
      if (std::abs(d) > rules_.max_cant_m + 1e-9)
        add("max_cant", a, b, std::abs(d) * 1e3, rules_.max_cant_m * 1e3, "mm",
            fmt::format("applied cant {:.0f} mm exceeds {:.0f} mm", std::abs(d) * 1e3,
                        rules_.max_cant_m * 1e3));
      if (d * k > 0.0)
        add("cant_direction", a, b, d * 1e3, 0.0, "mm", "cant raises the inner rail");
      // Deficiency against the cant banked into the curve (a cant leaning the wrong way adds).
      const double deficiency = std::abs(signedDeficiency(v, k, d));
      if (deficiency > rules_.max_cant_deficiency_m + 1e-9)
        add("cant_deficiency", a, b, deficiency * 1e3, rules_.max_cant_deficiency_m * 1e3, "mm",
            fmt::format("cant deficiency {:.0f} mm at {:.0f} km/h exceeds {:.0f} mm",
                        deficiency * 1e3, kmh(v), rules_.max_cant_deficiency_m * 1e3));
    }
  }

  void vertical() {
    const VerticalProfile& p = route_.track.vertical();
    const double end = route_.track.length();
    for (std::size_t i = 0; i < p.elements().size(); ++i) {
      const VerticalElement& e = p.elements()[i];
      const double a = p.elementStart(i), b = std::min(end, p.elementStart(i + 1));
      if (a >= end)
        break;
      const double v = speedOver(a, b);
      const double s1 = e.sin_pitch_start + e.curvature_1_m * e.length_m;
      const double grade =
          std::tan(std::max(std::abs(std::asin(e.sin_pitch_start)), std::abs(std::asin(s1))));
      if (grade > rules_.max_grade + 1e-9)
        add("gradient", a, b, grade * 1e3, rules_.max_grade * 1e3, "permille",
            fmt::format("gradient {:.2f} permille exceeds {:.2f} permille", grade * 1e3,
                        rules_.max_grade * 1e3));
      if (e.curvature_1_m != 0.0) {
        const double rv = 1.0 / std::abs(e.curvature_1_m);
        if (rv < rules_.minVerticalRadius(v) - 1e-6)
          add("vertical_radius", a, b, rv, rules_.minVerticalRadius(v), "m",
              fmt::format("vertical curve radius {:.0f} m is below {:.0f} m for {:.0f} km/h", rv,
                          rules_.minVerticalRadius(v), kmh(v)));
      }
    }
  }

  void stations() {
    const CantProfile& cant = route_.track.cant();
    for (const Block& blk : route_.blocks) {
      if (blk.type != BlockType::kStation)
        continue;
      double worst = 0.0;
      for (std::size_t i = 0; i < cant.elements().size(); ++i) {
        const double a = cant.elementStart(i), b = cant.elementStart(i + 1);
        if (b > blk.chainage_begin_m && a < blk.chainage_end_m)
          worst = std::max({worst, std::abs(cant.elements()[i].cant_start_m),
                            std::abs(cant.elements()[i].cant_end_m)});
      }
      // Steepest grade along the platform: sin θ is monotonic on each vertical element, so
      // the extremes are at the ends of its overlap with the station.
      const VerticalProfile& p = route_.track.vertical();
      for (std::size_t i = 0; i < p.elements().size(); ++i) {
        const double a = std::max(p.elementStart(i), blk.chainage_begin_m);
        const double b = std::min(p.elementStart(i + 1), blk.chainage_end_m);
        if (b <= a)
          continue;
        const double grade =
            std::tan(std::max(std::abs(p.at(a).pitch_rad), std::abs(p.at(b).pitch_rad)));
        if (grade > rules_.station_max_grade + 1e-9)
          add("station_gradient", a, b, grade * 1e3, rules_.station_max_grade * 1e3, "permille",
              fmt::format("gradient {:.2f} permille at a platform exceeds {:.2f} permille",
                          grade * 1e3, rules_.station_max_grade * 1e3));
      }
      if (worst > rules_.station_max_cant_m + 1e-9)
        add("station_cant", blk.chainage_begin_m, blk.chainage_end_m, worst * 1e3,
            rules_.station_max_cant_m * 1e3, "mm",
            fmt::format("cant {:.0f} mm at a platform exceeds {:.0f} mm", worst * 1e3,
                        rules_.station_max_cant_m * 1e3));
    }
  }

  std::vector<Violation> result() {
    std::stable_sort(out_.begin(), out_.end(), [](const Violation& x, const Violation& y) {
      return x.chainage_begin_m < y.chainage_begin_m;
    });
    return std::move(out_);
  }

 private:
  const Route& route_;
  const DesignRules& rules_;
  std::vector<Violation> out_;
};

}  // namespace

std::vector<Violation> checkDesign(const Route& route, const DesignRules& rules) {
  Checker checker(route, rules);
  checker.horizontal();
  checker.curves();
  checker.vertical();
  checker.stations();
  return checker.result();
}

}  // namespace trainsim::track
