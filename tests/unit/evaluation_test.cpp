// Odometry metrics (trainsim evaluate) against closed forms: trajectories built in the test
// whose segment errors, TEX, TEY and EOD follow from their construction.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include <nlohmann/json.hpp>

#include "trainsim/core/error.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/evaluation/odometry.hpp"

namespace trainsim::evaluation {
namespace {

constexpr std::size_t kFrames = 1000;  // 1 m apart: path lengths are whole metres

// KITTI camera poses of a camera driving 1 m a frame straight ahead (camera z).
Poses straight() {
  Poses p;
  for (std::size_t k = 0; k < kFrames; ++k) {
    Pose T = Pose::Identity();
    T.translation() = Eigen::Vector3d(0.0, 0.0, static_cast<double>(k));
    p.push_back(T);
  }
  return p;
}

// The devkit's segment of `length` m from `first` ends at the first frame more than `length`
// along: here first + length + 1, so the sequence holds this many segments of that length.
std::size_t segmentsOf(double length) {
  const auto span = static_cast<std::size_t>(length) + 1;
  return (kFrames - 1 - span) / 10 + 1;
}

TEST(Odometry, IdenticalTrajectoriesHaveNoError) {
  const Poses gt = straight();
  const Report r = evaluate(gt, gt);
  EXPECT_EQ(r.frames, kFrames);
  EXPECT_DOUBLE_EQ(r.path_m, static_cast<double>(kFrames - 1));
  ASSERT_EQ(r.lengths.size(), 8u);
  for (const Report::Length& l : r.lengths) {
    EXPECT_EQ(l.segments, segmentsOf(l.length_m)) << l.length_m;
    EXPECT_EQ(l.translation_percent, 0.0);
    EXPECT_EQ(l.rotation_deg_per_m, 0.0);
  }
  EXPECT_EQ(r.tex_m.max, 0.0);
  EXPECT_EQ(r.tey_m.max, 0.0);
  EXPECT_EQ(r.eod_percent.max, 0.0);
  EXPECT_EQ(r.tex_m.count, kFrames - 1);
  EXPECT_EQ(r.eod_percent.count, kFrames - 10);  // frames 10 m along and more
}

// An estimate whose every step is (1 + s) × the true one: each segment's translation error is
// s × its true length, which is length + 1 m here; EOD is 100 s % everywhere, TEX s, TEY 0.
TEST(Odometry, AScaleErrorGivesItsShareOfEverySegment) {
  const double s = 0.013;
  const Poses gt = straight();
  Poses est = gt;
  for (Pose& T : est)
    T.translation() *= 1.0 + s;
  const Report r = evaluate(gt, est);
  double sum = 0.0;
  std::size_t count = 0;
  for (const Report::Length& l : r.lengths) {
    const double expected = 100.0 * s * (l.length_m + 1.0) / l.length_m;
    EXPECT_NEAR(l.translation_percent, expected, 1e-12 * expected) << l.length_m;
    EXPECT_EQ(l.rotation_deg_per_m, 0.0);
    sum += expected * static_cast<double>(segmentsOf(l.length_m));
    count += segmentsOf(l.length_m);
  }
  EXPECT_EQ(r.all.segments, count);
  EXPECT_NEAR(r.all.translation_percent, sum / static_cast<double>(count), 1e-12);
  EXPECT_NEAR(r.tex_m.mean, s, 1e-12);
  EXPECT_NEAR(r.tex_m.stddev, 0.0, 1e-12);
  EXPECT_EQ(r.tey_m.max, 0.0);
  EXPECT_NEAR(r.eod_percent.mean, 100.0 * s, 1e-10);
  EXPECT_NEAR(r.eod_percent.max, 100.0 * s, 1e-10);
  EXPECT_NEAR(r.eod_percent.stddev, 0.0, 1e-10);
}

// An estimate that yaws ε more each frame but puts every frame at its true position. A segment
// of n frames starting at frame f: its error turns by n ε, and its translation is the true one
// seen turned by f ε, off by 2 n sin(f ε / 2). Step k is seen turned by k ε: TEX = 1 − cos k ε
// (forward), TEY = sin k ε (left).
TEST(Odometry, AYawDriftGivesTheRotationAndTheLeverOfEverySegment) {
  const double eps = 2e-5;
  const Poses gt = straight();
  Poses est = gt;
  for (std::size_t k = 0; k < kFrames; ++k)  // camera y points down: yaw is about it
    est[k].linear() = Eigen::AngleAxisd(static_cast<double>(k) * eps, Eigen::Vector3d::UnitY())
                          .toRotationMatrix();
  const std::vector<double> lengths = {100.0, 400.0};
  const std::vector<Segment> segments = kittiSegments(gt, est, lengths, 10);
  ASSERT_EQ(segments.size(), segmentsOf(100.0) + segmentsOf(400.0));
  for (const Segment& seg : segments) {
    const auto n = static_cast<double>(seg.last - seg.first);
    ASSERT_EQ(seg.last - seg.first, static_cast<std::size_t>(seg.length_m) + 1);
    EXPECT_NEAR(seg.rotation_rad, n * eps / seg.length_m, 1e-14) << seg.first;
    const double lever = 2.0 * n * std::sin(static_cast<double>(seg.first) * eps / 2.0);
    EXPECT_NEAR(seg.translation, lever / seg.length_m, 1e-13) << seg.first;
  }
  const FrameErrors f = frameErrors(vehicleAxes(gt), vehicleAxes(est));
  ASSERT_EQ(f.tex_m.size(), kFrames - 1);
  for (std::size_t k = 0; k + 1 < kFrames; ++k) {
    const double a = static_cast<double>(k) * eps;
    EXPECT_NEAR(f.tex_m[k], 1.0 - std::cos(a), 1e-12) << k;  // ulps of 1 km
    EXPECT_NEAR(f.tey_m[k], std::sin(a), 1e-12) << k;
  }
  for (const double e : f.eod_percent)
    EXPECT_NEAR(e, 0.0, 1e-10);  // every frame where it should be
}

// Velodyne poses running 1 m a frame forward, the estimate drifting δ a frame to the left,
// turned into camera-0 poses through a Tr with a lever arm and a tilt: with the Tr, TEX, TEY
// and EOD come back in the velodyne's axes exactly (TEX 0, TEY δ, EOD 100 δ %); without it
// they are those of the tilted camera.
TEST(Odometry, CalibTrGivesTheVelodynesAxes) {
  const double delta = 0.004;
  Pose tr = Pose::Identity();
  tr.linear() = rotationBodyFromKittiCamera().transpose() *
                Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.3, 1.0, -0.2).normalized());
  tr.translation() = Eigen::Vector3d(0.05, -0.4, -0.3);
  Poses gt, est;
  for (std::size_t k = 0; k < 300; ++k) {
    const auto x = static_cast<double>(k);
    Pose v = Pose::Identity(), w = Pose::Identity();
    v.translation() = Eigen::Vector3d(x, 0.0, 0.0);
    w.translation() = Eigen::Vector3d(x, delta * x, 0.0);
    // Camera-0 poses in camera 0's first frame, as poses.txt holds them: C = Tr V Tr⁻¹.
    gt.push_back(tr * v * tr.inverse());
    est.push_back(tr * w * tr.inverse());
  }
  const FrameErrors f = frameErrors(vehicleAxes(gt, &tr), vehicleAxes(est, &tr), 0.0);
  for (std::size_t k = 0; k + 1 < gt.size(); ++k) {
    EXPECT_NEAR(f.tex_m[k], 0.0, 1e-12) << k;
    EXPECT_NEAR(f.tey_m[k], delta, 1e-12) << k;
  }
  ASSERT_EQ(f.eod_percent.size(), gt.size() - 1);
  for (const double e : f.eod_percent)
    EXPECT_NEAR(e, 100.0 * delta, 1e-10);
  const FrameErrors camera = frameErrors(vehicleAxes(gt), vehicleAxes(est), 0.0);
  EXPECT_GT(camera.tex_m[0], 1e-5);  // the tilt puts part of the drift on the other axis
  EXPECT_LT(camera.tey_m[0], delta);
}

