// Image regression: renders of a fixed analytic scene (ground, signals on poles, trees at
// several distances, a wire) under noon sun, at night with headlights and through a lens,
// compared with checked-in baselines by vtkImageDifference (thresholded error, a few grey levels
// of tolerance for Mesa versions). TRAINSIM_UPDATE_BASELINES=1 rewrites the baselines.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <vtkImageData.h>
#include <vtkImageDifference.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include "support/scene_shapes.hpp"
#include "support/x_environment.hpp"
#include "trainsim/camera/lens.hpp"
#include "trainsim/camera/renderer.hpp"

#ifndef TRAINSIM_BASELINE_DIR
#error "TRAINSIM_BASELINE_DIR must name tests/data/camera"
#endif

namespace trainsim {
namespace {

const auto* const kX = ::testing::AddGlobalTestEnvironment(new test::XEnvironment);

std::shared_ptr<const scene::Tile> scene(const Eigen::Vector3d& O) {
  auto signal = std::make_shared<scene::Mesh>();
  signal->beginPart(scene::cls::kPole, scene::mat::kGalvanisedSteel);
  scene::addBox(*signal, {-0.15f, -0.15f, 0.0f}, {0.15f, 0.15f, 3.0f});
  signal->beginPart(scene::cls::kSignal, scene::mat::kPaintedMetal);
  scene::addBox(*signal, {-0.4f, -0.4f, 3.0f}, {0.4f, 0.4f, 4.2f});
  auto tree = std::make_shared<scene::Mesh>();
  tree->beginPart(scene::cls::kTrunk, scene::mat::kBark);
  scene::addCylinder(*tree, {0, 0, 0}, {0, 0, 2.5f}, 0.2f, 0.15f, 12);
  tree->beginPart(scene::cls::kTree, scene::mat::kLeaves);
  scene::addBlob(*tree, {0, 0, 3.5f}, {1.6f, 1.6f, 1.8f}, 3, {});
  std::vector<scene::Object> objects;
  for (int i = 0; i < 4; ++i)
    objects.push_back(scene::Object::place(signal, O + Eigen::Vector3d(12.0 + 9.0 * i, -3.0, 0.0),
                                           Eigen::Matrix3f::Identity(), 20 + i));
  for (int i = 0; i < 6; ++i)
    objects.push_back(scene::Object::place(tree, O + Eigen::Vector3d(20.0 + 35.0 * i, 7.0, 0.0),
                                           Eigen::Matrix3f::Identity(), 30 + i));
  scene::Wire wire;
  wire.points = {Eigen::Vector3f(5.0f, 0.0f, 5.5f), Eigen::Vector3f(200.0f, 0.0f, 5.5f)};
  wire.instance = 99;
  return test::makeTile(O,
                        {test::square({100.0, 0.0, 0.0}, Eigen::Vector3d::UnitZ(), 150.0,
                                      scene::cls::kTerrain, scene::mat::kGrass)},
                        {wire}, std::move(objects));
}

Eigen::Isometry3d camera(const Eigen::Vector3d& O) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = -Eigen::Vector3d::UnitY();
  T.linear().col(1) = -Eigen::Vector3d::UnitZ();
  T.linear().col(2) = Eigen::Vector3d::UnitX();
  T.translation() = O + Eigen::Vector3d(0.0, 0.0, 2.8);
  return T;
}

// The RGB image as VTK image data (rows bottom-up, as VTK's readers give them).
vtkSmartPointer<vtkImageData> toImage(const camera::CameraImages& img) {
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->SetDimensions(img.width, img.height, 1);
  out->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* p = static_cast<unsigned char*>(out->GetScalarPointer());
  for (int v = 0; v < img.height; ++v)
    std::copy_n(img.rgb.data() + 3 * static_cast<std::size_t>(img.height - 1 - v) * img.width,
                3 * img.width, p + 3 * static_cast<std::size_t>(v) * img.width);
  return out;
}

// Compares `img` with the baseline `name`.png (or writes it when asked to).
void expectBaseline(const camera::CameraImages& img, const std::string& name) {
  const std::filesystem::path file = std::filesystem::path(TRAINSIM_BASELINE_DIR) / (name + ".png");
  const vtkSmartPointer<vtkImageData> image = toImage(img);
  if (std::getenv("TRAINSIM_UPDATE_BASELINES") != nullptr) {
    vtkNew<vtkPNGWriter> w;
    w->SetFileName(file.c_str());
    w->SetInputData(image);
    w->Write();
    GTEST_SKIP() << "wrote " << file;
  }
  ASSERT_TRUE(std::filesystem::exists(file)) << file << " missing (TRAINSIM_UPDATE_BASELINES=1)";
  vtkNew<vtkPNGReader> r;
  r->SetFileName(file.c_str());
  r->Update();
  vtkNew<vtkImageDifference> diff;
  diff->SetInputData(image);
  diff->SetImageConnection(r->GetOutputPort());
  diff->AllowShiftOff();   // a shifted image is a changed camera model, not a tolerance
  diff->SetThreshold(16);  // per-pixel colour distance below which a pixel counts as equal
  diff->Update();
  const double error = diff->GetThresholdedError();
  ::testing::Test::RecordProperty(name + "_thresholded_error", std::to_string(error));
  EXPECT_LT(error, 10.0) << name << ": thresholded error " << error << " against " << file;
}

camera::RendererOptions options(const camera::Intrinsics& k) {
  camera::RendererOptions o;
  o.intrinsics = k;
  o.far_m = 300.0;
  return o;
}

const camera::Intrinsics kCamera = camera::Intrinsics::fromHorizontalFov(400, 200, 1.4);

TEST(CameraBaseline, NoonSun) {
  const Eigen::Vector3d O(3.0e5, 2.0e5, 12.0);
  const camera::CameraImages img =
      camera::Renderer(options(kCamera)).render({{scene(O)}}, camera(O), camera::Lighting());
  expectBaseline(img, "noon");
}

TEST(CameraBaseline, NightWithHeadlights) {
  const Eigen::Vector3d O(0.0, 0.0, 0.0);
  camera::Lighting night;
  night.sun_intensity = 0.0;
  night.ambient = 0.06;
  night.sky_zenith = {6, 9, 22};
  night.sky_horizon = {18, 22, 38};
  for (const double x : {-0.6, 0.6}) {  // camera frame: x right, y down, z forward
    camera::Spot s;
    s.position = {x, 1.8, 0.5};
    s.intensity = 1.4;
    s.half_distance_m = 35.0;
    night.spots.push_back(s);
  }
  const camera::CameraImages img =
      camera::Renderer(options(kCamera)).render({{scene(O)}}, camera(O), night);
  expectBaseline(img, "night");
}

TEST(CameraBaseline, ThroughABarrelLens) {
  const Eigen::Vector3d O(-1.0e6, 0.0, 0.0);
  const camera::LensRemap lens(kCamera, {-0.3, 0.09, 0.0, 0.0, 0.0});
  const camera::CameraImages img = lens.apply(
      camera::Renderer(options(lens.render())).render({{scene(O)}}, camera(O), camera::Lighting()));
  expectBaseline(img, "lens");
}

}  // namespace
}  // namespace trainsim
