// Embree's side of the LiDAR against analytic scenes built here: planes, boxes, wires and
// spheres at known places, at the scenario origin and 1000 km from it (there in the tile's level
// axes), instanced prototypes, and height fields as Embree grids, all against a double brute
// force.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "support/scene_shapes.hpp"
#include "trainsim/core/frames.hpp"
#include "trainsim/lidar/ray_scene.hpp"
#include "trainsim/scene/scene.hpp"

namespace trainsim {
namespace {

using lidar::Ray;
using lidar::RayHit;
using test::makeTile;
using test::square;

// Exact ray–triangle distance in double (Möller–Trumbore), infinity for a miss.
double rayTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                   const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18)
    return INFINITY;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (u < 0 || v < 0 || u + v > 1)
    return INFINITY;
  const double t = e2.dot(q) / det;
  return t > 0 ? t : INFINITY;
}

// Brute force over every triangle of every object of the tile (world, double).
double bruteForce(const scene::Tile& tile, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = INFINITY;
  for (const auto& obj : tile.objects)
    for (const auto& t : obj.mesh->triangles)
      best = std::min(best, rayTriangle(o, d, obj.worldVertex(t[0]), obj.worldVertex(t[1]),
                                        obj.worldVertex(t[2])));
  return best;
}

class RaySceneAt : public ::testing::TestWithParam<double> {};

