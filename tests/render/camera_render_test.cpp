// The cameras' renders of analytic scenes built here, under a private Xvfb the test starts
// itself: depth of a tilted plane against the closed form (also 1000 km from the scenario
// origin), class and instance ids exactly those of the objects drawn (no blended ids), known
// points landing on the rendered edges, and images that do not depend on what was drawn before.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "support/scene_shapes.hpp"
#include "support/x_environment.hpp"
#include "trainsim/camera/lens.hpp"
#include "trainsim/camera/renderer.hpp"

namespace trainsim {
namespace {

using test::makeTile;
using test::square;

const auto* const kX = ::testing::AddGlobalTestEnvironment(new test::XEnvironment);

// A camera at `at` looking along world +x (camera x = world −y, y = world −z), level.
Eigen::Isometry3d lookingAlongX(const Eigen::Vector3d& at) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = -Eigen::Vector3d::UnitY();
  T.linear().col(1) = -Eigen::Vector3d::UnitZ();
  T.linear().col(2) = Eigen::Vector3d::UnitX();
  T.translation() = at;
  return T;
}

camera::Intrinsics smallCamera() {
  camera::Intrinsics k;
  k.width = 320;
  k.height = 240;
  k.fx = 300.0;
  k.fy = 280.0;
  k.cx = 150.3;
  k.cy = 125.6;
  return k;
}

class CameraDepth : public ::testing::TestWithParam<double> {};

TEST_P(CameraDepth, APlaneAtAKnownDistanceAndAngleHasItsAnalyticDepth) {
  const Eigen::Vector3d O(GetParam(), 0.37 * GetParam(), 250.0);
  // A plane 20 m ahead on the axis, turned 35° about z and 10° about y: it fills the view.
  const Eigen::Vector3d n =
      (Eigen::AngleAxisd(0.6109, Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(-0.1745, Eigen::Vector3d::UnitY()) * -Eigen::Vector3d::UnitX())
          .normalized();
  const Eigen::Vector3d centre(20.0, 0.0, 2.0);
  const auto tile = makeTile(O, {square(centre, n, 200.0)});
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer renderer(o);
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.0));
  const camera::CameraImages img = renderer.render({{tile}}, T, {});
  ASSERT_EQ(img.depth.size(), 320u * 240u);
  const camera::Intrinsics& k = o.intrinsics;
  double worst = 0.0;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);  // z = 1
      const Eigen::Vector3d ray = T.linear() * d;
      const double depth = n.dot(O + centre - T.translation()) / n.dot(ray);
      worst = std::max(worst, std::abs(img.depth[v * k.width + u] - depth));
    }
  // Depths here are 10 to 60 m: the depth buffer's step is at most 0.5 mm, KITTI's PNG 3.9 mm.
  EXPECT_LT(worst, 1.0 / 256.0);
  RecordProperty("worst_depth_error_m", std::to_string(worst));
}

INSTANTIATE_TEST_SUITE_P(NearAndFar, CameraDepth, ::testing::Values(0.0, 1.0e6));

TEST(CameraDepth, NothingBeyondTheFarPlaneHasDepth) {
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  const auto tile = makeTile(O, {square({60.0, 0.0, 2.0}, -Eigen::Vector3d::UnitX(), 100.0)});
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  o.far_m = 50.0;
  const camera::CameraImages img = camera::Renderer(o).render({{tile}}, lookingAlongX(O), {});
  for (const float d : img.depth)
    ASSERT_EQ(d, 0.0f);
  for (const std::uint8_t c : img.semantic)
    ASSERT_EQ(c, scene::cls::kSky);
}