// The segment errors by speed: frames 0.1 s apart for the first 400 m (10 m/s), then 0.04 s
// (25 m/s), with a scale error s throughout. Each segment of length L has the error
// s (L + 1) / L (as above) and the speed of its path over its time, worked out here: the table
// holds each bin's segments and their mean, and nothing of a speed no segment has.
TEST(Odometry, TheSegmentsBySpeedFollowTheTimes) {
  const double s = 0.02;
  const Poses gt = straight();
  Poses est = gt;
  for (Pose& T : est)
    T.translation() *= 1.0 + s;
  std::vector<double> times(kFrames, 0.0);
  for (std::size_t k = 1; k < kFrames; ++k)
    times[k] = times[k - 1] + (k <= 400 ? 0.1 : 0.04);
  EvaluateOptions options;
  options.times = times;
  options.speed_bin_m_s = 5.0;
  const Report r = evaluate(gt, est, options);
  std::map<int, std::pair<std::size_t, double>> want;  // bin → segments, sum of errors (%)
  for (const double length : options.lengths_m)
    for (std::size_t first = 0; first + static_cast<std::size_t>(length) + 1 < kFrames;
         first += 10) {
      const std::size_t last = first + static_cast<std::size_t>(length) + 1;
      const double speed = static_cast<double>(last - first) / (times[last] - times[first]);
      // A speed on a bin's edge but for rounding counts in the bin above (10 m/s is 10-15).
      auto& [count, sum] = want[static_cast<int>(std::floor(speed / 5.0 + 1e-9))];
      ++count;
      sum += 100.0 * s * (length + 1.0) / length;
    }
  ASSERT_EQ(r.speeds.size(), want.size());
  std::size_t total = 0;
  for (const Report::Speed& bin : r.speeds) {
    const int b = static_cast<int>(bin.from_m_s / 5.0);
    ASSERT_TRUE(want.count(b)) << bin.from_m_s;
    EXPECT_EQ(bin.to_m_s, bin.from_m_s + 5.0);
    EXPECT_EQ(bin.errors.segments, want[b].first) << bin.from_m_s;
    EXPECT_NEAR(bin.errors.translation_percent, want[b].second / static_cast<double>(want[b].first),
                1e-12);
    EXPECT_EQ(bin.errors.rotation_deg_per_m, 0.0);
    total += bin.errors.segments;
  }
  EXPECT_EQ(total, r.all.segments);
  EXPECT_EQ(r.speeds.front().from_m_s, 10.0);  // the slowest segments: 10 m/s exactly
  EXPECT_EQ(r.speeds.back().from_m_s, 25.0);   // the fastest: 25 m/s exactly
  const nlohmann::json j = nlohmann::json::parse(json(r));
  EXPECT_EQ(j["kitti"]["speeds"].size(), r.speeds.size());
  EXPECT_EQ(j["kitti"]["speeds"][0]["segments"], r.speeds[0].errors.segments);
  EXPECT_NE(markdown(r).find("| 25–30 | 90–108 |"), std::string::npos) << markdown(r);
  // Without times there is no speed table; times that do not pair with the poses are refused.
  EXPECT_FALSE(nlohmann::json::parse(json(evaluate(gt, est))).at("kitti").contains("speeds"));
  times.pop_back();
  options.times = times;
  EXPECT_THROW(evaluate(gt, est, options), ConfigError);
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto path =
      std::filesystem::temp_directory_path() / fmt::format("trainsim_eval_{}_{}", ::getpid(), name);
  std::ofstream(path) << text;
  return path;
}

