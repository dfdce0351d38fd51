// Where the presets' beams leave the head: each Velodyne laser's vertical and horizontal offset
// from its calibration file, an Ouster's beam-origin radius and height, against the drivers'
// own formulas written out here; and the scanner casting from there, against a room of planes
// whose ranges are worked out here from each beam's origin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "lidar_test_poses.hpp"
#include "support/scene_shapes.hpp"
#include "trainsim/lidar/lidar.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/lidar/scan_pattern.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// vert_offset_correction by laser id: ros-drivers/velodyne VLP16db.yaml (ROS 2 branch, commit
// 3353568) and 64e_s3-xiesc.yaml. The HDL-64E S3's horiz_offset_correction is +0.026 m for even
// ids and -0.026 m for odd ones (0.025999999 in the file); the VLP-16 has none.
const std::vector<double> kVlp16Vertical = {0.0112, -0.0007, 0.0097, -0.0022, 0.0081, -0.0037,
                                            0.0066, -0.0051, 0.0051, -0.0066, 0.0037, -0.0081,
                                            0.0022, -0.0097, 0.0007, -0.0112};
const std::vector<double> kHdl64Vertical = {
    0.21569468, 0.21520962, 0.20631704, 0.205832,   0.21484217, 0.21437181, 0.21739969, 0.21695873,
    0.21398966, 0.21347521, 0.21660597, 0.21610622, 0.21049141, 0.21007986, 0.21303425, 0.21262268,
    0.2096977,  0.20919794, 0.21226994, 0.21179958, 0.2088452,  0.20840424, 0.21137333, 0.21093237,
    0.20544985, 0.2049501,  0.20800737, 0.20752234, 0.20461203, 0.20411228, 0.20714018, 0.20668451,
    0.15970787, 0.15922519, 0.14656122, 0.14595152, 0.15861549, 0.15808201, 0.16254044, 0.16200695,
    0.15729448, 0.15663397, 0.16123213, 0.16048269, 0.15228986, 0.15185799, 0.15584644, 0.15545268,
    0.15124829, 0.1507148,  0.15485568, 0.15429679, 0.14997808, 0.14941919, 0.15358547, 0.15291226,
    0.14530372, 0.14482104, 0.14868247, 0.14830141, 0.14432566, 0.14374136, 0.14769171, 0.14725984};

// A return at range r of a Velodyne laser as the velodyne driver (rawdata.cc) writes it: in the
// device's own frame (y forward, x right) from the block's rotation minus the laser's
// rot_correction, then turned into the ROS frame (x forward, y left). `rotation` is clockwise
// from forward: the negative of the scanner's counter-clockwise azimuth.
Eigen::Vector3d velodyneDriver(double r, double rotation, double elevation, double vertical,
                               double horizontal) {
  const double xy = r * std::cos(elevation) - vertical * std::sin(elevation);
  const double x = xy * std::sin(rotation) - horizontal * std::cos(rotation);
  const double y = xy * std::cos(rotation) + horizontal * std::sin(rotation);
  const double z = r * std::sin(elevation) + vertical * std::cos(elevation);
  return {y, -x, z};
}

// The same for an Ouster (ouster-sdk's XYZ lookup table): range r_fw as its firmware reports it
// (from the spin axis, the beam origin's radius n included), encoder angle θ, beam azimuth and
// altitude, then the lidar-to-sensor transform (a half turn about z and `height` up). The
// encoder angle is the head's azimuth in the lidar frame, whose x points backwards.
Eigen::Vector3d ousterSdk(double r_fw, double encoder, double beam_azimuth, double altitude,
                          double n, double height) {
  const double a = encoder - beam_azimuth;
  const Eigen::Vector3d lidar((r_fw - n) * std::cos(a) * std::cos(altitude) + n * std::cos(encoder),
                              (r_fw - n) * std::sin(a) * std::cos(altitude) + n * std::sin(encoder),
                              (r_fw - n) * std::sin(altitude));
  return {-lidar.x(), -lidar.y(), lidar.z() + height};
}

TEST(BeamOrigins, VelodyneReturnsLieWhereTheDriverPutsThem) {
  struct Case {
    const char* name;
    const std::vector<double>* vertical;
    double horizontal;
  };
  for (const Case& k :
       {Case{"vlp16", &kVlp16Vertical, 0.0}, Case{"hdl64", &kHdl64Vertical, 0.026}}) {
    SCOPED_TRACE(k.name);
    lidar::LidarParams params;
    params.pattern = lidar::preset(k.name, 10.0, 90);
    params.motion_distortion = false;
    const lidar::Scanner scanner(params);
    const auto& lasers = params.pattern.lasers;
    ASSERT_EQ(lasers.size(), k.vertical->size());
    for (std::size_t l = 0; l < lasers.size(); ++l) {
      EXPECT_EQ(lasers[l].vertical_offset_m, (*k.vertical)[l]);
      EXPECT_NEAR(lasers[l].horizontal_offset_m, l % 2 == 0 ? k.horizontal : -k.horizontal, 1e-8);
      for (int c = 0; c < 90; c += 7)
        for (const double r : {1.0, 37.5}) {
          const auto i = static_cast<int>(l);
          const Eigen::Vector3d ours = scanner.origin(c, i) + r * scanner.direction(c, i);
          const Eigen::Vector3d driver = velodyneDriver(
              r, -params.pattern.azimuthDeg(c, i) * kDeg, lasers[l].elevation_deg * kDeg,
              (*k.vertical)[l], lasers[l].horizontal_offset_m);
          EXPECT_LT((ours - driver).norm(), 1e-12) << "laser " << l << " column " << c;
        }
    }
  }
  // A calibration without offsets casts from the origin.
  lidar::LidarParams hdl32;
  hdl32.pattern = lidar::preset("hdl32", 10.0, 90);
  EXPECT_FALSE(hdl32.pattern.offsetBeams());
  EXPECT_EQ(lidar::Scanner(hdl32).origin(5, 3), Eigen::Vector3d::Zero());
}

