// The returns kernel is built twice, for SSE2 (the x86-64 baseline) and for AVX2, and the scanner
// runs the AVX2 one where the processor has it: a dataset must not depend on the machine, so
// the two must give the same bytes for every lane of every packet (white-box: the kernel is
// private to the LiDAR module). The closed-form accuracy tests in lidar_test.cpp run whichever
// build this processor picks; this test ties the other one to it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "packet_returns.hpp"
#include "support/scene_shapes.hpp"
#include "trainsim/core/random.hpp"
#include "trainsim/lidar/ray_scene.hpp"

namespace trainsim {
namespace {

using lidar::LidarPoint;
using lidar::RayPacket;
using lidar::detail::Isa;
using lidar::detail::kNoReturn;
using lidar::detail::packetReturns;
using lidar::detail::PacketSetup;

// A unit vector from two uniforms.
Eigen::Vector3d direction(double u, double v) {
  const double z = 2.0 * u - 1.0, phi = 2.0 * std::numbers::pi * v;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// Squares of every material all around the origin, each tilted at random against the line of
// sight (so rays meet them from head-on to grazing), 3 to 180 m out, and a copper wire.
std::shared_ptr<const scene::Tile> everyMaterialAround(const RandomStream& random) {
  std::vector<scene::Mesh> meshes;
  const auto& table = scene::materials();
  for (std::size_t k = 0; k < 240; ++k) {
    const auto u = random.uniform4(k, 0), w = random.uniform4(k, 1);
    const Eigen::Vector3d at = direction(u[0], u[1]) * (3.0 + 177.0 * u[2]);
    const Eigen::Vector3d tilt = direction(w[0], w[1]);
    const Eigen::Vector3d normal = (-at.normalized() + 3.0 * w[2] * tilt).normalized();
    const auto mat = static_cast<scene::MaterialId>(1 + k % (table.size() - 1));
    meshes.push_back(test::square(at, normal, 0.15 * at.norm(), scene::cls::kBuilding, mat));
  }
  scene::Wire wire{{{-20.0f, 10.0f, 4.0f}, {20.0f, 10.0f, 4.5f}},
                   0.006f,
                   scene::cls::kWire,
                   scene::mat::kCopper,
                   999};
  return test::makeTile(Eigen::Vector3d::Zero(), std::move(meshes), {wire});
}

TEST(PacketReturns, TheAvx2BuildGivesTheBaselineBuildsBytesInEveryLane) {
  if (!lidar::detail::avx2Returns())
    GTEST_SKIP() << "this processor has no AVX2: only the baseline build runs on it";
  const RandomStream random(7, "packet-returns");
  lidar::RayWorld world;
  const lidar::RayScene scene = world.scene({everyMaterialAround(random)});

  // 253 columns (the last packet five lanes), rays in every direction from the origin, cast.
  constexpr std::size_t kColumns = 253, kPadded = 256, kPackets = kPadded / 8;
  std::vector<RayPacket> packets(kPackets);
  std::vector<float> ax(kPadded), ay(kPadded), az(kPadded);
  for (std::size_t c = 0; c < kColumns; ++c) {
    const auto u = random.uniform4(1000 + c);
    const Eigen::Vector3f d = direction(u[0], u[1]).cast<float>();
    RayPacket& q = packets[c / 8];
    const std::size_t k = c % 8;
    q.org_x[k] = q.org_y[k] = q.org_z[k] = 0.0f;
    q.dir_x[k] = d.x();
    q.dir_y[k] = d.y();
    q.dir_z[k] = d.z();
    q.t_near[k] = 0.5f;
    q.t_far[k] = 200.0f;
    ax[c] = d.x();
    ay[c] = d.y();
    az[c] = d.z();
  }
  scene.cast(packets, kColumns);

  // Each column's deskewing: a rotation and a shift of a few metres, as a moving sensor has.
  std::vector<float> frames(24 * kPadded);
  std::vector<Eigen::Vector3d> directions(kColumns);
  for (std::size_t c = 0; c < kColumns; ++c) {
    const auto u = random.uniform4(2000 + c), v = random.uniform4(3000 + c);
    const Eigen::Matrix3f rot =
        Eigen::AngleAxisd(0.2 * u[0], direction(u[1], u[2])).toRotationMatrix().cast<float>();
    for (std::size_t i = 0; i < 9; ++i)
      frames[(12 + i) * kPadded + c] =
          rot(static_cast<Eigen::Index>(i / 3), static_cast<Eigen::Index>(i % 3));
    for (std::size_t i = 0; i < 3; ++i)
      frames[(21 + i) * kPadded + c] = static_cast<float>(4.0 * v[i] - 2.0);
    directions[c] = Eigen::Vector3d(ax[c], ay[c], az[c]).normalized();
  }
  std::vector<lidar::Backscatter> backscatter;
  for (const scene::Material& m : scene::materials())
    backscatter.emplace_back(m);

  std::size_t returned = 0, glossy = 0, cases = 0;
  for (const std::size_t R : {std::size_t{1}, std::size_t{2}})
    for (const auto scale : {lidar::IntensityScale::kUnit, lidar::IntensityScale::kVlp16})
      for (const bool falloff : {false, true})
        for (const bool measured : {false, true}) {
          PacketSetup s;
          s.backscatter = backscatter.data();
          s.sigma0 = 0.02;
          s.sigma1 = falloff ? 0.001 : 0.0;
          s.threshold = scale == lidar::IntensityScale::kUnit ? 0.02 : 0.0;
          s.range_min = 1.0f;
          s.range_max = 150.0f;  // some hits lie past it
          s.falloff = falloff;
          s.scale = scale;
          s.frames = frames.data();
          s.padded = kPadded;
          s.deskew = 12;
          s.shift = 21;
          s.ax = ax.data();
          s.ay = ay.data();
          s.az = az.data();
          s.directions = measured ? directions.data() : nullptr;
          s.ring = 3;
          s.returns = R;
          std::vector<double> noise(kPadded * R);
          std::vector<std::uint8_t> kept(kPadded);
          for (std::size_t c = 0; c < kPadded; ++c) {
            const auto u = random.uniform4(4000 + c, cases);
            noise[c * R] =
                std::sqrt(-2.0 * std::log(u[0])) * std::cos(2.0 * std::numbers::pi * u[1]);
            kept[c] = u[2] > 0.1;  // one pulse in ten dropped
          }
          // Both builds write into the same starting bytes.
          std::vector<LidarPoint> points[2];
          std::vector<float> keys[2];
          std::size_t found[2] = {0, 0};
          for (int b = 0; b < 2; ++b) {
            points[b].assign(kPadded * R, LidarPoint{});
            keys[b].assign(kPadded * R, kNoReturn);
            for (std::size_t i = 0; i < kPackets; ++i) {
              const std::size_t c0 = 8 * i;
              found[b] += packetReturns(s, packets[i], c0, std::min<std::size_t>(8, kColumns - c0),
                                        &noise[c0 * R], &kept[c0], points[b].data(), keys[b].data(),
                                        b == 0 ? Isa::kSse2 : Isa::kAvx2);
            }
          }
          ASSERT_EQ(found[0], found[1]) << "case " << cases;
          ASSERT_EQ(0, std::memcmp(keys[0].data(), keys[1].data(), keys[0].size() * sizeof(float)))
              << "case " << cases;
          for (std::size_t slot = 0; slot < keys[0].size(); ++slot)
            if (keys[0][slot] != kNoReturn) {  // an empty slot's point is never read
              glossy += backscatter[points[0][slot].material].specular() > 0.0;
              ASSERT_EQ(0, std::memcmp(&points[0][slot], &points[1][slot], sizeof(LidarPoint)))
                  << "case " << cases << ", slot " << slot << ": intensity "
                  << points[0][slot].intensity << " against " << points[1][slot].intensity;
            }
          returned += found[0];
          ++cases;
        }
  // Not vacuous: over a third of the rays returned in every case on average (the rest missed or
  // were dropped, out of range or too faint), glossy surfaces (the exponential) among them.
  EXPECT_GT(returned, cases * kColumns / 3);
  EXPECT_GT(glossy, returned / 10);
}

}  // namespace
}  // namespace trainsim