std::string messageOf(const std::filesystem::path& path) {
  try {
    readKittiPoses(path);
  } catch (const ConfigError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "no error";
}

TEST(KittiPoses, ReadsTheFormatAndNamesTheLineOfAnythingElse) {
  const std::string identity = "1 0 0 0 0 1 0 0 0 0 1 0\n";
  const auto good = write("good", identity + "1.000000e+00 0 0 +2.5e-1 0 1 0 0 0 0 1 1.5e2\n\n");
  const Poses p = readKittiPoses(good);
  std::filesystem::remove(good);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].translation(), Eigen::Vector3d(0.25, 0.0, 150.0));

  EXPECT_NE(messageOf(write("short", identity + "1 0 0 0 0 1 0 0 0 0 1\n")).find(":2: 11 numbers"),
            std::string::npos);
  EXPECT_NE(messageOf(write("nan", identity + "1 0 0 nan 0 1 0 0 0 0 1 0\n"))
                .find(":2: 'nan' is not a finite number"),
            std::string::npos);
  EXPECT_NE(messageOf(write("scaled", "2 0 0 0 0 1 0 0 0 0 1 0\n")).find(":1: the left 3 × 3"),
            std::string::npos);
  EXPECT_NE(messageOf(write("mirror", "-1 0 0 0 0 1 0 0 0 0 1 0\n")).find("not a rotation"),
            std::string::npos);
  EXPECT_NE(messageOf(write("gap", identity + "\n" + identity)).find(":2: empty line"),
            std::string::npos);
  EXPECT_NE(messageOf(write("empty", "")).find("no pose"), std::string::npos);
  EXPECT_NE(messageOf("/nonexistent/poses.txt").find("No such file or directory"),
            std::string::npos);
}

TEST(KittiTimes, ReadsRisingTimesAndNamesTheLineOfAnythingElse) {
  const auto message = [](const std::string& name, const std::string& text) {
    const auto path = write(name, text);
    try {
      readKittiTimes(path);
    } catch (const ConfigError& e) {
      std::filesystem::remove(path);
      return std::string(e.what());
    }
    std::filesystem::remove(path);
    return std::string("no error");
  };
  const auto good = write("times", "0.000000e+00\n1.000000e-01\n0.2\n\n");
  EXPECT_EQ(readKittiTimes(good), (std::vector<double>{0.0, 0.1, 0.2}));
  std::filesystem::remove(good);
  EXPECT_NE(message("same", "0\n0.1\n0.1\n").find(":3: 0.1 s does not come after"),
            std::string::npos);
  EXPECT_NE(message("two", "0\n0.1 0.2\n").find(":2: 2 numbers where a time has one"),
            std::string::npos);
  EXPECT_NE(message("nan", "0\nnan\n").find(":2: 'nan' is not a finite number"), std::string::npos);
  EXPECT_NE(message("gap", "0\n\n0.1\n").find(":2: empty line among the times"), std::string::npos);
  EXPECT_NE(message("empty", "").find("no time"), std::string::npos);
}

