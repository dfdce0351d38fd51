#include "trainsim/lidar/scan_pattern.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>

#include "trainsim/core/error.hpp"

namespace trainsim {
namespace embedded {
extern const std::string_view lidars_json;
}  // namespace embedded

namespace lidar {
namespace {

const std::vector<ScanPattern>& presets() {
  static const std::vector<ScanPattern> table = [] {
    std::vector<ScanPattern> out;
    const auto doc = nlohmann::json::parse(embedded::lidars_json);
    for (const auto& p : doc.at("presets")) {
      ScanPattern s;
      s.name = p.at("name").get<std::string>();
      s.rotation_hz = p.at("rotation_hz").get<double>();
      s.range_min_m = p.at("range_min_m").get<double>();
      s.range_max_m = p.at("range_max_m").get<double>();
      s.range_sigma_m = p.at("range_sigma_m").get<double>();
      s.firing_period_s = p.at("firing_period_us").get<double>() * 1e-6;
      s.shortest_column_s =
          p.value("shortest_column_us", p.at("firing_period_us").get<double>()) * 1e-6;
      if (p.contains("rotation_hz_range")) {
        s.rotation_hz_min = p.at("rotation_hz_range").at(0).get<double>();
        s.rotation_hz_max = p.at("rotation_hz_range").at(1).get<double>();
      }
      for (const auto& m : p.value("modes", nlohmann::json::array()))
        s.modes.emplace_back(m.at(0).get<int>(), m.at(1).get<double>());
      for (const auto& l : p.at("lasers"))
        s.lasers.push_back(
            {l.at(0).get<double>(), l.at(1).get<double>(), l.at(2).get<double>() * 1e-6, 0});
      // Beam origins, by laser id (a Velodyne calibration's) or for every beam (an Ouster's).
      const auto offsets = [&](const char* key, double Laser::*field) {
        if (!p.contains(key))
          return;
        if (p.at(key).size() != s.lasers.size())
          throw RuntimeError(fmt::format("lidars.json: {}'s {} has {} values for {} lasers", s.name,
                                         key, p.at(key).size(), s.lasers.size()));
        for (std::size_t l = 0; l < s.lasers.size(); ++l)
          s.lasers[l].*field = p.at(key).at(l).get<double>();
      };
      offsets("vertical_offsets_m", &Laser::vertical_offset_m);
      offsets("horizontal_offsets_m", &Laser::horizontal_offset_m);
      s.beam_origin_radius_m = p.value("beam_origin_radius_m", 0.0);
      s.beam_origin_height_m = p.value("beam_origin_height_m", 0.0);
      s.assignRings();
      out.push_back(std::move(s));
    }
    return out;
  }();
  return table;
}

}  // namespace

double ScanPattern::azimuthDeg(int column, int laser) const {
  const Laser& l = lasers[static_cast<std::size_t>(laser)];
  return 180.0 -
         360.0 * (static_cast<double>(first_column + column) / revolutionColumns() +
                  rotation_hz * l.time_offset_s) +
         l.azimuth_offset_deg;
}

bool ScanPattern::offsetBeams() const {
  return beam_origin_radius_m != 0.0 || beam_origin_height_m != 0.0 ||
         std::any_of(lasers.begin(), lasers.end(), [](const Laser& l) {
           return l.vertical_offset_m != 0.0 || l.horizontal_offset_m != 0.0;
         });
}

std::vector<int> ScanPattern::ringLasers() const {
  std::vector<int> out(lasers.size());
  for (std::size_t l = 0; l < lasers.size(); ++l)
    out[static_cast<std::size_t>(lasers[l].ring)] = static_cast<int>(l);
  return out;
}

void ScanPattern::assignRings() {
  std::vector<int> order(lasers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return lasers[static_cast<std::size_t>(a)].elevation_deg >
           lasers[static_cast<std::size_t>(b)].elevation_deg;
  });
  for (std::size_t r = 0; r < order.size(); ++r)
    lasers[static_cast<std::size_t>(order[r])].ring = static_cast<int>(r);
}

std::vector<std::string> presetNames() {
  std::vector<std::string> out;
  for (const ScanPattern& p : presets())
    out.push_back(p.name);
  return out;
}

ScanPattern preset(std::string_view name, double rotation_hz, int columns) {
  for (const ScanPattern& p : presets()) {
    if (p.name != name)
      continue;
    ScanPattern s = p;
    if (rotation_hz > 0.0)
      s.rotation_hz = rotation_hz;
    s.columns = columns > 0 ? columns
                            : static_cast<int>(std::floor(
                                  1.0 / (s.firing_period_s * s.rotation_hz) * (1.0 + 1e-9)));
    return s;
  }
  throw ConfigError(
      fmt::format("unknown LiDAR preset '{}' (known: {})", name, fmt::join(presetNames(), ", ")));
}

ScanPattern windowed(ScanPattern pattern, double fov_deg) {
  if (fov_deg >= 360.0)
    return pattern;
  // Revolution column k looks at 180° − 360° k / N: within ±fov / 2 for
  // N (180 − fov / 2) / 360 ≤ k ≤ N (180 + fov / 2) / 360.
  const int n = pattern.revolutionColumns();
  const double half = 0.5 * std::max(fov_deg, 0.0) / 360.0;
  const auto first = static_cast<int>(std::ceil(n * (0.5 - half) - 1e-9));
  const auto last = static_cast<int>(std::floor(n * (0.5 + half) + 1e-9));
  pattern.revolution_columns = n;
  pattern.first_column = first;
  pattern.columns = std::max(0, last - first + 1);
  return pattern;
}

ScanPattern uniformPattern(int channels, double fov_up_deg, double fov_down_deg, int columns,
                           double rotation_hz) {
  ScanPattern s;
  s.name = "uniform";
  s.columns = columns;
  s.rotation_hz = rotation_hz;
  for (int l = 0; l < channels; ++l) {
    const double f = channels > 1 ? static_cast<double>(l) / (channels - 1) : 0.0;
    s.lasers.push_back({fov_up_deg + f * (fov_down_deg - fov_up_deg), 0.0, 0.0, l});
  }
  return s;
}

}  // namespace lidar
}  // namespace trainsim