// A wall standing at the far plane, turned so its depth runs from 1 mm short of it to 1 mm past
// it across the picture: the depth image and the ids agree, pixel by pixel, on what is drawn (a
// pixel without depth is sky with no instance, one with depth is not sky), though a fragment
// within a rounding of the far plane leaves the depth buffer at its clear value.
TEST(CameraDepth, ThePicturesAgreePixelByPixelOnWhatIsDrawnAtTheFarPlane) {
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  int disagree = 0, drawn = 0, nothing = 0;
  for (const double far_m : {60.0, 63.7, 88.9}) {
    o.far_m = far_m;
    // Half the picture's width at the wall is far · cx / fx; the wall's depth moves 1 mm there.
    const double half_width = far_m * o.intrinsics.cx / o.intrinsics.fx;
    const Eigen::Vector3d n = Eigen::Vector3d(-1.0, -1e-3 / half_width, 0.0).normalized();
    const auto tile = makeTile(O, {square({far_m, 0.0, 2.0}, n, 200.0)});
    const camera::CameraImages img =
        camera::Renderer(o).render({{tile}}, lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.0)), {});
    for (std::size_t i = 0; i < img.depth.size(); ++i) {
      const bool sky = img.semantic[i] == scene::cls::kSky;
      disagree += (img.depth[i] == 0.0f) != sky || (sky && img.object[i] != 0);
      drawn += !sky;
      nothing += sky;
    }
  }
  EXPECT_GT(drawn, 10000);    // the wall's near side is drawn in every picture
  EXPECT_GT(nothing, 10000);  // and its far side is not
  EXPECT_EQ(disagree, 0);
}

// Signals (a pole with a head: two classes in one shared mesh) at known places, a ground plane
// and a wire.
struct SignalScene {
  std::shared_ptr<const scene::Tile> tile;
  std::vector<Eigen::Vector3d> heads, posts;  // world centres
  std::vector<scene::InstanceId> instances;
};

SignalScene signals(const Eigen::Vector3d& O) {
  auto mesh = std::make_shared<scene::Mesh>();
  mesh->beginPart(scene::cls::kPole, scene::mat::kGalvanisedSteel);
  scene::addBox(*mesh, {-0.15f, -0.15f, 0.0f}, {0.15f, 0.15f, 3.0f});
  mesh->beginPart(scene::cls::kSignal, scene::mat::kPaintedMetal);
  scene::addBox(*mesh, {-0.4f, -0.4f, 3.0f}, {0.4f, 0.4f, 4.2f});
  SignalScene s;
  std::vector<scene::Object> objects;
  const double ahead[] = {12.0, 18.0, 25.0, 40.0};
  const double side[] = {-3.0, 3.5, -1.5, 5.0};
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d foot = O + Eigen::Vector3d(ahead[i], side[i], 0.0);
    const scene::InstanceId id = scene::objectInstance(3, -2, static_cast<std::uint32_t>(i));
    objects.push_back(scene::Object::place(mesh, foot, Eigen::Matrix3f::Identity(), id));
    s.heads.push_back(foot + Eigen::Vector3d(0.0, 0.0, 3.6));
    s.posts.push_back(foot + Eigen::Vector3d(0.0, 0.0, 1.5));
    s.instances.push_back(id);
  }
  scene::Wire wire;
  wire.points = {Eigen::Vector3f(5.0f, 0.5f, 5.5f), Eigen::Vector3f(60.0f, 0.5f, 5.5f)};
  wire.instance = 99;
  s.tile = makeTile(O,
                    {square({30.0, 0.0, 0.0}, Eigen::Vector3d::UnitZ(), 80.0, scene::cls::kTerrain,
                            scene::mat::kGrass)},
                    {wire}, std::move(objects));
  return s;
}

