#include "trainsim/evaluation/odometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"

namespace trainsim::evaluation {
namespace {

// Largest |RᵀR − I| entry accepted as a rotation: a pose printed with six significant digits
// (KITTI's ground truth) is off by about 1e-6.
constexpr double kOrthonormalTolerance = 1e-3;

// Larger inputs are refused rather than read: a poses file of a 1000 km run at 10 Hz is about
// 50 MB, and a device or a wrong path (/dev/zero) would otherwise fill the memory.
constexpr std::size_t kMaxInputBytes = std::size_t{1} << 30;

// The whole file, read in blocks up to kMaxInputBytes; a leading UTF-8 byte order mark dropped.
std::string readInput(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path))
    throw ConfigError(fmt::format("{}: is a folder, not a file", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ConfigError(fmt::format("{}: {}", path.string(), std::strerror(errno)));
  std::string text;
  std::array<char, 1 << 16> block{};
  while (in.read(block.data(), block.size()) || in.gcount() > 0) {
    text.append(block.data(), static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxInputBytes)
      throw ConfigError(fmt::format("{}: larger than {} MiB, not a poses or calib file",
                                    path.string(), kMaxInputBytes >> 20));
  }
  if (text.starts_with("\xEF\xBB\xBF"))
    text.erase(0, 3);
  return text;
}

// The lines of `text` as views (without their line ends), numbered from 1.
template <typename Visit>
void forEachLine(std::string_view text, const Visit& visit) {
  std::size_t number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    visit(++number, text.substr(0, end));
    if (end == std::string_view::npos)
      break;
    text.remove_prefix(end + 1);
  }
}

bool isBlank(std::string_view line) {
  return std::all_of(line.begin(), line.end(),
                     [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
}

// The whitespace-separated numbers of `line`; nullopt at the first token that is not a finite
// number (its text in `bad`).
std::optional<std::vector<double>> numbersOf(std::string_view line, std::string& bad) {
  std::vector<double> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i])))
      ++i;
    if (i == line.size())
      break;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j])))
      ++j;
    const std::string_view token = line.substr(i, j - i);
    double value = 0.0;
    const char* begin = token.data();
    if (token.starts_with('+') && token.size() > 1 && token[1] != '-' && token[1] != '+')
      ++begin;
    const auto [end, ec] = std::from_chars(begin, token.data() + token.size(), value);
    if (ec != std::errc() || end != token.data() + token.size() || !std::isfinite(value)) {
      bad = std::string(token);
      return std::nullopt;
    }
    out.push_back(value);
    i = j;
  }
  return out;
}

// The pose of 12 numbers (a 3 × 4 matrix row by row), or the reason it is none.
std::optional<Pose> poseOf(const std::vector<double>& v, std::string& why) {
  if (v.size() != 12) {
    why = fmt::format("{} numbers where a pose has 12 (a 3 × 4 matrix, row by row)", v.size());
    return std::nullopt;
  }
  Pose T = Pose::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      T.matrix()(r, c) = v[static_cast<std::size_t>(4 * r + c)];
  const Eigen::Matrix3d R = T.linear();
  const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (off > kOrthonormalTolerance || R.determinant() <= 0.0) {
    why = fmt::format("the left 3 × 3 block is not a rotation (|RᵀR − I| = {:.2g}, det = {:.4g})",
                      off, R.determinant());
    return std::nullopt;
  }
  return T;
}