TEST_P(RaySceneAt, RangesMatchPlanesBoxesSpheresAndWiresToAMillimetre) {
  // The same scene at the origin and 1000 km out: world coordinates in double, tiles at their
  // own origin, the Embree scene relative to a tile's origin.
  const Eigen::Vector3d O(GetParam(), 0.5 * GetParam(), 250.0);
  const Eigen::Vector3d sensor = O + Eigen::Vector3d(3.0, 4.0, 1.8);
  std::vector<scene::Mesh> meshes;
  // Planes at 1 .. 199 m, each in its own direction (17° apart) and turned 35° from facing
  // the sensor.
  const std::vector<double> distances = {1.0, 2.5, 10.0, 30.0, 75.0, 120.0, 160.0, 199.0};
  const auto bearing = [](std::size_t k) {
    return (-60.0 + 17.0 * static_cast<double>(k)) * kRadPerDeg;
  };
  const auto normal = [&](std::size_t k) -> Eigen::Vector3d {
    const double a = bearing(k) + std::numbers::pi + 35 * kRadPerDeg;
    return Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
  };
  const auto centre = [&](std::size_t k) -> Eigen::Vector3d {
    return distances[k] * Eigen::Vector3d(std::cos(bearing(k)), std::sin(bearing(k)), 0.0);
  };
  for (std::size_t k = 0; k < distances.size(); ++k)
    meshes.push_back(square(sensor - O + centre(k), normal(k), 0.1 * distances[k]));
  scene::Mesh box;
  box.beginPart(scene::cls::kRock, scene::mat::kRock);
  scene::addBox(box, (sensor - O + Eigen::Vector3d(-40, -3, -2)).cast<float>(),
                (sensor - O + Eigen::Vector3d(-36, 5, 3)).cast<float>());
  meshes.push_back(std::move(box));
  scene::Mesh ball;
  ball.beginPart(scene::cls::kVegetation, scene::mat::kLeaves);
  scene::addBlob(ball, (sensor - O + Eigen::Vector3d(0, -25, 0)).cast<float>(),
                 Eigen::Vector3f::Constant(2.0f), 4);
  meshes.push_back(std::move(ball));
  // A contact wire 6 mm in radius, 5 m above the sensor, along x.
  scene::Wire wire;
  wire.radius_m = 0.006f;
  wire.instance = 77;
  for (double x : {-60.0, 0.0, 60.0})
    wire.points.push_back((sensor - O + Eigen::Vector3d(x, 0.0, 5.0)).cast<float>());
  // 1000 km out the Earth's curvature tilts the ground 9° against the world's axes, and the
  // tile's BVH is built in its level axes: the hits must not change.
  auto tile = std::make_shared<scene::Tile>(*makeTile(O, std::move(meshes), {wire}));
  if (GetParam() > 0.0)
    tile->level = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(),
                                                     Eigen::Vector3d(O.x(), O.y(), O.z() + 6.371e6))
                      .toRotationMatrix();

  lidar::RayWorld world;
  const lidar::RayScene scene = world.scene({tile});
  EXPECT_EQ(scene.origin(), O);

  std::vector<Eigen::Vector3d> dirs;
  for (std::size_t k = 0; k < distances.size(); ++k)  // centres of the planes and around
    for (double a : {-0.05, 0.0, 0.05})
      dirs.push_back(
          (centre(k) + a * distances[k] * Eigen::Vector3d(normal(k).y(), -normal(k).x(), 1.0))
              .normalized());
  for (double y : {-1.0, 0.0, 2.0, 4.5})  // the box's face x = -36
    for (double z : {-1.5, 0.0, 2.5})
      dirs.push_back(Eigen::Vector3d(-39.0, y, z).normalized());
  for (double a = -0.9; a <= 0.9; a += 0.15)  // the sphere
    for (double b = -0.9; b <= 0.9; b += 0.3)
      dirs.push_back(Eigen::Vector3d(a, -25.0, b).normalized());
  const std::size_t first_wire = dirs.size();
  for (double x : {-30.0, -5.0, 10.0, 45.0})  // up to the wire, through its axis
    dirs.push_back(Eigen::Vector3d(x, 0.0, 5.0).normalized());

  std::vector<Ray> rays;
  for (const auto& d : dirs)
    rays.push_back({(sensor - O).cast<float>(), d.cast<float>(), 0.5f, 300.0f});
  std::vector<RayHit> hits(rays.size());
  scene.intersect(rays, hits);

  double worst = 0.0, worst_wire = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    // The reference ray is the one Embree got (float direction), from the sensor in double.
    const Eigen::Vector3d d = rays[i].direction.cast<double>();
    double truth;
    if (i >= first_wire) {
      // The round wire along x at height 5 m: the first root of
      // (t d_y)² + (t d_z − 5)² = r² (the cylinder through the sensor's plane).
      const double r = 0.006, A = d.y() * d.y() + d.z() * d.z(), B = -2.0 * 5.0 * d.z(),
                   C = 25.0 - r * r;
      truth = (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
      ASSERT_TRUE(hits[i].hit()) << i;
      EXPECT_EQ(hits[i].cls, scene::cls::kWire);
      EXPECT_EQ(scene.instances()[hits[i].object], 77u);
    } else {
      truth = bruteForce(*tile, sensor, d);
    }
    ASSERT_TRUE(std::isfinite(truth)) << i << " " << d.transpose();
    ASSERT_TRUE(hits[i].hit()) << i;
    if (i >= first_wire) {
      // Along the ray, even 6° from the wire, where an error across it grows tenfold.
      worst_wire = std::max(worst_wire, std::abs(hits[i].range - truth));
      const Eigen::Vector3d radial(0.0, d.y() * truth, d.z() * truth - 5.0);
      EXPECT_GT(std::abs(hits[i].normal.cast<double>().dot(radial.normalized())), 1.0 - 1e-5);
      continue;
    }
    worst = std::max(worst, std::abs(hits[i].range - truth));
    if (i < 3 * distances.size()) {
      EXPECT_EQ(hits[i].cls, scene::cls::kBuilding);
      EXPECT_EQ(hits[i].material, scene::mat::kConcrete);
      EXPECT_EQ(scene.instances()[hits[i].object], i / 3 + 1);  // each plane its own instance
      EXPECT_GT(std::abs(hits[i].normal.cast<double>().dot(normal(i / 3))), 1.0 - 1e-6);
    }
  }
  EXPECT_LT(worst, 1e-3) << "worst range error " << worst;
  EXPECT_LT(worst_wire, 1e-4) << "worst range error on the wire "
                              << worst_wire;  // measured < 10 µm
}