TEST(CameraIds, PixelsCarryTheClassAndInstanceOfTheObjectDrawnAndNothingElse) {
  const Eigen::Vector3d O(1.0e6, -2.0e5, 40.0);
  const SignalScene s = signals(O);
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer renderer(o);
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.5));
  const camera::CameraImages img = renderer.render({{s.tile}}, T, {});
  ASSERT_EQ(img.semantic.size(), img.object.size());
  const auto at = [&](const Eigen::Vector3d& world) {
    const Eigen::Vector2d uv = o.intrinsics.project(T.inverse() * world);
    const auto i = static_cast<std::size_t>(std::lround(uv.y())) * o.intrinsics.width +
                   static_cast<std::size_t>(std::lround(uv.x()));
    return std::pair{img.semantic[i], img.instances.at(img.object[i])};
  };
  for (std::size_t i = 0; i < s.heads.size(); ++i) {
    EXPECT_EQ(at(s.heads[i]), std::pair(std::uint8_t{scene::cls::kSignal}, s.instances[i])) << i;
    EXPECT_EQ(at(s.posts[i]), std::pair(std::uint8_t{scene::cls::kPole}, s.instances[i])) << i;
  }
  EXPECT_EQ(at(O + Eigen::Vector3d(10.0, -1.0, 0.0)),
            std::pair(std::uint8_t{scene::cls::kTerrain}, scene::InstanceId{1}));
  // Every pixel's (class, instance) is one the scene has: nothing blended across edges.
  std::set<std::pair<int, scene::InstanceId>> allowed = {
      {scene::cls::kSky, 0}, {scene::cls::kTerrain, 1}, {scene::cls::kWire, 99}};
  for (const scene::InstanceId id : s.instances) {
    allowed.insert({scene::cls::kPole, id});
    allowed.insert({scene::cls::kSignal, id});
  }
  std::map<std::pair<int, scene::InstanceId>, int> seen;
  for (std::size_t i = 0; i < img.semantic.size(); ++i) {
    ASSERT_LT(img.object[i], img.instances.size());
    ++seen[{img.semantic[i], img.instances[img.object[i]]}];
  }
  for (const auto& [pair, count] : seen)
    EXPECT_TRUE(allowed.count(pair))
        << "class " << pair.first << " instance " << pair.second << " on " << count << " pixels";
  EXPECT_EQ(seen.size(), allowed.size());  // all of them drawn, the wire included
}

TEST(CameraProjection, KnownPointsLandOnTheRenderedEdges) {
  const Eigen::Vector3d O(-3.0e5, 7.0e5, 10.0);
  const camera::Intrinsics k = smallCamera();
  const Eigen::Isometry3d T = lookingAlongX(O);
  // A square facing the camera 15 m ahead, off the axis.
  const Eigen::Vector3d centre(15.0, -1.3, 0.8);
  const auto tile = makeTile(O, {square(centre, -Eigen::Vector3d::UnitX(), 1.1)});
  camera::RendererOptions o;
  o.intrinsics = k;
  const camera::CameraImages img = camera::Renderer(o).render({{tile}}, T, {});
  // The square's pixels: its rows and columns.
  int u0 = k.width, u1 = -1, v0 = k.height, v1 = -1;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u)
      if (img.semantic[v * k.width + u] == scene::cls::kBuilding) {
        u0 = std::min(u0, u);
        u1 = std::max(u1, u);
        v0 = std::min(v0, v);
        v1 = std::max(v1, v);
      }
  // Its corners through the pinhole. A pixel is drawn when its centre is inside, so the first
  // column is the first pixel centre at or right of the left edge.
  const Eigen::Isometry3d T_cam_world = T.inverse();
  const Eigen::Vector2d a = k.project(T_cam_world * (O + centre + Eigen::Vector3d(0, 1.1, 1.1)));
  const Eigen::Vector2d b = k.project(T_cam_world * (O + centre - Eigen::Vector3d(0, 1.1, 1.1)));
  EXPECT_EQ(u0, static_cast<int>(std::ceil(a.x())));
  EXPECT_EQ(u1, static_cast<int>(std::ceil(b.x())) - 1);
  EXPECT_EQ(v0, static_cast<int>(std::ceil(a.y())));
  EXPECT_EQ(v1, static_cast<int>(std::ceil(b.y())) - 1);
  // So every edge lies within half a pixel of the drawn pixels' border.
  EXPECT_LE(std::abs((u0 - 0.5) - a.x()), 1.0);
  RecordProperty("edges_px",
                 fmt::format("{:.3f} {:.3f} {:.3f} {:.3f}", a.x(), b.x(), a.y(), b.y()));
}