// The angle of a rotation matrix: atan2 of its sine and cosine. The devkit's acos((trace − 1)
// / 2) alone is ill-conditioned for the small angles odometry errors are: an error ε in the
// trace (the digits a poses file keeps) moves it by ε / sin θ, 5e-6 of a 1.5 mrad angle from
// poses printed to 13 digits (cli_commands.sh).
double angleOf(const Eigen::Matrix3d& R) {
  const Eigen::Vector3d s(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  return std::atan2(0.5 * s.norm(), 0.5 * (R.trace() - 1.0));
}

// The ground truth's path length up to each frame.
std::vector<double> pathLengths(const Poses& poses) {
  std::vector<double> d(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i)
    d[i] = d[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  return d;
}

}  // namespace

namespace {

// The rows of a file of one record a line (poses.txt, times.txt): each line's numbers with its
// number, to `visit`. Blank lines may end the file, not come between rows; a token that is not
// a finite number is refused with the file and line named, and so is a file with no row.
template <typename Visit>
void forEachRow(const std::filesystem::path& path, std::string_view rows, const Visit& visit) {
  const std::string text = readInput(path);
  std::size_t blank = 0, count = 0;
  forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    if (isBlank(line)) {
      blank = blank == 0 ? line_number : blank;
      return;
    }
    if (blank != 0)
      throw ConfigError(fmt::format("{}:{}: empty line among the {} (one line per frame)",
                                    path.string(), blank, rows));
    std::string bad;
    const auto numbers = numbersOf(line, bad);
    if (!numbers)
      throw ConfigError(fmt::format("{}:{}: '{}' is not a finite number a double holds",
                                    path.string(), line_number, messageValue(bad)));
    visit(line_number, *numbers);
    ++count;
  });
  if (count == 0)
    throw ConfigError(fmt::format("{}: no {} in the file", path.string(), rows));
}

}  // namespace

Poses readKittiPoses(const std::filesystem::path& path) {
  Poses poses;
  forEachRow(path, "poses", [&](std::size_t line_number, const std::vector<double>& numbers) {
    std::string why;
    const auto pose = poseOf(numbers, why);
    if (!pose)
      throw ConfigError(fmt::format("{}:{}: {}", path.string(), line_number, why));
    poses.push_back(*pose);
  });
  return poses;
}

std::vector<double> readKittiTimes(const std::filesystem::path& path) {
  std::vector<double> times;
  forEachRow(path, "times", [&](std::size_t line_number, const std::vector<double>& numbers) {
    if (numbers.size() != 1)
      throw ConfigError(fmt::format("{}:{}: {} numbers where a time has one (seconds)",
                                    path.string(), line_number, numbers.size()));
    if (!times.empty() && !(numbers.front() > times.back()))
      throw ConfigError(fmt::format("{}:{}: {} s does not come after the line before's {} s",
                                    path.string(), line_number, numbers.front(), times.back()));
    times.push_back(numbers.front());
  });
  return times;
}

Pose readKittiTr(const std::filesystem::path& calib) {
  const std::string text = readInput(calib);
  std::optional<Pose> tr;
  forEachLine(text, [&](std::size_t line_number, std::string_view line) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (tr || start == std::string_view::npos || !line.substr(start).starts_with("Tr:"))
      return;
    std::string bad, why;
    const auto numbers = numbersOf(line.substr(start + 3), bad);
    if (!numbers)
      throw ConfigError(fmt::format("{}:{}: Tr: '{}' is not a finite number a double holds",
                                    calib.string(), line_number, messageValue(bad)));
    tr = poseOf(*numbers, why);
    if (!tr)
      throw ConfigError(fmt::format("{}:{}: Tr: {}", calib.string(), line_number, why));
  });
  if (!tr)
    throw ConfigError(
        fmt::format("{}: no 'Tr:' line (velodyne → camera 0); a dataset with a LiDAR writes one",
                    calib.string()));
  return *tr;
}

Poses vehicleAxes(const Poses& camera_poses, const Pose* tr) {
  // T_cam_vehicle: Tr itself, or the rotation from vehicle axes into KITTI's camera axes.
  Pose to_camera = Pose::Identity();
  if (tr != nullptr)
    to_camera = *tr;
  else
    to_camera.linear() = rotationBodyFromKittiCamera().transpose();
  const Pose from_camera = to_camera.inverse();
  const Pose first = camera_poses.front().inverse();
  Poses out;
  out.reserve(camera_poses.size());
  for (const Pose& C : camera_poses)
    out.push_back(from_camera * first * C * to_camera);
  return out;
}