// Seeded mutations of a valid poses file (bytes replaced, inserted, deleted; lines cut or
// repeated): every one is read and evaluated or refused with a ConfigError naming the file, and
// nothing else escapes (under the sanitizers: no memory error either).
TEST(KittiPoses, MutatedFilesAreReadOrRefusedByName) {
  std::string valid;
  for (int k = 0; k < 30; ++k)
    valid += fmt::format("1 0 0 {:.6e} 0 1 0 0 0 0 1 {:.6e}\n", 0.01 * k, 2.0 * k);
  const auto valid_path = write("valid", valid);
  const Poses gt = readKittiPoses(valid_path);
  std::filesystem::remove(valid_path);
  const RandomStream random(7, "poses-fuzz");
  const std::string alphabet = "0123456789 .-+eE\n\tnaif#x";
  int accepted = 0;
  for (std::uint64_t i = 0; i < 2000; ++i) {
    std::string text = valid;
    const std::array<double, 4> u = random.uniform4(i);
    const auto at = static_cast<std::size_t>(u[1] * static_cast<double>(text.size()));
    const char c = alphabet[static_cast<std::size_t>(u[2] * static_cast<double>(alphabet.size()))];
    switch (static_cast<int>(u[0] * 4.0)) {
      case 0:
        text[at] = c;
        break;
      case 1:
        text.insert(at, 1, c);
        break;
      case 2:
        text.erase(at, 1 + static_cast<std::size_t>(u[3] * 40.0));
        break;
      default:
        text.insert(at, text.substr(at, static_cast<std::size_t>(u[3] * 60.0)));
        break;
    }
    const auto path = write(fmt::format("fuzz{}", i), text);
    try {
      const Poses est = readKittiPoses(path);
      if (est.size() == gt.size())
        evaluate(gt, est);
      ++accepted;
    } catch (const ConfigError& e) {
      const std::string message = e.what();
      EXPECT_TRUE(message.starts_with(path.string() + ":")) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    std::filesystem::remove(path);
  }
  EXPECT_GT(accepted, 0);  // some mutations keep a valid file (a digit for a digit)
}

TEST(KittiPoses, ReadsTrFromCalib) {
  const auto calib =
      write("calib", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n");
  const Pose tr = readKittiTr(calib);
  std::filesystem::remove(calib);
  EXPECT_EQ(tr.translation(), Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(Eigen::Matrix3d(tr.linear()), rotationBodyFromKittiCamera().transpose());
  const auto none = write("calib_none", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_THROW(readKittiTr(none), ConfigError);
  std::filesystem::remove(none);
}

TEST(Odometry, RejectsSequencesThatDoNotPair) {
  const Poses gt = straight();
  Poses est = gt;
  est.pop_back();
  try {
    evaluate(gt, est);
    FAIL() << "evaluated sequences of different lengths";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--est holds 999 poses and --gt 1000"), std::string::npos);
  }
  EXPECT_THROW(evaluate(Poses(1, Pose::Identity()), Poses(1, Pose::Identity())), ConfigError);
  EvaluateOptions bad;
  bad.lengths_m = {100.0, -5.0};
  EXPECT_THROW(evaluate(gt, gt, bad), ConfigError);
  bad = {};
  bad.step = 0;
  EXPECT_THROW(evaluate(gt, gt, bad), ConfigError);
  bad = {};
  bad.lengths_m = {100.0, 200.0, 100.0};  // 100 m counted twice in 'all'
  EXPECT_THROW(evaluate(gt, gt, bad), ConfigError);
}

TEST(Odometry, JsonCarriesTheReport) {
  const Poses gt = straight();
  Poses est = gt;
  for (Pose& T : est)
    T.translation() *= 1.01;
  const Report r = evaluate(gt, est);
  const nlohmann::json j = nlohmann::json::parse(json(r));
  EXPECT_EQ(j["frames"], kFrames);
  EXPECT_EQ(j["kitti"]["lengths"].size(), 8u);
  EXPECT_DOUBLE_EQ(j["kitti"]["all"]["translation_percent"].get<double>(),
                   r.all.translation_percent);
  EXPECT_DOUBLE_EQ(j["paper"]["eod_percent"]["mean"].get<double>(), r.eod_percent.mean);
  const std::string md = markdown(r);
  EXPECT_NE(md.find("| 100 | 90 | 1.0100 | 0.0000 |"), std::string::npos) << md;
}

}  // namespace
}  // namespace trainsim::evaluation