// Small squares facing the camera all over a distorted camera's view (a KITTI-like barrel lens
// with tangential terms). The Brown–Conrady model, inverted here by fixed-point iteration,
// says which square each pixel's ray meets: every pixel of the remapped image agrees, except
// where a square's edge passes within half a pixel of the pixel's centre.
TEST(CameraLens, PixelsShowWhatTheDistortionModelSaysTheirRaysMeet) {
  const Eigen::Vector3d O(2.0e5, -4.0e5, 30.0);
  const camera::Intrinsics k = smallCamera();
  const camera::Distortion d{-0.28, 0.07, 0.0012, -0.0009, 0.0};
  const camera::LensRemap lens(k, d);
  EXPECT_GT(lens.render().width, k.width);  // barrel: the corners see beyond the pinhole's view
  const double ahead = 12.0, half = 0.3;
  std::vector<scene::Mesh> squares;
  std::vector<Eigen::Vector2d> centres;  // camera (x, y) at `ahead`
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) {
      const double x = ((i + 0.5) / 5.0 * k.width - k.cx) / k.fx * 1.1 * ahead;
      const double y = ((j + 0.5) / 4.0 * k.height - k.cy) / k.fy * 1.1 * ahead;
      centres.emplace_back(x, y);
      // Camera x = world −y, camera y = world −z (lookingAlongX).
      squares.push_back(square({ahead, -x, -y}, -Eigen::Vector3d::UnitX(), half));
    }
  const auto tile = makeTile(O, std::move(squares));
  camera::RendererOptions o;
  o.intrinsics = lens.render();
  const camera::CameraImages img =
      lens.apply(camera::Renderer(o).render({{tile}}, lookingAlongX(O), {}));
  ASSERT_EQ(img.width, k.width);
  ASSERT_EQ(img.object.size(), static_cast<std::size_t>(k.width * k.height));
  // The instance (1, 2, … as the squares; 0: none) the ray through pixel point (u, v) meets.
  const auto model = [&](double u, double v) -> scene::InstanceId {
    const Eigen::Vector2d target((u - k.cx) / k.fx, (v - k.cy) / k.fy);
    Eigen::Vector2d xy = target;
    for (int it = 0; it < 500; ++it)
      xy += target - d.apply(xy);
    EXPECT_LT((d.apply(xy) - target).norm(), 1e-12);
    for (std::size_t n = 0; n < centres.size(); ++n)
      if ((ahead * xy - centres[n]).cwiseAbs().maxCoeff() <= half)
        return static_cast<scene::InstanceId>(n + 1);
    return 0;
  };
  int wrong = 0, at_edges = 0, drawn = 0;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const scene::InstanceId got = img.instances[img.object[v * k.width + u]];
      const scene::InstanceId want = model(u, v);
      drawn += want != 0;
      if (got == want)
        continue;
      bool near_edge = false;
      for (const auto& [du, dv] : {std::pair{-0.5, 0.0},
                                   {0.5, 0.0},
                                   {0.0, -0.5},
                                   {0.0, 0.5},
                                   {-0.35, -0.35},
                                   {0.35, -0.35},
                                   {-0.35, 0.35},
                                   {0.35, 0.35}})
        near_edge |= model(u + du, v + dv) != want;
      ++(near_edge ? at_edges : wrong);
      EXPECT_TRUE(near_edge) << "pixel " << u << ", " << v << ": " << got << " for " << want;
    }
  EXPECT_GT(drawn, 2500);  // about 15 x 15 px a square, some partly outside the image
  EXPECT_EQ(wrong, 0);
  RecordProperty("pixels_on_squares_off_by_under_half_px", fmt::format("{} {}", drawn, at_edges));
}