TEST(BeamOrigins, OusterReturnsLieWhereItsSdkPutsThem) {
  // Both OS1 presets: lidar_origin_to_beam_origin_mm 15.806 (ouster-sdk's default for an OS-1
  // and the OS1-128's metadata) and lidar_to_sensor_transform's z, 36.18 mm.
  for (const char* name : {"os1_64", "os1_128"}) {
    SCOPED_TRACE(name);
    lidar::LidarParams params;
    params.pattern = lidar::preset(name, 10.0, 1024);
    params.motion_distortion = false;
    const lidar::Scanner scanner(params);
    const double n = 0.015806, height = 0.03618;
    EXPECT_EQ(params.pattern.beam_origin_radius_m, n);
    EXPECT_EQ(params.pattern.beam_origin_height_m, height);
    const auto& lasers = params.pattern.lasers;
    for (std::size_t l = 0; l < lasers.size(); l += 3)
      for (int c = 0; c < 1024; c += 61) {
        const auto i = static_cast<int>(l);
        const double r = 12.0;  // from the beam's origin; the firmware reports r + n
        const Eigen::Vector3d ours = scanner.origin(c, i) + r * scanner.direction(c, i);
        // Measurement id c: encoder 2π (1 − c / 1024) in the lidar frame (x backwards).
        const Eigen::Vector3d sdk = ousterSdk(r + n, 2.0 * std::numbers::pi * (1.0 - c / 1024.0),
                                              -lasers[l].azimuth_offset_deg * kDeg,
                                              lasers[l].elevation_deg * kDeg, n, height);
        EXPECT_LT((ours - sdk).norm(), 1e-12) << "beam " << l << " column " << c;
      }
  }
}

// The range along `d` from `o` to the inside of the axis-aligned cube of half side `half`
// around the origin.
double toCube(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double half) {
  double t = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
    if (d[k] != 0.0)
      t = std::min(t, ((d[k] > 0.0 ? half : -half) - o[k]) / d[k]);
  return t;
}

TEST(BeamOrigins, RaysStartWhereTheBeamsLeaveTheHeadFarOut) {
  // A closed room of planes 6 m each way round a sensor 1000 km out. Every return's range is
  // the distance from its beam's origin to the room, to a millimetre (from the sensor's origin
  // it would be off by up to 10 cm for the HDL-64E, 17 mm for the OS1-64 and 3 mm for the VLP-16
  // here), and its point is that origin plus the range along the beam.
  const Eigen::Vector3d O(1.0e6, -2.0e5, 50.0);
  const double half = 6.0;
  std::vector<scene::Mesh> walls;
  for (int axis = 0; axis < 3; ++axis)
    for (const double s : {-1.0, 1.0}) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[axis] = 1.0;
      walls.push_back(test::square(s * half * e, -s * e, half * 1.01));
    }
  const auto tile = test::makeTile(O, std::move(walls));
  // Each preset through the packets' returns; the HDL-64E also with the points written as
  // measured, and with several sub-rays a pulse (a footprint too narrow to spread the ranges).
  struct Case {
    const char* name;
    int sub_rays;
    bool compensated;
  };
  for (const Case& k : {Case{"hdl64", 1, true}, Case{"os1_64", 1, true}, Case{"vlp16", 1, true},
                        Case{"hdl64", 1, false}, Case{"hdl64", 5, true}}) {
    const std::string name = k.name;
    SCOPED_TRACE(name + (k.compensated ? "" : ", as measured") +
                 (k.sub_rays > 1 ? ", sub-rays" : ""));
    lidar::LidarParams params;
    params.pattern = lidar::preset(name, 10.0, name[0] == 'o' ? 512 : 300);
    params.range_sigma_m = 0.0;
    params.motion_distortion = false;
    params.motion_compensated = k.compensated;
    params.sub_rays = k.sub_rays;
    params.divergence_rad = 1e-7;
    const lidar::Scanner scanner(params);
    lidar::RayWorld world;
    const lidar::LidarFrame frame =
        scanner.scan(world.scene({tile}), test::fixedPose(O), RandomStream(3, "beams"), 0);
    ASSERT_EQ(static_cast<std::int64_t>(frame.points.size()), scanner.pulsesPerFrame());
    const std::vector<int> ring_laser = params.pattern.ringLasers();
    double worst = 0.0, worst_point = 0.0, most_moved = 0.0;
    for (const lidar::LidarPoint& p : frame.points) {
      const int l = ring_laser[p.ring];
      const Eigen::Vector3d o = scanner.origin(p.column, l), d = scanner.direction(p.column, l);
      const double expected = toCube(o, d, half);
      worst = std::max(worst, std::abs(p.range_m - expected));
      const Eigen::Vector3d at = o + expected * d;
      worst_point = std::max(worst_point, (p.xyz.cast<double>() - at).norm());
      worst_point = std::max(worst_point, (scanner.written(p).cast<double>() - at).norm());
      most_moved =
          std::max(most_moved, std::abs(expected - toCube(Eigen::Vector3d::Zero(), d, half)));
    }
    EXPECT_LT(worst, 1e-3);
    EXPECT_LT(worst_point, 1e-3);
    // The offsets move the ranges by more than the accuracy asked of them.
    const double moved = name[0] == 'h' ? 0.05 : name[0] == 'o' ? 0.01 : 0.002;
    EXPECT_GT(most_moved, moved);
  }
}