std::vector<Segment> kittiSegments(const Poses& gt, const Poses& est,
                                   std::span<const double> lengths_m, std::size_t step,
                                   std::span<const double> times) {
  if (gt.size() != est.size() || (!times.empty() && times.size() != gt.size()))
    throw ConfigError("kittiSegments: the two trajectories (or the times) differ in length");
  const std::vector<double> dist = pathLengths(gt);
  std::vector<Segment> out;
  for (std::size_t first = 0; first < gt.size(); first += std::max<std::size_t>(step, 1))
    for (const double length : lengths_m) {
      // The devkit's last frame: the first whose path length exceeds the first's by more than
      // the segment length.
      const auto it = std::upper_bound(dist.begin() + static_cast<std::ptrdiff_t>(first),
                                       dist.end(), dist[first] + length);
      if (it == dist.end())
        continue;
      const auto last = static_cast<std::size_t>(it - dist.begin());
      const Pose delta_gt = gt[first].inverse() * gt[last];
      const Pose delta_est = est[first].inverse() * est[last];
      const Pose error = delta_est.inverse() * delta_gt;
      out.push_back(
          {first, last, length, error.translation().norm() / length,
           angleOf(error.linear()) / length,
           times.empty() ? 0.0 : (dist[last] - dist[first]) / (times[last] - times[first])});
    }
  return out;
}

Stats statsOf(std::span<const double> values) {
  Stats s;
  s.count = values.size();
  if (values.empty())
    return s;
  double sum = 0.0;
  for (const double v : values) {
    sum += v;
    s.max = std::max(s.max, v);
  }
  s.mean = sum / static_cast<double>(values.size());
  double squares = 0.0;
  for (const double v : values)
    squares += (v - s.mean) * (v - s.mean);
  s.stddev = std::sqrt(squares / static_cast<double>(values.size()));
  return s;
}

FrameErrors frameErrors(const Poses& gt, const Poses& est, double eod_from_m) {
  if (gt.size() != est.size())
    throw ConfigError("frameErrors: the two trajectories differ in length");
  FrameErrors out;
  for (std::size_t k = 0; k + 1 < gt.size(); ++k) {
    const Eigen::Vector3d step_gt = (gt[k].inverse() * gt[k + 1]).translation();
    const Eigen::Vector3d step_est = (est[k].inverse() * est[k + 1]).translation();
    out.tex_m.push_back(std::abs(step_est.x() - step_gt.x()));
    out.tey_m.push_back(std::abs(step_est.y() - step_gt.y()));
  }
  const std::vector<double> dist = pathLengths(gt);
  const Pose gt0 = gt.front().inverse(), est0 = est.front().inverse();
  for (std::size_t k = 1; k < gt.size(); ++k) {
    if (!(dist[k] >= eod_from_m) || dist[k] <= 0.0)
      continue;
    const Eigen::Vector3d e = (est0 * est[k]).translation() - (gt0 * gt[k]).translation();
    out.eod_percent.push_back(100.0 * e.head<2>().norm() / dist[k]);
  }
  return out;
}