// Levels of detail move no pixel of a surface farther than their budget: a tree far enough for
// its lightest levels differs from full detail only on its outline, and keeps its classes.
TEST(CameraLevelsOfDetail, AFarTreeKeepsItsClassesAndChangesOnlyAtItsOutline) {
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  auto tree = std::make_shared<scene::Mesh>();
  tree->beginPart(scene::cls::kTrunk, scene::mat::kBark);
  scene::addCylinder(*tree, {0, 0, 0}, {0, 0, 2.5f}, 0.2f, 0.15f, 16);
  tree->beginPart(scene::cls::kTree, scene::mat::kLeaves);
  scene::addBlob(*tree, {0, 0, 3.5f}, {1.6f, 1.6f, 1.8f}, 3, {});
  std::vector<scene::Object> objects;
  for (int i = 0; i < 6; ++i)
    objects.push_back(scene::Object::place(tree,
                                           O + Eigen::Vector3d(60.0 + 40.0 * i, 8.0 - 4.0 * i, 0),
                                           Eigen::Matrix3f::Identity(), 10 + i));
  const auto tile = makeTile(O, {}, {}, std::move(objects));
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  o.lod_pixels = 0.0;
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.5));
  const camera::CameraImages full = camera::Renderer(o).render({{tile}}, T, {});
  o.lod_pixels = 1.0;
  const camera::CameraImages light = camera::Renderer(o).render({{tile}}, T, {});
  EXPECT_LT(light.triangles, full.triangles * 3 / 4);
  int changed = 0, drawn = 0;
  for (std::size_t i = 0; i < full.semantic.size(); ++i) {
    drawn += full.semantic[i] != scene::cls::kSky;
    if (full.semantic[i] == light.semantic[i])
      continue;
    ++changed;
    // A changed pixel lies on an outline: a neighbour of it differs in the full render.
    const int u = static_cast<int>(i % full.width), v = static_cast<int>(i / full.width);
    bool edge = false;
    for (int dv = -1; dv <= 1; ++dv)
      for (int du = -1; du <= 1; ++du) {
        const int uu = std::clamp(u + du, 0, full.width - 1),
                  vv = std::clamp(v + dv, 0, full.height - 1);
        edge |= full.semantic[vv * full.width + uu] != full.semantic[i];
      }
    EXPECT_TRUE(edge) << "pixel " << u << ", " << v << " changed class inside a surface";
  }
  EXPECT_GT(drawn, 300);
  EXPECT_LT(changed, drawn / 10);
  RecordProperty("triangles_full_lod", fmt::format("{} {}", full.triangles, light.triangles));
  RecordProperty("pixels_drawn_changed", fmt::format("{} {}", drawn, changed));
}

TEST(CameraRender, ImagesDoNotDependOnWhatWasDrawnBefore) {
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  const SignalScene s = signals(O);
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer renderer(o);
  const Eigen::Isometry3d A = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.5));
  Eigen::Isometry3d B = A;
  B.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * A.linear();
  const camera::CameraImages first = renderer.render({{s.tile}}, A, {});
  const camera::CameraImages other = renderer.render({{s.tile}}, B, {});
  const camera::CameraImages again = renderer.render({{s.tile}}, A, {});
  EXPECT_NE(first.rgb, other.rgb);
  EXPECT_EQ(first.rgb, again.rgb);
  EXPECT_EQ(first.depth, again.depth);
  EXPECT_EQ(first.semantic, again.semantic);
  // Object values may differ; the instances they stand for may not.
  for (std::size_t i = 0; i < first.object.size(); ++i)
    ASSERT_EQ(first.instances[first.object[i]], again.instances[again.object[i]]);
  // A fresh renderer draws the same.
  const camera::CameraImages fresh = camera::Renderer(o).render({{s.tile}}, A, {});
  EXPECT_EQ(first.rgb, fresh.rgb);
  EXPECT_EQ(first.depth, fresh.depth);
}