TEST(BeamOrigins, TheVehicleCutsEachBeamFromWhereItLeavesTheHead) {
  // The HDL-64E 5 cm above a train's roof on its front edge, over flat ground: its beams leave
  // the head 0.14-0.22 m higher still, so a beam is hidden when the ray from its own origin
  // crosses the roof's plane within the roof's rectangle (written here, not the scanner's slab
  // test), and every other beam reaching the ground returns it at the range from its origin.
  const Eigen::Vector3d O(3.0e5, -2.0e5, 0.0);
  const double height = 3.85, roof = 3.8, front = 10.0, length = 24.0, half_width = 1.45;
  const auto tile = test::makeTile(O, {test::square({0, 0, -height}, {0, 0, 1}, 400.0,
                                                    scene::cls::kTerrain, scene::mat::kGrass)});
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  lidar::LidarParams p;
  p.pattern = lidar::preset("hdl64", 10.0, 1001);
  p.range_sigma_m = 0.0;
  p.motion_distortion = false;
  lidar::LidarParams::Vehicle v;
  v.box = Eigen::AlignedBox3d(Eigen::Vector3d(front - length, -half_width, 0.0),
                              Eigen::Vector3d(front, half_width, roof));
  v.sensor_pose.translation() = Eigen::Vector3d(front, 0.0, height);
  p.vehicle = v;
  const lidar::Scanner scanner(p);
  // A beam leaving the head above the roof enters the body through the roof, or, from a head
  // a little ahead of the roof's front edge (the offsets put some beams' origins there), through
  // the front face below it.
  const auto hidden = [&](const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    if (d.z() >= 0.0)
      return false;
    const Eigen::Vector3d at(front + o.x(), o.y(), height + o.z());  // the origin on the vehicle
    const double t = (at.z() - roof) / -d.z();
    const double x = at.x() + t * d.x(), y = at.y() + t * d.y();
    if (x >= front - length && x <= front && std::abs(y) <= half_width)
      return true;
    if (at.x() <= front || d.x() >= 0.0)
      return false;
    const double s = (front - at.x()) / d.x();  // where it crosses the front face's plane
    const double z = at.z() + s * d.z(), w = at.y() + s * d.y();
    return z >= 0.0 && z <= roof && std::abs(w) <= half_width;
  };
  std::size_t expected = 0, hidden_by_origin = 0;
  for (int c = 0; c < 1001; ++c)
    for (int l = 0; l < 64; ++l) {
      const Eigen::Vector3d o = scanner.origin(c, l), d = scanner.direction(c, l);
      const double range = (-height - o.z()) / d.z();
      const bool ground =
          d.z() < 0.0 && range >= p.pattern.range_min_m && range <= p.pattern.range_max_m;
      expected += ground && !hidden(o, d);
      // Beams the roof would hide from the sensor's origin but not from their own.
      hidden_by_origin += ground && !hidden(o, d) && hidden(Eigen::Vector3d::Zero(), d);
    }
  const auto frame = scanner.scan(scene, test::fixedPose(O), RandomStream(1, "x"), 0);
  EXPECT_EQ(frame.points.size(), expected);
  EXPECT_GT(hidden_by_origin, 100u) << "the beams' height matters here";
  const std::vector<int> ring_laser = p.pattern.ringLasers();
  for (const auto& pt : frame.points) {
    const int l = ring_laser[pt.ring];
    const Eigen::Vector3d o = scanner.origin(pt.column, l), d = scanner.direction(pt.column, l);
    ASSERT_FALSE(hidden(o, d)) << pt.xyz.transpose();
    EXPECT_NEAR(pt.range_m, (-height - o.z()) / d.z(), 1e-3);
  }
}

}  // namespace
}  // namespace trainsim
