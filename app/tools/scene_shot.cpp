// trainsim-scene-shot: renders a stretch of the generated scene (terrain, track assets,
// objects) to a PNG with VTK, as the docs' pictures are made. Needs an X display (Xvfb).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <iostream>

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>

#include "scene_polydata.hpp"
#include "trainsim/core/error.hpp"
#include "trainsim/environment/environment.hpp"
#include "trainsim/io/file_io.hpp"
#include "trainsim/io/png.hpp"
#include "trainsim/sim/plan.hpp"
#include "trainsim/sim/schema.hpp"
#include "trainsim/terrain/railway.hpp"

namespace {

using namespace trainsim;

int run(int argc, char** argv) {
  CLI::App app{
      "Renders a stretch of TrainSim's generated scene to a PNG (needs X: run under Xvfb)"};
  std::string scenario_path, out = "scene.png";
  double chainage = 300.0, height = 6.0, back = 40.0, side = 8.0, ahead = 120.0, radius = 600.0;
  int width = 1600, pixels_high = 900;
  app.add_option("SCENARIO", scenario_path, "Scenario JSON (default: built-in)");
  app.add_option("--out,-o", out, "PNG file");
  app.add_option("--chainage", chainage, "Main chainage the camera looks at (m)");
  app.add_option("--height", height, "Camera height above the rails (m)");
  app.add_option("--back", back, "Camera distance behind the chainage (m)");
  app.add_option("--side", side, "Camera offset to the left (m)");
  app.add_option("--ahead", ahead, "Distance ahead the camera looks at (m)");
  app.add_option("--radius", radius, "Scene radius drawn (m)");
  app.add_option("--width", width, "Image width");
  app.add_option("--height-px", pixels_high, "Image height");
  CLI11_PARSE(app, argc, argv);

  const scenario::Scenario scenario = sim::loadScenario(scenario_path);
  const auto plan = sim::makePlan(scenario);
  const auto stage = sim::makeEnvironment(*plan, scenario);
  const auto& railway = *stage->railway;
  const track::TrackFrame at = railway.frame(0, chainage);
  const track::TrackFrame look =
      railway.frame(0, std::min(railway.main().length(), chainage + ahead));
  const Eigen::Vector3d origin = at.position;
  auto stream = stage->environment->stream(16);
  const scene::SceneWindow window = stream->window(origin, radius);

  const app::ScenePolyData scene = app::scenePolyData(window.tiles, origin);

  vtkNew<vtkRenderer> renderer;
  for (vtkPolyData* data : {scene.surfaces.GetPointer(), scene.wires.GetPointer()}) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(data);
    mapper->SetScalarModeToUseCellData();
    mapper->SetColorModeToDirectScalars();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetLineWidth(1.5f);
    actor->GetProperty()->SetAmbient(0.35);
    actor->GetProperty()->SetDiffuse(0.75);
    renderer->AddActor(actor);
  }
  renderer->SetBackground(0.62, 0.76, 0.92);
  renderer->AutomaticLightCreationOff();
  vtkNew<vtkLight> sun;
  sun->SetLightTypeToSceneLight();
  sun->SetPosition(-300.0, -200.0, 600.0);
  sun->SetFocalPoint(0, 0, 0);
  sun->SetIntensity(1.0);
  renderer->AddLight(sun);
  Eigen::Vector3d hl(at.left.x(), at.left.y(), 0.0);
  hl.normalize();
  const Eigen::Vector3d eye = -back * at.tangent + side * hl + Eigen::Vector3d(0, 0, height);
  const Eigen::Vector3d focus = look.position - origin;
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetPosition(eye.data());
  camera->SetFocalPoint(focus.data());
  camera->SetViewUp(0, 0, 1);
  camera->SetViewAngle(50.0);
  camera->SetClippingRange(0.5, 2.0 * radius);

  vtkNew<vtkRenderWindow> render_window;
  render_window->SetOffScreenRendering(1);
  render_window->SetMultiSamples(4);
  render_window->AddRenderer(renderer);
  render_window->SetSize(width, pixels_high);
  render_window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(render_window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  const auto* rgb = static_cast<const std::uint8_t*>(image->GetScalarPointer());
  // VTK's rows run bottom to top; PNG's top to bottom.
  std::vector<std::uint8_t> flipped(static_cast<std::size_t>(width) * pixels_high * 3);
  for (int r = 0; r < pixels_high; ++r)
    std::copy_n(rgb + static_cast<std::size_t>(r) * width * 3, static_cast<std::size_t>(width) * 3,
                flipped.data() + static_cast<std::size_t>(pixels_high - 1 - r) * width * 3);
  io::writeFileAtomic(out, io::encodePngRgb8(width, pixels_high, flipped));
  std::cout << fmt::format("wrote {} ({} tiles, {} triangles)\n", out, window.tiles.size(),
                           scene.triangles);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "trainsim-scene-shot: " << e.what() << "\n";
    return trainsim::exitCodeFor(e);
  }
}