TEST(CameraRender, TooManyThingsOnlyInOnePictureAreTooMany) {
  // A picture may hold 65535 things. Two pictures of 35 000 each, one after the other, hold
  // 70 000 between them: the second must not fail for the first's (which a renderer keeps for
  // the renders to come), whatever came before it.
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  auto box = std::make_shared<scene::Mesh>();
  box->prototype = true;
  box->beginPart(scene::cls::kRock, scene::mat::kRock);
  scene::addBox(*box, {-0.05f, -0.05f, 0.0f}, {0.05f, 0.05f, 0.1f});
  const auto field = [&](int which) {
    std::vector<scene::Object> objects;
    for (int i = 0; i < 35000; ++i) {
      // 100 rows 20-70 m ahead, 350 a row across the middle 80 % of the view (they overlap).
      const double x = 20.0 + 0.5 * (i / 350);
      const double y = (i % 350 / 350.0 - 0.5) * 0.8 * x * 150.0 / 300.0;
      const Eigen::Vector3d foot = O + Eigen::Vector3d(x, y, 0.0);
      objects.push_back(
          scene::Object::place(box, foot, Eigen::Matrix3f::Identity(),
                               scene::objectInstance(which, 0, static_cast<std::uint32_t>(i))));
    }
    auto tile = std::const_pointer_cast<scene::Tile>(makeTile(O, {}, {}, std::move(objects)));
    tile->index = {which, 0};  // another tile's things, not a copy of the same tile's
    return std::shared_ptr<const scene::Tile>(tile);
  };
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer renderer(o);
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.5));
  const auto a = field(1), b = field(2);
  const camera::CameraImages first = renderer.render({{a}}, T, {});
  const camera::CameraImages second = renderer.render({{b}}, T, {});
  // Each picture's pixels show its own field's things, a great many of them.
  const auto shown = [](const camera::CameraImages& img, const scene::Tile& tile) {
    std::set<scene::InstanceId> ids, own;
    for (const scene::Object& object : tile.objects)
      own.insert(object.instance);
    for (const std::uint16_t v : img.object)
      if (v != 0) {
        EXPECT_TRUE(own.contains(img.instances.at(v)));
        ids.insert(img.instances.at(v));
      }
    return ids.size();
  };
  EXPECT_GT(shown(first, *a), 1000u);
  EXPECT_GT(shown(second, *b), 1000u);
  EXPECT_EQ(first.semantic, second.semantic);  // the same field, other ids
}