INSTANTIATE_TEST_SUITE_P(NearAndFar, RaySceneAt, ::testing::Values(0.0, 1.0e6));

TEST(RayScene, InstancedPrototypesCarryTheirObjectsLabelsAndTransform) {
  const Eigen::Vector3d O(1.0e6, -3.0e5, 10.0);
  auto proto = std::make_shared<scene::Mesh>();
  proto->prototype = true;
  proto->beginPart(scene::cls::kTrunk, scene::mat::kBark);
  scene::addCylinder(*proto, {0, 0, 0}, {0, 0, 3}, 0.3f, 0.3f, 12);
  proto->beginPart(scene::cls::kTree, scene::mat::kLeaves);
  scene::addBlob(*proto, {0, 0, 4}, Eigen::Vector3f(1.5f, 1.5f, 1.8f), 2);
  const std::shared_ptr<const scene::Mesh> shared = proto;
  std::vector<scene::Object> objects;
  for (int k = 0; k < 3; ++k) {
    const float c = std::cos(0.4f * k), s = std::sin(0.4f * k);
    Eigen::Matrix3f linear;
    linear << c, -s, 0, s, c, 0, 0, 0, 1;
    linear *= 1.0f + 0.2f * k;
    objects.push_back(scene::Object::place(
        shared, O + Eigen::Vector3d(20.0 + 10 * k, 5.0 + 8.0 * k * (k == 2 ? -1 : 1), 0.0), linear,
        1000 + k));
  }
  const auto tile = makeTile(O, {}, {}, std::move(objects));
  lidar::RayWorld world;
  const auto scene = world.scene({tile});
  EXPECT_EQ(scene.instanceCount(), 4u);  // the tile and three trees
  const Eigen::Vector3d sensor = O + Eigen::Vector3d(0, 5.0, 1.0);
  std::vector<Ray> rays;
  for (const auto& o : tile->objects)
    for (double z : {1.0, 4.0})  // trunk, crown
      rays.push_back({(sensor - O).cast<float>(),
                      (o.position + Eigen::Vector3d(0, 0, z) - sensor).normalized().cast<float>(),
                      0.1f, 500.0f});
  std::vector<RayHit> hits(rays.size());
  scene.intersect(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_TRUE(hits[i].hit());
    EXPECT_EQ(scene.instances()[hits[i].object], 1000 + i / 2);
    EXPECT_EQ(hits[i].cls, i % 2 == 0 ? scene::cls::kTrunk : scene::cls::kTree);
    const double truth = bruteForce(*tile, sensor, rays[i].direction.cast<double>());
    EXPECT_NEAR(hits[i].range, truth, 1e-3);
  }
}