Report evaluate(const Poses& gt, const Poses& est, const EvaluateOptions& options) {
  if (gt.size() != est.size())
    throw ConfigError(fmt::format(
        "--est holds {} poses and --gt {}: both need one line per frame of the sequence",
        est.size(), gt.size()));
  if (gt.size() < 2)
    throw ConfigError("--gt: a sequence needs at least two poses");
  if (options.step < 1)
    throw ConfigError("--step: must be at least 1 frame");
  if (!(options.eod_from_m >= 0.0))
    throw ConfigError("--eod-from: must be a distance of 0 m or more");
  if (!options.times.empty() && options.times.size() != gt.size())
    throw ConfigError(fmt::format("--times holds {} times and --gt {} poses: one line per frame",
                                  options.times.size(), gt.size()));
  if (!(options.speed_bin_m_s > 0.0) || !std::isfinite(options.speed_bin_m_s))
    throw ConfigError("--speed-bin: must be a positive speed (m/s)");
  if (options.lengths_m.empty())
    throw ConfigError("--lengths: at least one segment length");
  for (std::size_t i = 0; i < options.lengths_m.size(); ++i) {
    const double length = options.lengths_m[i];
    if (!(length > 0.0) || !std::isfinite(length))
      throw ConfigError(fmt::format("--lengths: {} is not a positive length", length));
    if (std::find(options.lengths_m.begin(),
                  options.lengths_m.begin() + static_cast<std::ptrdiff_t>(i),
                  length) != options.lengths_m.begin() + static_cast<std::ptrdiff_t>(i))
      throw ConfigError(fmt::format(
          "--lengths: {:g} m is given twice (its segments would count twice in 'all')", length));
  }

  Report report;
  report.frames = gt.size();
  report.path_m = pathLengths(gt).back();
  report.step = options.step;
  report.eod_from_m = options.eod_from_m;
  report.velodyne_axes = options.tr != nullptr;
  const std::vector<Segment> segments =
      kittiSegments(gt, est, options.lengths_m, options.step, options.times);
  // Every segment `take` takes, averaged as the devkit does (per segment, not per metre).
  const auto summarise = [&](double length, const auto& take) {
    Report::Length l;
    l.length_m = length;
    double t = 0.0, r = 0.0;
    for (const Segment& s : segments)
      if (take(s)) {
        t += s.translation;
        r += s.rotation_rad;
        ++l.segments;
      }
    if (l.segments > 0) {
      l.translation_percent = 100.0 * t / static_cast<double>(l.segments);
      l.rotation_deg_per_m = r / static_cast<double>(l.segments) / kRadPerDeg;
    }
    return l;
  };
  for (const double length : options.lengths_m)
    report.lengths.push_back(
        summarise(length, [&](const Segment& s) { return s.length_m == length; }));
  report.all = summarise(0.0, [](const Segment&) { return true; });
  if (!options.times.empty()) {
    report.speed_bin_m_s = options.speed_bin_m_s;
    // A speed on a bin's edge but for the rounding of the times' digits (10 m/s from frames
    // 0.1 s apart) counts in the bin above the edge, as its true value does.
    const auto binOf = [&](const Segment& s) {
      return static_cast<std::size_t>(std::floor(s.speed_m_s / options.speed_bin_m_s + 1e-9));
    };
    std::size_t bins = 0;
    for (const Segment& s : segments)
      bins = std::max(bins, binOf(s) + 1);
    for (std::size_t b = 0; b < bins; ++b) {
      const double from = static_cast<double>(b) * options.speed_bin_m_s;
      const double to = from + options.speed_bin_m_s;
      const Report::Length errors = summarise(0.0, [&](const Segment& s) { return binOf(s) == b; });
      if (errors.segments > 0)
        report.speeds.push_back({from, to, errors});
    }
  }

  const FrameErrors frame =
      frameErrors(vehicleAxes(gt, options.tr), vehicleAxes(est, options.tr), options.eod_from_m);
  report.tex_m = statsOf(frame.tex_m);
  report.tey_m = statsOf(frame.tey_m);
  report.eod_percent = statsOf(frame.eod_percent);
  return report;
}