TEST(CameraRender, ALitSignalLampShowsItsEmissionColourWhateverTheLightAndKeepsItsLabels) {
  // A signal head 15 m ahead facing the camera: a red lamp lit over a dark yellow and green
  // lens (discs as boxes 0.3 m across, so their centres are well inside many pixels).
  const Eigen::Vector3d O(2.0e5, -4.0e5, 30.0);
  auto mesh = std::make_shared<scene::Mesh>();
  mesh->beginPart(scene::cls::kSignal, scene::mat::kPaintedMetal);
  scene::addBox(*mesh, {0.05f, -0.4f, -1.2f}, {0.5f, 0.4f, 1.2f});
  const std::pair<float, scene::MaterialId> lamps[] = {{0.75f, scene::mat::kSignalLampRed},
                                                       {0.0f, scene::mat::kSignalLensYellow},
                                                       {-0.75f, scene::mat::kSignalLensGreen}};
  for (const auto& [z, material] : lamps) {
    mesh->beginPart(scene::cls::kSignal, material);
    scene::addBox(*mesh, {0.0f, -0.15f, z - 0.15f}, {0.05f, 0.15f, z + 0.15f});
  }
  const Eigen::Vector3d head = O + Eigen::Vector3d(15.0, 0.0, 2.0);
  const scene::InstanceId id = scene::objectInstance(1, 1, 7);
  const auto tile =
      makeTile(O, {}, {}, {scene::Object::place(mesh, head, Eigen::Matrix3f::Identity(), id)});
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer renderer(o);
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.0));
  camera::Lighting noon, night;
  night.sun_intensity = 0.0;
  night.ambient = 0.02;
  night.sky_zenith = night.sky_horizon = {4, 6, 12};
  const camera::CameraImages day = renderer.render({{tile}}, T, noon);
  const camera::CameraImages dark = renderer.render({{tile}}, T, night);
  const auto pixel = [&](const Eigen::Vector3d& world) {
    const Eigen::Vector2d uv = o.intrinsics.project(T.inverse() * world);
    return static_cast<std::size_t>(std::lround(uv.y())) * o.intrinsics.width +
           static_cast<std::size_t>(std::lround(uv.x()));
  };
  const auto rgb = [](const camera::CameraImages& img, std::size_t i) {
    return scene::Rgb{img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]};
  };
  const std::size_t red = pixel(head + Eigen::Vector3d(0.0, 0.0, 0.75)), yellow = pixel(head),
                    green = pixel(head + Eigen::Vector3d(0.0, 0.0, -0.75)),
                    body = pixel(head + Eigen::Vector3d(0.0, 0.3, 0.4));
  const scene::Rgb glow = scene::material(scene::mat::kSignalLampRed).emission;
  // The lit lamp is its emission colour by day and by night, exactly (drawn unlit, no FXAA).
  EXPECT_EQ(rgb(day, red), glow);
  EXPECT_EQ(rgb(dark, red), glow);
  // The dark lenses and the head are lit by the scene: darker still at night, and far below the
  // lamp.
  for (const std::size_t i : {yellow, green, body}) {
    const scene::Rgb d = rgb(dark, i), n = rgb(day, i);
    EXPECT_LT(std::max({d[0], d[1], d[2]}), 12) << i;
    EXPECT_LT(n[0] + n[1] + n[2], 255) << i;
    EXPECT_GT(n[0] + n[1] + n[2], d[0] + d[1] + d[2]) << i;
  }
  // The lamp keeps its labels and its depth: class signal, the signal's instance, 15 m away.
  for (const camera::CameraImages* img : {&day, &dark}) {
    EXPECT_EQ(img->semantic[red], scene::cls::kSignal);
    EXPECT_EQ(img->instances.at(img->object[red]), id);
    EXPECT_NEAR(img->depth[red], 15.0, 1.0 / 256.0);
  }
}

TEST(CameraRender, AWireIsShadedByTheLightOfTheSceneNotDrawnAtItsFullColour) {
  // The signal scene's wire (copper) runs 5.5 m up across the view: by day it is shaded by the
  // sky's light and half the sun's, at night (no sun, no lamps) it is nearly black.
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  const SignalScene s = signals(O);
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer renderer(o);
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.5));
  camera::Lighting noon, night;
  night.sun_intensity = 0.0;
  night.ambient = 0.02;
  const camera::CameraImages day = renderer.render({{s.tile}}, T, noon);
  const camera::CameraImages dark = renderer.render({{s.tile}}, T, night);
  const scene::Rgb copper = scene::material(scene::mat::kCopper).colour;
  const double shade = noon.ambient + 0.5 * (1.0 - noon.ambient) * noon.sun_intensity;
  int wire = 0;
  for (std::size_t i = 0; i < day.semantic.size(); ++i) {
    if (day.semantic[i] != scene::cls::kWire)
      continue;
    ++wire;
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(day.rgb[3 * i + ch], shade * copper[ch], 1.0) << i;
      EXPECT_LE(dark.rgb[3 * i + ch], std::lround(0.02 * copper[ch]) + 1) << i;
    }
  }
  EXPECT_GT(wire, 20);
}