// A bumpy height field as terrain::terrainMesh makes one (Mesh::grid_columns), cast into as
// triangles and as an Embree grid: the same surface, label and normal, to float rounding, and
// both within a millimetre of the double brute force over the mesh's triangles.
TEST(RayScene, HeightFieldsAsEmbreeGridsAreTheSameSurfaceAsTheirTriangles) {
  const Eigen::Vector3d O(1.0e6, 2.0e5, 120.0);
  constexpr int kW = 41, kH = 33;
  scene::Mesh field;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c)
      field.addVertex(Eigen::Vector3f(2.0f * c, 2.0f * r,
                                      1.5f * std::sin(0.3f * c) * std::cos(0.23f * r) + 0.1f * c));
  field.beginPart(scene::cls::kTerrain, scene::mat::kGrass);
  for (int r = 0; r + 1 < kH; ++r)
    for (int c = 0; c + 1 < kW; ++c) {
      const auto v = static_cast<std::uint32_t>(r * kW + c);
      field.addQuad(v + 1, v + kW + 1, v + kW, v);
    }
  field.grid_columns = kW;
  const auto tile = makeTile(O, {field});
  lidar::RayWorld triangles, grids({true, "avx2", true});
  const auto a = triangles.scene({tile});
  const auto b = grids.scene({tile});
  std::vector<Ray> rays;
  const Eigen::Vector3d sensor(40.0, 30.0, 8.0);
  for (int i = 0; i < 2000; ++i) {
    const double az = 0.0314 * i, el = -0.08 - 0.6 * (i % 97) / 97.0;
    const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    rays.push_back({sensor.cast<float>(), d.cast<float>(), 0.1f, 300.0f});
  }
  std::vector<RayHit> ha(rays.size()), hb(rays.size());
  a.intersect(rays, ha);
  b.intersect(rays, hb);
  int hits = 0;
  double worst = 0.0, worst_truth = 0.0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(ha[i].hit(), hb[i].hit()) << i;
    if (!ha[i].hit())
      continue;
    ++hits;
    worst = std::max(worst, std::abs(static_cast<double>(ha[i].range - hb[i].range)));
    const double truth = bruteForce(*tile, O + sensor, rays[i].direction.cast<double>());
    worst_truth = std::max(worst_truth, std::abs(hb[i].range - truth));
    EXPECT_EQ(hb[i].cls, scene::cls::kTerrain);
    EXPECT_EQ(hb[i].material, scene::mat::kGrass);
    EXPECT_EQ(b.instances()[hb[i].object], a.instances()[ha[i].object]);
    EXPECT_GT(ha[i].normal.dot(hb[i].normal), 0.9999f) << i;
  }
  EXPECT_GT(hits, 1500);
  EXPECT_LT(worst, 1e-4) << "grid against triangles";
  EXPECT_LT(worst_truth, 1e-3) << "grid against the double brute force";
}

// What a ray returns is a pure function of the tiles: not of who else holds their meshes at the
// moment. A camera keeps every mesh it has drawn; the LiDAR once took a mesh held twice for a
// shared prototype and instanced it, so a bridge was cast in other float axes (one intensity a
// bit apart) depending on whether the camera had drawn its tile first, i.e. on the threads.
TEST(RayScene, WhatARayHitsDoesNotDependOnWhoElseHoldsATilesMeshes) {
  const Eigen::Vector3d O(3.0e5, -1.0e5, 40.0);
  scene::Mesh deck;
  deck.beginPart(scene::cls::kBridge, scene::mat::kConcrete);
  scene::addOrientedBox(deck, {20.0f, 3.0f, 1.0f}, Eigen::Vector3f(14.0f, 9.0f, 0.0f),
                        Eigen::Vector3f(-1.2f, 1.8f, 0.3f), Eigen::Vector3f(0.0f, 0.0f, 0.8f));
  const auto tile = makeTile(O, {square({20.0, 0.0, -2.0}, Eigen::Vector3d::UnitZ(), 60.0,
                                        scene::cls::kTerrain, scene::mat::kGrass),
                                 deck});
  std::vector<Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    const double az = -0.9 + 1.4 * i / 3000.0, el = -0.25 + 0.2 * (i % 61) / 61.0;
    const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    rays.push_back({Eigen::Vector3f(-8.0f, 2.0f, 4.0f), d.cast<float>(), 0.1f, 300.0f});
  }
  const auto cast = [&](std::size_t& instances) {
    lidar::RayWorld world;
    const auto scene = world.scene({tile});
    std::vector<RayHit> hits(rays.size());
    scene.intersect(rays, hits);
    instances = scene.instanceCount();
    return hits;
  };
  std::size_t alone = 0, held = 0;
  const auto a = cast(alone);
  const std::vector<scene::Object> camera = tile->objects;  // holds every mesh once more
  const auto b = cast(held);
  EXPECT_EQ(alone, 1u);  // the tile: its meshes are no prototypes
  EXPECT_EQ(held, alone);
  int bridge = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(a[i].hit(), b[i].hit()) << i;
    EXPECT_EQ(a[i].range, b[i].range) << i;
    EXPECT_EQ(a[i].normal, b[i].normal) << i;
    EXPECT_EQ(a[i].cls, b[i].cls) << i;
    bridge += a[i].cls == scene::cls::kBridge;
  }
  EXPECT_GT(bridge, 300);
}

}  // namespace
}  // namespace trainsim