std::string markdown(const Report& r) {
  std::string out = fmt::format(
      "{} frames, {:.1f} m of ground-truth path\n\n"
      "KITTI odometry segment errors (the devkit's method: segments start every {} frames, "
      "lengths along the ground truth's path)\n\n"
      "| segment length (m) | segments | translation (%) | rotation (deg/100 m) |\n"
      "|---|---|---|---|\n",
      r.frames, r.path_m, r.step);
  const auto row = [](const std::string& name, const Report::Length& l) {
    if (l.segments == 0)
      return fmt::format("| {} | 0 | – | – |\n", name);
    return fmt::format("| {} | {} | {:.4f} | {:.4f} |\n", name, l.segments, l.translation_percent,
                       100.0 * l.rotation_deg_per_m);
  };
  bool few = false;
  for (const Report::Length& l : r.lengths) {
    out += row(fmt::format("{:g}", l.length_m), l);
    few = few || (l.segments > 0 && l.segments < 3);
  }
  out += row("all", r.all);
  if (few)
    out +=
        "\nLengths with fewer than 3 segments are left out of the devkit's plots (not of its "
        "summary, the row 'all').\n";
  if (r.speed_bin_m_s > 0.0) {
    out += fmt::format(
        "\nThe same segments by speed (the ground truth's path over its time in times.txt; "
        "bins of {:g} m/s)\n\n"
        "| speed (m/s) | speed (km/h) | segments | translation (%) | rotation (deg/100 m) |\n"
        "|---|---|---|---|---|\n",
        r.speed_bin_m_s);
    for (const Report::Speed& s : r.speeds)
      out += fmt::format("| {:g}–{:g} | {:.0f}–{:.0f} | {} | {:.4f} | {:.4f} |\n", s.from_m_s,
                         s.to_m_s, 3.6 * s.from_m_s, 3.6 * s.to_m_s, s.errors.segments,
                         s.errors.translation_percent, 100.0 * s.errors.rotation_deg_per_m);
    if (r.speeds.empty())
      out += "| – | – | 0 | – | – |\n";
  }
  out += fmt::format(
      "\nFrame-to-frame translation errors TEX and TEY and error over distance EOD (the TrainSim "
      "paper's metrics, x forward and y left: {}; EOD from {:g} m of path)\n\n"
      "| metric | frames | mean | standard deviation | max |\n"
      "|---|---|---|---|---|\n",
      r.velodyne_axes
          ? "the velodyne's axes (calib.txt's Tr)"
          : "camera 0's axes renamed, its offset and tilt on the vehicle not taken out (--calib "
            "gives the velodyne's)",
      r.eod_from_m);
  const auto stats = [](const std::string& name, const Stats& s) {
    if (s.count == 0)
      return fmt::format("| {} | 0 | – | – | – |\n", name);
    return fmt::format("| {} | {} | {:.4f} | {:.4f} | {:.4f} |\n", name, s.count, s.mean, s.stddev,
                       s.max);
  };
  out += stats("TEX (m)", r.tex_m);
  out += stats("TEY (m)", r.tey_m);
  out += stats("EOD (%)", r.eod_percent);
  return out;
}

std::string json(const Report& r) {
  // Figures over no segment or frame are null, not 0 (which would read as no error).
  const auto value = [](std::size_t count, double v) {
    return count == 0 ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(v);
  };
  const auto length = [&](const Report::Length& l) {
    nlohmann::ordered_json j;
    if (l.length_m > 0.0)
      j["length_m"] = l.length_m;
    j["segments"] = l.segments;
    j["translation_percent"] = value(l.segments, l.translation_percent);
    // The benchmark site's unit (the devkit's stats.txt has rad/m), and per 100 m.
    j["rotation_deg_per_m"] = value(l.segments, l.rotation_deg_per_m);
    j["rotation_deg_per_100m"] = value(l.segments, 100.0 * l.rotation_deg_per_m);
    return j;
  };
  const auto stats = [&](const Stats& s) {
    return nlohmann::ordered_json{{"frames", s.count},
                                  {"mean", value(s.count, s.mean)},
                                  {"stddev", value(s.count, s.stddev)},
                                  {"max", value(s.count, s.max)}};
  };
  nlohmann::ordered_json j;
  j["frames"] = r.frames;
  j["path_m"] = r.path_m;
  j["kitti"]["step_frames"] = r.step;
  j["kitti"]["lengths"] = nlohmann::ordered_json::array();
  for (const Report::Length& l : r.lengths)
    j["kitti"]["lengths"].push_back(length(l));
  j["kitti"]["all"] = length(r.all);
  if (r.speed_bin_m_s > 0.0) {
    j["kitti"]["speed_bin_m_s"] = r.speed_bin_m_s;
    j["kitti"]["speeds"] = nlohmann::ordered_json::array();
    for (const Report::Speed& s : r.speeds) {
      nlohmann::ordered_json bin{{"from_m_s", s.from_m_s}, {"to_m_s", s.to_m_s}};
      bin.update(length(s.errors));
      j["kitti"]["speeds"].push_back(std::move(bin));
    }
  }
  j["paper"]["axes"] = r.velodyne_axes ? "velodyne" : "camera";
  j["paper"]["tex_m"] = stats(r.tex_m);
  j["paper"]["tey_m"] = stats(r.tey_m);
  j["paper"]["eod_from_m"] = r.eod_from_m;
  j["paper"]["eod_percent"] = stats(r.eod_percent);
  return j.dump(2) + "\n";
}

}  // namespace trainsim::evaluation