TEST(CameraRender, EachSurfaceIsLitByTheDaylightThatReachesItAndTheShadeByTheRest) {
  // Ground 200 m square, the camera 2 m over it looking along +x. Daylight reaches the ground
  // fully nearer than x = 20 m, none of it past 40 m, linearly in between (a tunnel's bore, as
  // the camera sensor's function has it). Each pixel is then the render by day where its
  // surface is in daylight, the shade's render where none reaches it, their blend between, and
  // the sky the day's sky. The renderer draws it in one colour pass, each surface lit by both
  // lightings in proportion; the test blends two renders, one under each lighting alone.
  const Eigen::Vector3d O(1.0e6, 0.0, 250.0);  // far from the scenario origin
  // And a wall in daylight (x = 10 m, left of the axis) and one in the shade (x = 60 m, right),
  // and a wire 4 m up from the day into the shade.
  scene::Wire wire;
  wire.points = {Eigen::Vector3f(5.0f, 1.0f, 4.0f), Eigen::Vector3f(70.0f, 1.0f, 4.0f)};
  wire.instance = 7;
  const auto tile =
      makeTile(O,
               {square(Eigen::Vector3d(100.0, 0.0, 0.0), Eigen::Vector3d::UnitZ(), 200.0),
                square(Eigen::Vector3d(10.0, 3.0, 1.0), -Eigen::Vector3d::UnitX(), 1.0),
                square(Eigen::Vector3d(60.0, -8.0, 3.0), -Eigen::Vector3d::UnitX(), 3.0)},
               {wire});
  const auto share = [&](const Eigen::Vector3d& p) {
    return std::clamp((40.0 - (p.x() - O.x())) / 20.0, 0.0, 1.0);
  };
  camera::RendererOptions o;
  o.intrinsics = smallCamera();
  const camera::Renderer plain(o);
  o.daylight = [&](std::span<const Eigen::Vector3d> points, std::span<float> shares) {
    for (std::size_t i = 0; i < points.size(); ++i)
      shares[i] = static_cast<float>(share(points[i]));
  };
  const camera::Renderer shaded(o);
  // Told which things may be out of daylight (x > 20 m): the same images.
  o.shade_meets = [&](const scene::Box3d& box) { return box.max.x() > O.x() + 20.0; };
  const camera::Renderer partly(o);
  const Eigen::Isometry3d T = lookingAlongX(O + Eigen::Vector3d(0.0, 0.0, 2.0));
  camera::Lighting day, shade;
  shade.sun_intensity = 0.0;
  shade.ambient = 0.05;
  camera::Spot lamp;
  lamp.direction = Eigen::Vector3d(0.0, 0.1, 1.0).normalized();
  shade.spots.push_back(lamp);
  const camera::CameraImages a = plain.render({{tile}}, T, day);
  const camera::CameraImages b = plain.render({{tile}}, T, shade);
  const camera::CameraImages mixed = shaded.render({{tile}}, T, day, &shade);
  EXPECT_EQ(partly.render({{tile}}, T, day, &shade).rgb, mixed.rgb);
  // Without a shade, the daylight function changes nothing.
  EXPECT_EQ(shaded.render({{tile}}, T, day).rgb, a.rgb);
  ASSERT_EQ(mixed.rgb.size(), a.rgb.size());
  EXPECT_EQ(mixed.depth, a.depth);
  const camera::Intrinsics& k = o.intrinsics;
  int sunny = 0, dark = 0, between = 0, sky = 0, wired = 0;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      const double z = a.depth[i];
      const double w =
          z > 0.0 ? share(T * Eigen::Vector3d((u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z))
                  : 1.0;
      (z == 0.0 ? sky : w == 1.0 ? sunny : w == 0.0 ? dark : between) += 1;
      wired += a.semantic[i] == scene::cls::kWire && w > 0.0 && w < 1.0;
      // Both references and the one render are rounded to 8 bits.
      for (int c = 0; c < 3; ++c) {
        const double expected = b.rgb[3 * i + c] + w * (a.rgb[3 * i + c] - b.rgb[3 * i + c]);
        ASSERT_NEAR(mixed.rgb[3 * i + c], expected, 1.0 + 1e-4) << u << " " << v;
      }
    }
  EXPECT_GT(sunny, 1000);
  EXPECT_GT(dark, 1000);
  EXPECT_GT(between, 1000);
  EXPECT_GT(sky, 1000);
  EXPECT_GT(wired, 5);
  // The shade is darker than the day where the lamp does not reach.
  EXPECT_LT(b.rgb[3 * (k.width * (k.height - 1)) + 1], a.rgb[3 * (k.width * (k.height - 1)) + 1]);
}

}  // namespace
}  // namespace trainsim
